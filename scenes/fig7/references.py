#!/usr/bin/env python3
"""Renders the converged explicit-ply references of the nine Fig. 7 scenes (the ply-based
model of Montazeri et al. 2020 on the same yarn and material, docs/explicit-references.md) at
the scenes' 192 x 96 and writes them to tests/data/fig7/ply/<scene>.exr (half float, zip).

    PYTHONPATH=<builddir> python3 scenes/fig7/references.py [--chunks 16] [--work DIR]

Each image is the mean of --chunks independent renders of 256 samples per pixel (seeds 1000,
1001, ...), 2048 spp by default: 5-15 minutes a scene on two busy cores. Chunks are kept in
--work (default: a folder in the system's temporary directory) as .npy files, so an interrupted
run resumes where it stopped."""
import argparse
import json
import tempfile
import time
from pathlib import Path

import numpy as np

import purlcore

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
OUT = ROOT / "tests" / "data" / "fig7" / "ply"
PLIES = (1, 3, 6)
LIGHTS = ("front", "back", "both")
CHUNK_SPP, FIRST_SEED = 256, 1000


def scene_names():
    return [f"yarn_{plies}ply_{light}" for plies in PLIES for light in LIGHTS]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--chunks", type=int, default=8, help="renders of 256 spp averaged per image")
    ap.add_argument("--work", default=str(Path(tempfile.gettempdir()) / "purl_fig7_references"))
    args = ap.parse_args()
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    OUT.mkdir(parents=True, exist_ok=True)
    for name in scene_names():
        scene = json.loads((HERE / f"{name}.json").read_text())
        chunks = []
        for c in range(args.chunks):
            path = work / f"{name}_{c}.npy"
            if not path.exists():
                started = time.time()
                job = purlcore.RenderJob(scene, None, str(HERE), "ply")
                job.start(spp=CHUNK_SPP, seed=FIRST_SEED + c)
                job.wait()
                np.save(path, np.asarray(job.passes()["Combined"])[..., :3].astype(np.float32))
                print(f"{name}: chunk {c + 1}/{args.chunks} in {time.time() - started:.1f} s", flush=True)
            chunks.append(np.load(path))
        purlcore.write_image(str(OUT / f"{name}.exr"), np.mean(chunks, axis=0))
        print(f"wrote {OUT / name}.exr ({args.chunks * CHUNK_SPP} spp)", flush=True)


if __name__ == "__main__":
    main()
