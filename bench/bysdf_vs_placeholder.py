#!/usr/bin/env python3
"""Time per camera sample of the demo scene (scenes/demo_knit.json) with the BYSDF against the
placeholder material, side by side in one run.

The two materials are rendered alternately (B, P, B, P, ...) so that load changes on a shared
machine hit both alike; the report gives the median over repeats of render seconds per camera
sample for each, their ratio, and rays and path length per sample (the BYSDF's implicit plies let
rays pass between them and its transmission lobes continue paths, so it also traces more).
The placeholder yarn takes the BYSDF yarn's body transmission colour; the geometry, lights,
camera and seed are the same.

Usage: PYTHONPATH=<builddir> python3 bench/bysdf_vs_placeholder.py [--repeats 5] [--spp 4]
       [--scale 0.5] [--threads 0]
"""
import argparse
import copy
import json
import os
import statistics
import sys

import purl_worker  # bench/, beside this file
import purlcore

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def scene_variants(scale):
    with open(os.path.join(ROOT, "scenes", "demo_knit.json")) as f:
        bysdf = json.load(f)
    bysdf["film"]["width"] = max(8, int(bysdf["film"]["width"] * scale))
    bysdf["film"]["height"] = max(8, int(bysdf["film"]["height"] * scale))
    placeholder = purl_worker.placeholder_materials(copy.deepcopy(bysdf))
    return {"bysdf": bysdf, "placeholder": placeholder}


def render_once(job, spp, threads):
    job.start(spp=spp, seed=1, threads=threads)
    job.wait()
    if job.error:
        raise RuntimeError(job.error)
    s = job.stats()
    return {"seconds_per_sample": s["render_seconds"] / s["samples"], "rays_per_sample": s["rays"] / s["samples"],
            "path_length": s["mean_path_length"], "threads": s["threads"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--scale", type=float, default=0.5, help="film size relative to the scene's 480 x 360")
    ap.add_argument("--threads", type=int, default=0, help="0: all cores")
    args = ap.parse_args()

    scenes = scene_variants(args.scale)
    # Scenes are built once (Embree, frames, fiber maps); only the render is timed.
    jobs = {name: purlcore.RenderJob(json.dumps(s), base_dir=os.path.join(ROOT, "scenes")) for name, s in scenes.items()}
    for name in jobs:  # warm-up: page in code and data
        render_once(jobs[name], 1, args.threads)
    runs = {name: [] for name in jobs}
    for _ in range(args.repeats):
        for name in jobs:
            runs[name].append(render_once(jobs[name], args.spp, args.threads))

    film = scenes["bysdf"]["film"]
    print(f"demo_knit.json at {film['width']} x {film['height']}, {args.spp} spp, {args.repeats} alternating repeats, "
          f"{runs['bysdf'][0]['threads']} threads")
    print(f"{'material':<12} {'us/sample (median)':>19} {'min':>8} {'max':>8} {'rays/sample':>12} {'path length':>12}")
    median = {}
    for name, rs in runs.items():
        t = [r["seconds_per_sample"] * 1e6 for r in rs]
        median[name] = statistics.median(t)
        print(f"{name:<12} {median[name]:>19.2f} {min(t):>8.2f} {max(t):>8.2f} "
              f"{statistics.median(r['rays_per_sample'] for r in rs):>12.2f} "
              f"{statistics.median(r['path_length'] for r in rs):>12.2f}")
    ratios = [b["seconds_per_sample"] / p["seconds_per_sample"] for b, p in zip(runs["bysdf"], runs["placeholder"])]
    print(f"BYSDF / placeholder time per sample: {median['bysdf'] / median['placeholder']:.2f} "
          f"(ratio of medians); per-repeat ratios {', '.join(f'{r:.2f}' for r in ratios)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
