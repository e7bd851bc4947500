#!/usr/bin/env python3
"""Equal-quality time of the multi-scale modes: the glove (BYSDF) far away and close up (and
at mid distance), near vs multi vs far vs auto, each against its own converged image.

For each view and mode one RenderJob (the scene is built once) renders a reference at
--ref-spp, then --repeats renders at every --spp with other seeds. The modes take turns inside
each repeat (near, multi, auto, ... near, multi, ...) so load changes on a shared machine hit
them alike. Quality is the relative MSE against the mode's own reference,
    relMSE = mean((I - R)^2) / mean(R)^2     (over pixels and RGB),
which for a Monte Carlo image falls as v / spp. The reference's own noise adds v / ref_spp, so
    v = relMSE / (1 / spp + 1 / ref_spp),
and the time to reach a target relMSE e is  T(e) = v x (render seconds per spp) / e, with the
render's CPU seconds (all threads of this process; --clock wall for wall-clock time).
Reported: the median over repeats and sample counts of v x seconds-per-spp, T at --target,
and the ratios of near's T to the others' (> 1: faster than near at equal quality).
The multi-scale modes converge to a different image than near where a yarn is wider than a
pixel (and far is wrong there, Khattar et al. 2024 Fig. 8), which is why each mode is
measured against its own converged image, as the paper does.

Accuracy: each mode's converged image against near's converged image (the near field is the
ground truth of the model): the ratio of image means, the relative MSE between the two
converged images and the part of it their own noise explains, (v_mode + v_near) / ref_spp, and
mean LDR FLIP (bench/metrics.py; None without flip-evaluator).

Modes: near, multi, far, auto, plus far-sampled (multi with a 16-pixel footprint: the sampled
far field, traced h samples, at every hit) to compare against the tabulated far field.

Usage: PYTHONPATH=<builddir> python3 bench/multiscale_equal_quality.py [--views far,close]
       [--modes near,multi,far,auto,far-sampled,multi:multiscale_sample_spacing=0.5] [--spp 2,4] [--ref-spp 32] [--repeats 3]
       [--threads 2] [--scale 1] [--json out.json] [--set multiscale_max_h_samples=5 ...]
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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import metrics  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = os.path.join(ROOT, "tests", "data", "multiscale")  # glove_{close,mid,far}.json
# label -> (render.multiscale mode, extra render.multiscale settings)
MODES = {"near": ("near", {}), "multi": ("multi", {}), "far": ("far", {}), "auto": ("auto", {}),
         "far-sampled": ("multi", {"multiscale_footprint_scale": 16.0})}


def mode_spec(label):
    """(mode, extra settings) of a --modes label: a name of MODES, optionally followed by
    ':NAME=VALUE' settings of its own (e.g. multi:multiscale_sample_spacing=0.5), so variants of
    one mode are timed side by side in one run."""
    name, *settings = label.split(":")
    mode, extra = MODES[name]
    return mode, {**extra, **{k: float(v) for k, v in (item.split("=", 1) for item in settings)}}


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
    cpu = time.process_time()
    job.start(spp=spp, seed=seed, threads=threads)
    job.wait()
    if job.error:
        raise RuntimeError(job.error)
    stats = job.stats()
    stats["cpu_seconds"] = time.process_time() - cpu  # every thread of this process
    image = np.asarray(job.passes()["Combined"], dtype=np.float64)[:, :, :3]
    return image, stats


def relative_mse(image, reference):
    return float(np.mean((image - reference) ** 2) / max(np.mean(reference) ** 2, 1e-30))


def measure_view(view, modes, args):
    jobs = {m: purlcore.RenderJob(load_view(view, args.scale, {**args.set, **mode_spec(m)[1]}), base_dir=SCENES,
                                  mode=mode_spec(m)[0]) for m in modes}
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
                per_spp = stats["cpu_seconds" if args.clock == "cpu" else "render_seconds"] / spp
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
        # Accuracy against near's converged image, and how much of the difference is noise.
        r, n = references[m], references["near"]
        v_mode = out[m]["variance_times_seconds"] / out[m]["seconds_per_spp"]
        v_near = out["near"]["variance_times_seconds"] / out["near"]["seconds_per_spp"]
        out[m]["mean_vs_near"] = float(np.mean(r) / max(np.mean(n), 1e-30))
        out[m]["relmse_vs_near"] = relative_mse(r, n)
        out[m]["noise_part_vs_near"] = (v_mode + v_near) / args.ref_spp if m != "near" else 2 * v_near / args.ref_spp
        out[m]["flip_vs_near"] = metrics.flip(r.astype(np.float32), n.astype(np.float32))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--views", default="far,close")
    ap.add_argument("--modes", default="near,multi,far,auto,far-sampled", help=f"of {', '.join(MODES)}, each optionally with :NAME=VALUE settings of its own; near first")
    ap.add_argument("--spp", default="2,4", help="sample counts of the timed renders")
    ap.add_argument("--ref-spp", type=int, default=32)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--scale", type=float, default=1.0, help="film size factor over the test scenes (64 x 80)")
    ap.add_argument("--target", type=float, default=0.01, help="relMSE whose time is reported")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="a render.multiscale parameter for every mode, e.g. multiscale_max_h_samples=5")
    ap.add_argument("--clock", choices=("cpu", "wall"), default="cpu",
                    help="the cost of a render: CPU seconds of this process (steadier on a shared machine) "
                         "or wall-clock seconds")
    ap.add_argument("--json", default="", help="also write the results here")
    args = ap.parse_args()
    args.spp = [int(s) for s in args.spp.split(",")]
    args.set = {k: float(v) for k, v in (item.split("=", 1) for item in args.set)}
    start = time.time()
    results = {}
    for view in args.views.split(","):
        results[view] = measure_view(view, args.modes.split(","), args)
    print(f"\nglove, film {64 * args.scale:.0f} x {80 * args.scale:.0f}, references {args.ref_spp} spp, "
          f"timed at {args.spp} spp x {args.repeats} repeats, {args.threads} threads, {args.clock} time, "
          f"{time.time() - start:.0f} s in all" + (f", multiscale {args.set}" if args.set else ""))
    print(f"| view | mode | s per spp | mean h samples | relMSE at {args.spp[0]} / {args.spp[-1]} spp | "
          f"time to relMSE {args.target} (s) | speed-up vs near | mean vs near | relMSE vs near (noise part) | "
          f"FLIP vs near |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for view, modes in results.items():
        for m, r in modes.items():
            flip = "-" if r["flip_vs_near"] is None else f"{r['flip_vs_near']:.4f}"
            print(f"| {view} | {m} | {r['seconds_per_spp']:.3f} | {r['mean_h_samples']:.2f} | "
                  f"{r['relmse_per_spp'][str(args.spp[0])]:.4f} / {r['relmse_per_spp'][str(args.spp[-1])]:.4f} | "
                  f"{r['time_to_target']:.1f} | {r['speedup_vs_near']:.2f} | {r['mean_vs_near']:.4f} | "
                  f"{r['relmse_vs_near']:.4f} ({r['noise_part_vs_near']:.4f}) | {flip} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"args": vars(args), "results": results}, f, indent=2)


if __name__ == "__main__":
    main()
