#!/usr/bin/env python3
"""Why a preset misses its explicit-fiber target: what no yarn-level model can reach.

For each preset made by scripts/make_presets.py (its references kept in --work) it measures,
per lighting, FLIP (bench/metrics.py) of the explicit-fiber reference against
  - another explicit-fiber render of the same scene (seed 2, same spp): the reference's own noise;
  - the reference averaged over 3 x 3 pixels: the same image without its fiber-scale detail
    (single fibers and their glints are about one pixel wide here), the best a model whose
    smallest feature is a ply or a fiber bundle could do;
and lists the fitted BYSDF's and the fitted explicit plies' FLIP and mean brightness from the
preset's provenance.

    PYTHONPATH=<builddir> python3 tools/preset_limits.py [--work DIR] [--only cotton,wool]
"""
import argparse
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "bench"))
import metrics  # noqa: E402

LIGHTINGS = ("front", "back", "both")


def box3(image):
    padded = np.pad(image, ((1, 1), (1, 1), (0, 0)), mode="edge")
    h, w = image.shape[:2]
    return sum(padded[dy:dy + h, dx:dx + w] for dy in range(3) for dx in range(3)) / 9.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--work", default=str(Path(tempfile.gettempdir()) / "purl_preset_references"))
    ap.add_argument("--only", default="")
    args = ap.parse_args()
    import purlcore
    names = [n for n in args.only.split(",") if n] or sorted(p.stem for p in (REPO / "presets").glob("*.json"))
    print("| preset | light | FLIP fiber seed 1 vs 2 | FLIP fiber vs its 3x3 mean | FLIP BYSDF | FLIP plies | "
          "mean fiber / BYSDF |")
    print("|---|---|---|---|---|---|---|")
    for name in names:
        preset = json.loads((REPO / "presets" / f"{name}.json").read_text())
        check = preset["provenance"]["check"]
        spp, seed = preset["provenance"]["reference"]["spp"], preset["provenance"]["reference"]["seed"]
        for light in LIGHTINGS:
            reference = purlcore.read_image(str(Path(args.work) / f"{name}_{light}_fiber.exr"))
            scene = json.loads((REPO / "presets" / "sources" / f"{name}_{light}.json").read_text())
            job = purlcore.RenderJob(scene, None, str(REPO / "presets" / "sources"), "fiber")
            job.start(spp=spp, seed=seed + 1)
            job.wait()
            other = np.asarray(job.passes()["Combined"])[..., :3].astype(np.float32)
            print(f"| {name} | {light} | {metrics.flip(other, reference):.3f} | "
                  f"{metrics.flip(box3(reference), reference):.3f} | {check['flip_vs_fiber'][light]:.3f} | "
                  f"{check['flip_ply_vs_fiber'][light]:.3f} | {np.mean(check['mean_fiber'][light]):.4f} / "
                  f"{np.mean(check['mean_bysdf'][light]):.4f} |", flush=True)


if __name__ == "__main__":
    main()
