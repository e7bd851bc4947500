#!/usr/bin/env python3
"""The paper's Fig. 7 protocol with Purl: for 1, 3 and 6 plies, fit the BYSDF to the converged
explicit-ply references (scenes/fig7/references.py) under front light and back light, then
check all three lightings (front, back, both) without refitting.

    PYTHONPATH=<builddir> python3 scenes/fig7/fit.py [--crossing 2] [--check-spp 512] [--sheet]

Writes scenes/fig7/fitted/yarn_<n>ply.json (the fitted material as a preset, with its
provenance), prints the before/after table of docs/bysdf.md (FLIP against the reference of the
BYSDF at the scene's own parameters, then with the fitted ones), and with --sheet draws
docs/images/fig7_fit.png (reference | BYSDF fitted | difference). --crossing 0 runs the same
with the paper's tau^N_i and G_p (ply_crossing 0), into fitted/paper_yarn_<n>ply.json; the default
is the spread crossing (2), --crossing 1 the traced one (both into fitted/yarn_<n>ply.json).

The fit: effective lobe albedos of the body lobes and the body extinction (axB, ayB, sigma_t;
7 unknowns, docs/fitting.md), 16 spp, seed 7, 2 x 2 blocks, at most 5 iterations."""
import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

import purlcore

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
REFERENCES = ROOT / "tests" / "data" / "fig7" / "ply"
FITTED = HERE / "fitted"
PLIES = (1, 3, 6)
LIGHTS = ("front", "back", "both")
FIT_PARAMS, FIT_SPP, FIT_SEED, FIT_BLOCK, FIT_ITERATIONS = "axB,ayB,sigma_t", 16, 7, 2, 5
FIT_ALL = "axS,ayS,axB,ayB,sigma_t,sigma_tS,alpha_x,alpha_y,alpha_t"  # --all: every lobe and roughness
sys.path.insert(0, str(ROOT / "bench"))
import metrics  # noqa: E402  (LDR FLIP of the benchmark: sRGB, clipped)


def scene(plies, light, crossing):
    s = json.loads((HERE / f"yarn_{plies}ply_{light}.json").read_text())
    s["yarns"][0]["material"]["ply_crossing"] = crossing
    return s


def fitted_path(plies, crossing):
    return FITTED / (f"yarn_{plies}ply.json" if crossing else f"paper_yarn_{plies}ply.json")


def render(s, spp, seed=2):
    job = purlcore.RenderJob(s, None, str(HERE), "bysdf")
    job.start(spp=spp, seed=seed)
    job.wait()
    return np.asarray(job.passes()["Combined"])[..., :3].astype(np.float32)


def with_material(s, material):
    s = json.loads(json.dumps(s))
    s["yarns"][0]["material"] = material
    return s


def fit(plies, crossing, params):
    targets = [{"scene": scene(plies, light, crossing), "image": str(REFERENCES / f"yarn_{plies}ply_{light}.exr")}
               for light in ("front", "back")]
    started = time.time()

    def progress(p):
        if p["event"] != "jacobian":
            print(f"  {plies} plies: iteration {p['iteration']} {p['event']}, mse {p['mse']:.4g}, "
                  f"{p['seconds']:.0f} s, at most ~{p['seconds_left']:.0f} s left", flush=True)
        return True
    preset = purlcore.fit(targets, base_dir=str(HERE), params=params, iterations=FIT_ITERATIONS, spp=FIT_SPP,
                          seed=FIT_SEED, block=FIT_BLOCK, progress=progress, name=f"fig7_{plies}ply")
    for t, light in zip(preset["provenance"]["targets"], ("front", "back")):
        t["scene"] = f"scenes/fig7/yarn_{plies}ply_{light}.json (ply_crossing {crossing})"
        t["image"] = f"tests/data/fig7/ply/yarn_{plies}ply_{light}.exr"
    preset["provenance"]["generated_by"] = "scenes/fig7/fit.py"
    FITTED.mkdir(exist_ok=True)
    fitted_path(plies, crossing).write_text(json.dumps(preset, indent=2) + "\n")
    print(f"{plies} plies: fitted in {time.time() - started:.0f} s", flush=True)
    return preset


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--crossing", type=int, default=2, choices=(0, 1, 2))
    ap.add_argument("--check-spp", type=int, default=512)
    ap.add_argument("--plies", default="1,3,6")
    ap.add_argument("--refit", action="store_true", help="fit again even when fitted/ holds a result")
    ap.add_argument("--all", action="store_true", help=f"fit {FIT_ALL} (17 unknowns) instead of {FIT_PARAMS}")
    ap.add_argument("--params", default="", help="fit these unknowns (purl fit names) instead")
    ap.add_argument("--sheet", action="store_true", help="draw docs/images/fig7_fit.png")
    args = ap.parse_args()
    rows, sheet = [], []
    for plies in (int(p) for p in args.plies.split(",")):
        path = fitted_path(plies, args.crossing)
        preset = (json.loads(path.read_text()) if path.exists() and not args.refit
                  else fit(plies, args.crossing, args.params or (FIT_ALL if args.all else FIT_PARAMS)))
        for light in LIGHTS:
            reference = purlcore.read_image(str(REFERENCES / f"yarn_{plies}ply_{light}.exr"))
            s = scene(plies, light, args.crossing)
            before = render(s, args.check_spp)
            after = render(with_material(s, preset["material"]), args.check_spp)
            rows.append((plies, light, metrics.flip(before, reference), metrics.flip(after, reference),
                         float(reference.mean()), float(before.mean()), float(after.mean())))
            sheet.append((plies, light, reference, after))
            print("| %d | %s | %.3f | %.3f | %.4f / %.4f / %.4f |" % rows[-1], flush=True)
    print("\n| plies | light | FLIP vs ply, scene's parameters | FLIP vs ply, fitted | mean ply / before / after |")
    print("|---|---|---|---|---|")
    for r in rows:
        print("| %d | %s | %.3f | %.3f | %.4f / %.4f / %.4f |" % r)
    if args.sheet:
        draw_sheet(sheet, ROOT / "docs" / "images" / "fig7_fit.png")


def draw_sheet(shots, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(shots), 3, figsize=(7.5, 1.35 * len(shots)), dpi=100)
    for row, (plies, light, reference, fitted) in enumerate(shots):
        diff = (fitted - reference).mean(axis=-1) * 5  # x5: red brighter, blue darker than the reference
        panels = (metrics.srgb(reference), metrics.srgb(fitted),
                  np.stack([np.clip(diff, 0, 1), np.zeros_like(diff), np.clip(-diff, 0, 1)], axis=-1))
        for col, image in enumerate(panels):
            ax = axes[row][col]
            ax.imshow(image, interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            if row == 0:
                ax.set_title(("explicit plies (reference)", "BYSDF, fitted", "difference x5 (red: brighter)")[col],
                             fontsize=9)
            if col == 0:
                ax.set_ylabel(f"{plies} ply {light}", fontsize=8)
    fig.tight_layout(pad=0.3)
    fig.savefig(out)
    print("wrote", out)


if __name__ == "__main__":
    main()
