#!/usr/bin/env python3
"""Issue 26 diagnostic: image means of the back-lit 3-ply Fig. 7 yarn, lobe by lobe, in the
near, multi and far (tabulated) modes (docs/multiscale.md, "Back light, lobe by lobe").

    PYTHONPATH=build python3 bench/far_field_backlight.py [--spp 128] [--seed 1] [--work /tmp/purl-farfield]

The film is 48 x 24 so the yarn (0.2 wide at 1.4) spans about 9.5 pixels and a 16-pixel
multi-scale footprint reaches both silhouettes: multi is then the sampled far field the table is
built from, and far/multi compares the table with its own source in the renderer, multi/near
the far-field model with the plies it averages. "Only" keeps one lobe's albedo (the others 0).
"""
import argparse
import json
import subprocess
from pathlib import Path

import purlcore

REPO = Path(__file__).resolve().parent.parent
SCENE = REPO / "scenes" / "fig7" / "yarn_3ply_back.json"
LOBES = ("specular_reflection_albedo", "specular_transmission_albedo", "body_reflection_albedo",
         "body_transmission_albedo")


def scene_for(lobe, work):
    d = json.loads(SCENE.read_text())
    d["film"] = {"width": 48, "height": 24}
    d["yarns"][0]["bcc"] = str(SCENE.parent / d["yarns"][0]["bcc"])
    d["render"]["multiscale"] = {"multiscale_footprint_scale": 16}
    m = d["yarns"][0]["material"]
    if lobe:
        for k in LOBES:
            if k != lobe:
                m[k] = [0, 0, 0]
    path = work / f"{lobe or 'all'}.json"
    path.write_text(json.dumps(d))
    return path


def image_mean(scene, mode, spp, seed, work):
    out = work / f"{scene.stem}_{mode}_{seed}.exr"
    subprocess.run([str(REPO / "build" / "purl"), "render", str(scene), "-o", str(out), "--spp", str(spp),
                    "--seed", str(seed), "--mode", mode, "--threads", "2"], check=True, capture_output=True)
    return float(purlcore.read_image(str(out)).mean())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spp", type=int, default=128)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--work", type=Path, default=Path("/tmp/purl-farfield"))
    a = ap.parse_args()
    a.work.mkdir(parents=True, exist_ok=True)
    print(f"{'lobes':30s} {'near':>8s} {'multi':>8s} {'far':>8s}  far/multi multi/near far/near")
    for lobe in (None,) + LOBES:
        scene = scene_for(lobe, a.work)
        m = {mode: image_mean(scene, mode, a.spp, a.seed, a.work) for mode in ("near", "multi", "far")}
        print(f"{'only ' + lobe if lobe else 'all':30s} {m['near']:8.5f} {m['multi']:8.5f} {m['far']:8.5f}  "
              f"{m['far'] / m['multi']:9.3f} {m['multi'] / m['near']:10.3f} {m['far'] / m['near']:8.3f}", flush=True)


if __name__ == "__main__":
    main()
