#!/usr/bin/env python3
"""Fireflies of the demo knit at 16 spp, with path regularisation (render.filter_glossy, Cycles'
Filter Glossy) off and on, against the converged image of each; and how far the regularisation
moves the converged image itself (docs/denoising.md).

    PYTHONPATH=build python3 bench/fireflies.py [--work /tmp/purl-denoise] [--reference-spp 128]

Per pixel, the error is the largest channel of |image - converged| (linear radiance); the figure
of merit is its 99.9th percentile over the pixels of four 16-spp renders (seeds 1-4), pooled.
Writes bench/results/fireflies.json.
"""
import argparse
import json
import os
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "bench"))
from denoise_quality import reference, render, scenes  # noqa: E402
from metrics import relative_mse  # noqa: E402

SEEDS = (1, 2, 3, 4)
SPP = 16
SETTINGS = (0.0, 1.0)  # filter_glossy off (before) and on (the default)


def pixel_errors(image, converged):
    return np.max(np.abs(image - converged), axis=-1).ravel()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--work", default="/tmp/purl-denoise")
    parser.add_argument("--reference-spp", type=int, default=128)
    parser.add_argument("--output", default=str(REPO / "bench" / "results" / "fireflies.json"))
    args = parser.parse_args()
    import purlcore
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    name, scene, base = scenes()[0]  # the demo knit
    result = {"scene": name, "size": [scene["film"]["width"], scene["film"]["height"]], "spp": SPP,
              "seeds": list(SEEDS), "reference_spp": 2 * args.reference_spp, "settings": {}}
    converged = {}
    for fg in SETTINGS:
        ref_a, ref_b = reference(purlcore, name, scene, base, args.reference_spp, work, fg)
        converged[fg] = (ref_a, ref_b)
        ref = 0.5 * (ref_a + ref_b)
        errors, relmse, seconds = [], [], []
        for seed in SEEDS:
            passes, stats = render(purlcore, scene, base, SPP, seed, False, fg)
            errors.append(pixel_errors(passes["Combined"], ref))
            relmse.append(relative_mse(passes["Combined"], ref_a, ref_b)[0])
            seconds.append(stats["render_seconds"])
        errors = np.concatenate(errors)
        # The converged image's own noise at the same percentile: halves against each other.
        ref_noise = pixel_errors(ref_a, ref_b) / 2
        entry = {"p99_9": float(np.percentile(errors, 99.9)), "p99": float(np.percentile(errors, 99)),
                 "max": float(errors.max()), "relmse": float(np.mean(relmse)),
                 "render_seconds": float(np.median(seconds)),
                 "reference_noise_p99_9": float(np.percentile(ref_noise, 99.9)),
                 "converged_mean_rgb": [float(v) for v in ref.reshape(-1, 3).mean(axis=0)]}
        result["settings"]["{:g}".format(fg)] = entry
        print("filter_glossy {:g}: 99.9th pct pixel error {:.4f} (99th {:.4f}, max {:.3f}), relMSE {:.4f}, "
              "{:.1f} s per render".format(fg, entry["p99_9"], entry["p99"], entry["max"], entry["relmse"],
                                          entry["render_seconds"]), flush=True)
    # Bias of the regularisation: the converged images against each other, less their noise.
    off, on = converged[0.0], converged[1.0]
    bias, noise = relative_mse(0.5 * (on[0] + on[1]), off[0], off[1])
    mean_off = 0.5 * (off[0] + off[1])
    mean_on = 0.5 * (on[0] + on[1])
    result["converged_change"] = {
        "relmse": bias, "reference_noise_relmse": noise,
        "mean_change": float(mean_on.mean() / mean_off.mean() - 1.0),
        "p99_9_pixel_change": float(np.percentile(pixel_errors(mean_on, mean_off), 99.9))}
    result["load"] = os.getloadavg()
    print("converged change: relMSE {relmse:.5f} (noise {reference_noise_relmse:.5f} subtracted), mean {mean_change:+.3%}, "
          "99.9th pct pixel change {p99_9_pixel_change:.4f}".format(**result["converged_change"]))
    Path(args.output).write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
