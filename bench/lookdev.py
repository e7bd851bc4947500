"""The look-dev loop's native costs, wall and CPU time side by side (docs/blender-addon.md).

    PYTHONPATH=build python3 bench/lookdev.py [--bcc ../shared/data/glove.bcc] [--size 512] [--repeats 5]

For a BCC file (default the shared glove) at a viewport size: reading it with the radius estimate
(the importer's native part), building the RenderJob (what every scene edit costs the viewport),
the viewport's first coarse pass (COARSE_PIXELS, 1 sample), a full-size 1-sample pass, a view
change (set_view) and the F12 pass overhead (progressive passes against one render of the same
samples). Prints medians over --repeats and the machine's load. CPU seconds are the process's
user + system time: on an idle 2-core machine a step takes about max(CPU / 2, its serial part).
"""
import argparse
import json
import os
import resource
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
COARSE_PIXELS = 128 * 128  # as addon/viewport.py


def cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def measure(label, function, repeats, rows):
    walls, cpus = [], []
    for _ in range(repeats):
        cpu, wall = cpu_seconds(), time.perf_counter()
        function()
        walls.append(time.perf_counter() - wall)
        cpus.append(cpu_seconds() - cpu)
    rows.append((label, float(np.median(walls)), float(np.median(cpus))))
    print("{:<58} wall {:7.3f} s   CPU {:7.3f} s".format(label, rows[-1][1], rows[-1][2]), flush=True)


def scene_for(data, radius, size):
    points = data["points"]
    centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
    extent = float(np.ptp(points, axis=0).max())
    camera = {"position": (centre + np.array([0.0, -2.0 * extent, 0.3 * extent])).tolist(),
              "look_at": centre.tolist(), "lens": 50, "clip_start": 0.01 * extent, "clip_end": 100 * extent}
    scene = {"version": 1, "camera": camera, "film": {"width": size, "height": size},
             "render": {"spp": 1, "seed": 1}, "world": {"color": [0.05, 0.05, 0.06]},
             "lights": [{"type": "sun", "strength": 3.0, "position": camera["position"], "look_at": camera["look_at"]}],
             "yarns": [{"name": "yarns", "arrays": "yarns", "material": {"model": "bysdf"}}]}
    basis = {"C0": "catmull_rom", "BS": "bspline", "PL": "polyline", "BZ": "bezier"}[data["type"]]
    arrays = {"yarns": {"points": points, "radii": np.full(len(points), radius, dtype=np.float32),
                        "offsets": data["offsets"].astype(np.int64), "closed": data["closed"], "basis": basis}}
    return scene, arrays


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--bcc", default=os.path.join(REPO, "..", "shared", "data", "glove.bcc"))
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--json", help="also write the rows here")
    args = parser.parse_args()
    import purlcore

    print("load average {:.1f} {:.1f} {:.1f}, {} CPUs, {}".format(*os.getloadavg(), os.cpu_count(),
                                                              os.path.basename(args.bcc)), flush=True)
    rows = []
    measure("read_bcc + radius estimate", lambda: purlcore.read_bcc(args.bcc), args.repeats, rows)
    data = purlcore.read_bcc(args.bcc)
    print("  {} curves, {} points, type {}, radius estimate {:.4g}".format(
        len(data["closed"]), len(data["points"]), data["type"], data["radius_estimate"]))
    scene, arrays = scene_for(data, data["radius_estimate"], args.size)
    jobs = []
    measure("RenderJob build (viewport mode near)", lambda: jobs.append(purlcore.RenderJob(scene, arrays, mode="near")),
            args.repeats, rows)
    job = jobs[-1]
    del jobs[:-1]
    scale = 1
    while (args.size // scale) ** 2 > COARSE_PIXELS:
        scale *= 2
    coarse = {"camera": scene["camera"], "film": {"width": args.size // scale, "height": args.size // scale}}
    full = {"camera": scene["camera"], "film": scene["film"]}

    def render(view, spp=1, first=0):
        job.set_view(view)
        job.start(spp=spp, first_sample=first)
        job.wait()

    measure("coarse pass {0}x{0}, 1 spp".format(args.size // scale), lambda: render(coarse), args.repeats, rows)
    measure("full pass {0}x{0}, 1 spp".format(args.size), lambda: render(full), args.repeats, rows)
    moved = dict(full, camera=dict(scene["camera"], position=[v * 1.01 for v in scene["camera"]["position"]]))
    measure("set_view (a camera move, no rebuild)", lambda: job.set_view(moved), args.repeats, rows)
    # F12 overhead: 8 samples as passes 1, 1, 2, 4 against one render of 8.
    measure("F12 8 spp in one render", lambda: render(full, 8), max(1, args.repeats // 2), rows)

    def passes():
        for first, count in ((0, 1), (1, 1), (2, 2), (4, 4)):
            render(full, count, first)
            job.passes()
    measure("F12 8 spp as passes 1, 1, 2, 4 (+ copies)", passes, max(1, args.repeats // 2), rows)
    first_image = rows[1][1] + rows[2][1]
    print("first viewport image (build + coarse pass): wall {:.3f} s, CPU {:.3f} s".format(
        first_image, rows[1][2] + rows[2][2]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"load": os.getloadavg(), "rows": rows}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
