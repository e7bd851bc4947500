#!/usr/bin/env python3
"""Equal-quality time of the multi-scale modes: the glove (BYSDF) far away and close up,
near vs multi vs auto (and far on the far view), each against its own converged image.

For each view and mode one RenderJob (the scene is built once) renders a reference at
--ref-spp, then --repeats renders at every --spp with other seeds. The modes take turns inside
each repeat (near, multi, auto, ... near, multi, ...) so load changes on a shared machine hit
them alike. Quality is the relative MSE against the mode's own reference,
    relMSE = mean((I - R)^2) / mean(R)^2     (over pixels and RGB),
which for a Monte Carlo image falls as v / spp. The reference's own noise adds v / ref_spp, so
    v = relMSE / (1 / spp + 1 / ref_spp),
and the time to reach a target relMSE e is  T(e) = v x (render seconds per spp) / e.
Reported: the median over repeats and sample counts of v x seconds-per-spp, T at --target,
and the ratios of near's T to the others' (> 1: faster than near at equal quality).
The multi-scale modes converge to a different image than near where a yarn is wider than a
pixel (and far is wrong there, Khattar et al. 2024 Fig. 8), which is why each mode is
measured against its own converged image, as the paper does.

Usage: PYTHONPATH=<builddir> python3 bench/multiscale_equal_quality.py [--views far,close]
       [--spp 2,4] [--ref-spp 32] [--repeats 3] [--threads 2] [--scale 1] [--json out.json]
       [--set multiscale_max_h_samples=5 ...]
"""
import argparse
import copy
import json
import os
import statistics
import sys
import time

import numpy as np
import purlcore

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = os.path.join(ROOT, "tests", "data", "multiscale")  # glove_{close,mid,far}.json


def load_view(view, scale, overrides):
    with open(os.path.join(SCENES, f"glove_{view}.json")) as f:
        scene = json.load(f)
    # A larger film with the same field of view: yarns cover the same share of the frame, and
    # `scale` times as many pixels per yarn.
    scene = copy.deepcopy(scene)
    scene["film"]["width"] = int(round(scene["film"]["width"] * scale))
    scene["film"]["height"] = int(round(scene["film"]["height"] * scale))
    scene["render"].setdefault("multiscale", {}).update(overrides)
    return scene


def render(job, spp, seed, threads):
    job.start(spp=spp, seed=seed, threads=threads)
    job.wait()
    if job.error:
        raise RuntimeError(job.error)
    stats = job.stats()
    image = np.asarray(job.passes()["Combined"], dtype=np.float64)[:, :, :3]
    return image, stats


def relative_mse(image, reference):
    return float(np.mean((image - reference) ** 2) / max(np.mean(reference) ** 2, 1e-30))


def measure_view(view, modes, args):
    scene = load_view(view, args.scale, args.set)
    jobs = {m: purlcore.RenderJob(scene, base_dir=SCENES, mode=m) for m in modes}
    references, hits = {}, {}
    for m in modes:
        start = time.time()
        references[m], stats = render(jobs[m], args.ref_spp, 1000, args.threads)
        hits[m] = stats
        print(f"  {view}/{m}: reference {args.ref_spp} spp in {time.time() - start:.1f} s; "
              f"hits {stats['multiscale_hits']}, mean h samples {stats['mean_h_samples']:.2f}", file=sys.stderr)
    samples = {m: [] for m in modes}  # v x seconds per spp, per render
    seconds = {m: [] for m in modes}
    relmse = {m: {s: [] for s in args.spp} for m in modes}
    for r in range(args.repeats):
        for spp in args.spp:
            for m in modes:
                image, stats = render(jobs[m], spp, 1 + r * 100 + spp, args.threads)
                e = relative_mse(image, references[m])
                v = e / (1.0 / spp + 1.0 / args.ref_spp)
                per_spp = stats["render_seconds"] / spp
                samples[m].append(v * per_spp)
                seconds[m].append(per_spp)
                relmse[m][spp].append(e)
        print(f"  {view}: repeat {r + 1}/{args.repeats} done", file=sys.stderr)
    out = {}
    for m in modes:
        cost = statistics.median(samples[m])
        out[m] = {
            "seconds_per_spp": statistics.median(seconds[m]),
            "relmse_per_spp": {str(s): statistics.median(relmse[m][s]) for s in args.spp},
            "variance_times_seconds": cost,
            "time_to_target": cost / args.target,
            "mean_h_samples": hits[m]["mean_h_samples"],
            "hits": hits[m]["multiscale_hits"],
        }
    for m in modes:
        out[m]["speedup_vs_near"] = out["near"]["time_to_target"] / out[m]["time_to_target"]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--views", default="far,close")
    ap.add_argument("--spp", default="2,4", help="sample counts of the timed renders")
    ap.add_argument("--ref-spp", type=int, default=32)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--scale", type=float, default=1.0, help="film size factor over the test scenes (64 x 80)")
    ap.add_argument("--target", type=float, default=0.01, help="relMSE whose time is reported")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="a render.multiscale parameter for every mode, e.g. multiscale_max_h_samples=5")
    ap.add_argument("--json", default="", help="also write the results here")
    args = ap.parse_args()
    args.spp = [int(s) for s in args.spp.split(",")]
    args.set = {k: float(v) for k, v in (item.split("=", 1) for item in args.set)}
    start = time.time()
    results = {}
    for view in args.views.split(","):
        modes = ["near", "multi", "auto"] + (["far"] if view == "far" else [])
        results[view] = measure_view(view, modes, args)
    print(f"\nglove, film {64 * args.scale:.0f} x {80 * args.scale:.0f}, references {args.ref_spp} spp, "
          f"timed at {args.spp} spp x {args.repeats} repeats, {args.threads} threads, "
          f"{time.time() - start:.0f} s in all" + (f", multiscale {args.set}" if args.set else ""))
    print(f"| view | mode | s per spp | mean h samples | relMSE at {args.spp[-1]} spp | "
          f"time to relMSE {args.target} (s) | speed-up vs near |")
    print("|---|---|---|---|---|---|---|")
    for view, modes in results.items():
        for m, r in modes.items():
            print(f"| {view} | {m} | {r['seconds_per_spp']:.3f} | {r['mean_h_samples']:.2f} | "
                  f"{r['relmse_per_spp'][str(args.spp[-1])]:.4f} | {r['time_to_target']:.1f} | "
                  f"{r['speedup_vs_near']:.2f} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"args": vars(args), "results": results}, f, indent=2)


if __name__ == "__main__":
    main()
