#!/usr/bin/env python3
"""Renders the nine Fig. 7 scenes (1, 3, 6 plies x front, back, both lights) with the BYSDF and
lays them out as one labelled contact sheet (rows: plies, columns: lighting).

    PYTHONPATH=<builddir> python3 scenes/fig7/contact_sheet.py [--spp 64] [--out docs/images/fig7_bysdf.png]

Images are shown as sRGB of the linear render (no exposure change, values above 1 clipped), so
the three lightings keep their relative brightness."""
import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import purlcore  # noqa: E402

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
PLIES = (1, 3, 6)
LIGHTS = ("front", "back", "both")


def srgb(linear):
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spp", type=int, default=None, help="samples per pixel (default: the scenes' own)")
    ap.add_argument("--out", default=str(ROOT / "docs" / "images" / "fig7_bysdf.png"))
    args = ap.parse_args()

    fig, axes = plt.subplots(len(PLIES), len(LIGHTS), figsize=(7.2, 3.9), dpi=110)
    for r, plies in enumerate(PLIES):
        for c, light in enumerate(LIGHTS):
            path = HERE / f"yarn_{plies}ply_{light}.json"
            scene = json.loads(path.read_text())
            rgb = purlcore.render(scene, base_dir=str(HERE), spp=args.spp)["Combined"][..., :3]
            ax = axes[r][c]
            ax.imshow(srgb(rgb), interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            if r == 0:
                ax.set_title({"front": "front light", "back": "back light", "both": "front + back"}[light], fontsize=10)
            if c == 0:
                ax.set_ylabel("1 ply" if plies == 1 else f"{plies} plies", fontsize=10)
            print(path.name, flush=True)
    fig.suptitle("BYSDF, single yarn (Khattar et al. 2024, Fig. 7 set-up)", fontsize=11)
    fig.tight_layout(pad=0.4)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out)
    print("wrote", args.out)


if __name__ == "__main__":
    main()
