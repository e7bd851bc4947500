#!/usr/bin/env python3
"""Scale test: a scene of at least 10^6 B-spline control points, rendered small.

Scenes (written to --out):
  glove  the shared glove.bcc tiled TX x TY times, one yarn set per tile placed by matrix_world
         (each tile: 58,537 Catmull-Rom points -> 234,148 B-spline control points)
  weave  a generated plain-weave sheet, N warps x N wefts (about 4 N^2 control points)
For each scene it runs `purl render --stats` under /usr/bin/time -v and reports load, build and
render time, samples per second, peak memory, memory per control point (peak minus a tiny
baseline scene) and the renderer's own acceleration-structure and shading figures; then it
asks for the same scene with --model ply and --model fiber and reports what happens.
Usage: python3 bench/scale/run_scale.py [--purl build/purl] [--glove-tiles 5x5] [--weave 500]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GLOVE_CENTRE = (0.0, 0.0, 0.0)


def camera_for(width, depth):
    """A camera looking down at the XY plane, seeing a square `width` across."""
    height = 1.1 * width * 50.0 / 36.0  # lens 50 mm on a 36 mm sensor
    return {"position": [0.0, -0.3 * height, height], "look_at": [0.0, 0.0, depth]}


def glove_scene(tiles_x, tiles_y, bcc):
    # glove.bcc is about 28 x 35 x 26 units (Y-up file, Z-up after loading); 0.12 is a yarn
    # radius at which neighbouring yarns about touch. Tiles sit 40 x 45 units apart.
    yarns = []
    for ty in range(tiles_y):
        for tx in range(tiles_x):
            dx, dy = 40.0 * (tx - 0.5 * (tiles_x - 1)), 45.0 * (ty - 0.5 * (tiles_y - 1))
            yarns.append({"name": "glove %d,%d" % (tx, ty), "bcc": bcc, "radius": 0.12,
                          "matrix_world": [1, 0, 0, dx, 0, 1, 0, dy, 0, 0, 1, 0, 0, 0, 0, 1]})
    width = max(40.0 * tiles_x, 45.0 * tiles_y)
    return {"camera": camera_for(width, 0.0), "yarns": yarns}


def weave_scene(n):
    radius = 0.0005
    width = n * 5 * radius
    return {"camera": camera_for(width, 0.0),
            "yarns": [{"name": "sheet", "generate": {"kind": "plain", "radius": radius, "warps": n, "wefts": n}}]}


def baseline_scene():
    return {"camera": camera_for(0.01, 0.0),
            "yarns": [{"generate": {"kind": "plain", "warps": 2, "wefts": 2}}]}


def finish(scene, size, spp):
    scene["film"] = {"width": size, "height": size}
    scene["render"] = {"spp": spp, "seed": 1}
    scene["world"] = {"color": [0.8, 0.85, 0.9], "strength": 1.0}
    scene["lights"] = [{"type": "sun", "position": [1, -1, 2], "look_at": [0, 0, 0], "strength": 3}]
    return scene


def run(purl, scene_path, out_dir, threads, model=None):
    image = os.path.join(out_dir, os.path.basename(scene_path).replace(".json", "") + ("-" + model if model else "") + ".png")
    cmd = ["/usr/bin/time", "-v", purl, "render", scene_path, "-o", image, "--stats", "--threads", str(threads)]
    if model:
        cmd += ["--model", model]
    start = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - start
    err = proc.stderr
    result = {"status": proc.returncode, "wall_s": wall}
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", err)
    if m:
        result["peak_rss_mb"] = int(m.group(1)) / 1024.0
    m = re.search(r"build ([\d.]+) s, render ([\d.]+) s, (\d+) threads", err)
    if m:
        result.update(build_s=float(m.group(1)), render_s=float(m.group(2)), threads=int(m.group(3)))
        result["load_s"] = wall - result["build_s"] - result["render_s"]
    m = re.search(r"samples (\d+) \(([\d.]+)/s\), rays (\d+)", err)
    if m:
        result.update(samples=int(m.group(1)), samples_per_s=float(m.group(2)), rays=int(m.group(3)))
    m = re.search(r"curves (\d+), control points (\d+), acceleration structure ([\d.]+) MB, "
                  r"frames and maps ([\d.]+) MB", err)
    if m:
        result.update(curves=int(m.group(1)), control_points=int(m.group(2)),
                      accel_mb=float(m.group(3)), shading_mb=float(m.group(4)))
    if proc.returncode != 0:
        result["error"] = " | ".join(l for l in err.splitlines() if "error" in l.lower())[:300]
    return result


def report(name, r, baseline_mb):
    if r["status"] != 0:
        print("  %-22s status %d after %.1f s, peak %.0f MB: %s" % (name, r["status"], r["wall_s"],
                                                                  r.get("peak_rss_mb", 0), r.get("error", "")))
        return
    cp = r["control_points"]
    per_cp = (r["peak_rss_mb"] - baseline_mb) * 1048576.0 / cp
    print("  %-22s %d curves, %d control points" % (name, r["curves"], cp))
    print("  %-22s load %.2f s, build %.2f s, render %.2f s (%d threads), %.0f samples/s, %.0f rays/s"
          % ("", r["load_s"], r["build_s"], r["render_s"], r["threads"], r["samples_per_s"],
             r["rays"] / max(r["render_s"], 1e-9)))
    print("  %-22s peak RSS %.0f MB (baseline %.0f MB): %.1f B per control point; Embree %.1f B/cp, "
          "frames+maps %.1f B/cp" % ("", r["peak_rss_mb"], baseline_mb, per_cp,
                                     r["accel_mb"] * 1048576.0 / cp, r["shading_mb"] * 1048576.0 / cp))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--purl", default=os.path.join(ROOT, "build", "purl"))
    ap.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data"))
    ap.add_argument("--out", default="/tmp/purl-scale")
    ap.add_argument("--glove-tiles", default="5x1", help="TXxTY, 0x0 to skip")
    ap.add_argument("--weave", type=int, default=500, help="warps = wefts of the sheet, 0 to skip")
    ap.add_argument("--size", type=int, default=64, help="image width and height")
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--models", default="ply,fiber", help="explicit models to try on each scene")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)

    scenes = [("baseline", baseline_scene())]
    tx, ty = (int(v) for v in args.glove_tiles.lower().split("x"))
    bcc = os.path.abspath(os.path.join(args.data, "glove.bcc"))
    if tx * ty > 0:
        if os.path.exists(bcc):
            scenes.append(("glove-%dx%d" % (tx, ty), glove_scene(tx, ty, bcc)))
        else:
            print("no %s: glove scene skipped" % bcc, file=sys.stderr)
    if args.weave > 0:
        scenes.append(("weave-%d" % args.weave, weave_scene(args.weave)))

    baseline_mb = 0.0
    for name, scene in scenes:
        path = os.path.join(args.out, name + ".json")
        with open(path, "w") as f:
            json.dump(finish(scene, args.size, args.spp), f, indent=1)
        r = run(args.purl, path, args.out, args.threads)
        if name == "baseline":
            baseline_mb = r.get("peak_rss_mb", 0.0)
            print("baseline (tiny scene): peak RSS %.0f MB" % baseline_mb)
            continue
        print("%s (%dx%d px, %d spp):" % (name, args.size, args.size, args.spp))
        report("bysdf", r, baseline_mb)
        for model in filter(None, args.models.split(",")):
            report("--model " + model, run(args.purl, path, args.out, args.threads, model), baseline_mb)


if __name__ == "__main__":
    main()
