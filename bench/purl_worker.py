"""One Purl method on one scene, in a process of its own (so peak memory is per method).

Builds the scene once (purlcore.RenderJob), then renders it at every sample count of the
series, `--repeats` times each with different seeds, and finally the converged image as two
halves with their own seeds (the analysis uses their difference to remove the reference's own
noise from the error; bench/metrics.py). Writes <out>.npz (images) and <out>.json (figures).

Run by bench/run.py; by hand:
  PYTHONPATH=build python3 bench/purl_worker.py scene.json --method bysdf-auto \
      --series 1,4,16 --reference-spp 256 --out /tmp/x
"""
import argparse
import json
import os
import resource
import sys
import time

import numpy as np

# Method name -> (yarn model, multi-scale mode or None, integrator).
METHODS = {
    "bysdf": ("bysdf", None, "path"),  # the scene's own multi-scale settings
    "bysdf-near": ("bysdf", "near", "path"),
    "bysdf-multi": ("bysdf", "multi", "path"),
    "bysdf-far": ("bysdf", "far", "path"),
    "bysdf-auto": ("bysdf", "auto", "path"),
    "ply": ("ply", None, "path"),
    "fiber": ("fiber", None, "path"),
    "trace": ("bysdf", None, "trace"),
    "trace-ply": ("ply", None, "trace"),
    "trace-fiber": ("fiber", None, "trace"),
}


def scene_for(path, method):
    with open(path, encoding="utf-8") as f:
        scene = json.load(f)
    model, mode, integrator = METHODS[method]
    render = scene.setdefault("render", {})
    if mode is not None:
        render.setdefault("multiscale", {})["mode"] = mode
    if integrator != "path":
        render["integrator"] = integrator
    return scene, model


def render_once(job, spp, seed, threads):
    job.start(spp=spp, seed=seed, threads=threads)
    job.wait()
    if job.error:
        raise RuntimeError(job.error)
    image = np.ascontiguousarray(job.passes()["Combined"][..., :3], dtype=np.float32)
    return image, job.stats()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("--method", required=True, choices=sorted(METHODS))
    parser.add_argument("--series", required=True, help="comma-separated sample counts")
    parser.add_argument("--reference-spp", type=int, default=0, help="0: no converged image")
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--out", required=True, help="output path without extension")
    args = parser.parse_args()

    import purlcore  # noqa: E402  (PYTHONPATH is set by the caller)

    scene, model = scene_for(args.scene, args.method)
    start = time.perf_counter()
    job = purlcore.RenderJob(json.dumps(scene), None, os.path.dirname(os.path.abspath(args.scene)), model)
    setup_seconds = time.perf_counter() - start  # explicit geometry + Embree + maps

    series, images, stats_first = [], {}, None
    for spp in [int(s) for s in args.series.split(",")]:
        runs = []
        for r in range(args.repeats):
            image, stats = render_once(job, spp, 101 + 17 * r, args.threads)
            if r == 0:
                images["spp%d" % spp] = image
            runs.append(stats)
        stats_first = stats_first or runs[0]
        series.append({"spp": spp, "runs": runs})
    reference = None
    if args.reference_spp > 0:
        half = max(1, args.reference_spp // 2)
        a, sa = render_once(job, half, 9001, args.threads)
        b, sb = render_once(job, half, 9002, args.threads)
        images["reference_a"], images["reference_b"] = a, b
        reference = {"spp": 2 * half, "runs": [sa, sb]}
    np.savez_compressed(args.out + ".npz", **images)
    summary = {
        "method": args.method,
        "model": model,
        "setup_seconds": setup_seconds,
        "series": series,
        "reference": reference,
        "peak_resident_bytes": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
        "acceleration_bytes": stats_first["acceleration_bytes"],
        "shading_bytes": stats_first["shading_bytes"],
        "control_points": stats_first["control_points"],
        "curves": stats_first["curves"],
        "build_seconds": stats_first["build_seconds"],
    }
    with open(args.out + ".json", "w", encoding="utf-8") as f:
        json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
