#!/usr/bin/env python3
"""Draw where in the benchmark garments the implicit ply methods disagree with explicit plies.

Input: a dump of bench/native/dump_ply_queries (which records each ray's film position).
    python3 tools/draw_cloth_accuracy.py /tmp/dump --out docs/images/cloth-ply-accuracy.png

One row per scene, with these columns:
- tangent error of the exact (elliptical) method, then of the local one, in degrees, where the
  answer and the explicit plies hit the same ply (mean of the pixel's rays);
- the share of each pixel's rays on which the hit state, the ply or N_i differ from the explicit
  answer, exact then local;
- the distribution of tangent errors of every method (exact, local, circular).
Rays whose explicit answer met another passage of the yarn are left out (and counted).
"""
import argparse
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from compare_ply_queries import load_or_exit, mismatch, same_ply, tangent_turn  # noqa: E402

TANGENT_SCALE = 3.0  # degrees at full colour


def binned_mean(x, y, values, shape):
    """Mean of `values` per film pixel (NaN where no ray fell), from the rays' film positions."""
    rows = np.clip(y.astype(int), 0, shape[0] - 1)
    cols = np.clip(x.astype(int), 0, shape[1] - 1)
    total = np.zeros(shape)
    count = np.zeros(shape)
    np.add.at(total, (rows, cols), values)
    np.add.at(count, (rows, cols), 1)
    with np.errstate(invalid="ignore"):
        return total / count


def draw(meta, data, out):
    col = {name: i for i, name in enumerate(meta["fields"])}
    methods = meta["methods"]
    for needed in ("explicit", "elliptical", "local"):
        if needed not in methods:
            raise SystemExit(f"the dump has no `{needed}` method; it has {', '.join(methods)}")
    if "film_x" not in col:
        raise SystemExit("the dump has no film positions; write it again with a current dump_ply_queries")
    ref = methods.index("explicit")
    shown = [("elliptical", "exact"), ("local", "local")]
    curves = [(m, label) for m, label in (("elliptical", "exact"), ("local", "local"), ("circular", "circular"))
              if m in methods]
    scenes = list(data)
    fig, axes = plt.subplots(len(scenes), 5, figsize=(21, 4.6 * len(scenes)), squeeze=False)
    for row, scene in enumerate(scenes):
        d = data[scene]
        e = d[:, ref]
        x, y = e[:, col["film_x"]], e[:, col["film_y"]]
        shape = (int(np.ceil(y.max() + 1e-3)), int(np.ceil(x.max() + 1e-3)))
        comparable = e[:, col["converged"]] == 1
        for k, (method, label) in enumerate(shown):
            m = d[:, methods.index(method)]
            same = same_ply(m, e, col, comparable)
            err = tangent_turn(m[same], e[same], col)
            ax = axes[row, k]
            image = ax.imshow(binned_mean(x[same], y[same], err, shape), cmap="inferno", vmin=0, vmax=TANGENT_SCALE)
            ax.set_facecolor("0.2")
            ax.set_title(f"{label}: tangent error (mean {err.mean():.3f} deg)", fontsize=10)
            if k == 0:
                ax.set_ylabel(scene, fontsize=12)
            fig.colorbar(image, ax=ax, fraction=0.046, label="degrees")
            wrong = mismatch(m, e, col, comparable)
            ax = axes[row, 2 + k]
            image = ax.imshow(binned_mean(x[comparable], y[comparable], wrong[comparable].astype(float), shape),
                              cmap="Blues", vmin=0, vmax=0.5)
            ax.set_facecolor("0.2")
            ax.set_title(f"{label}: hit, ply or N_i wrong on {wrong.sum() / comparable.sum():.2%} of rays", fontsize=10)
            fig.colorbar(image, ax=ax, fraction=0.046, label="share of the pixel's rays")
        ax = axes[row, 4]
        for method, label in curves:
            m = d[:, methods.index(method)]
            same = same_ply(m, e, col, comparable)
            err = np.sort(tangent_turn(m[same], e[same], col))
            ax.plot(np.maximum(err, 1e-4), np.arange(1, len(err) + 1) / len(err), label=label)
        ax.set_xscale("log")
        ax.set_xlim(1e-3, 30)
        ax.set_xlabel("tangent error against explicit plies, degrees")
        ax.set_ylabel("share of rays on the same ply")
        ax.set_title(f"{scene}: {comparable.sum()} rays compared, {(~comparable).sum()} left out", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        for ax in axes[row, :4]:
            ax.set_xticks([])
            ax.set_yticks([])
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    print(f"wrote {out}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("prefix", help="dump_ply_queries output prefix")
    parser.add_argument("--out", default="cloth-ply-accuracy.png")
    args = parser.parse_args()
    meta, data = load_or_exit(args.prefix, "draw_cloth_accuracy")
    draw(meta, data, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
