#!/usr/bin/env python3
"""Regenerates presets/<name>.json: BYSDF parameters fitted to the explicit-fiber reference.

For each fiber BCSDF preset of Khungurn et al. 2015 (cotton, silk, polyester, fleece, gabardine):
  1. writes the source scenes presets/sources/<name>_{front,back,both}.json: the 3-ply yarn of
     the paper's Fig. 7 (scenes/fig7/single_yarn.bcc), 96 x 48 px, whose explicit fibers use the
     published fiber parameters of that name;
  2. renders the explicit-fiber references (`purl render --model fiber`) into a work folder;
  3. fits the BYSDF to the front-lit and back-lit references with `purl fit` (progress shown);
  4. checks the fit without refitting: renders front, back and front+back lighting with the
     fitted BYSDF and compares with the explicit-fiber references and with explicit-ply renders
     of the fitted material: mean squared error and FLIP (PyPI flip-evaluator, LDR-FLIP on the
     clamped sRGB images), and writes those numbers into the preset's provenance.

    PYTHONPATH=build python3 scripts/make_presets.py [--purl build/purl] [--only cotton,silk]

Needs purlcore (PYTHONPATH) and `pip install flip-evaluator`. About 2-4 minutes per preset on
two cores; the references go to --work (default: a temporary folder) and are not kept.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
PRESETS = REPO / "presets"
SOURCES = PRESETS / "sources"
NAMES = ("cotton", "silk", "polyester", "fleece", "gabardine")

FRONT_LIGHT = {"type": "area", "size": 0.6, "position": [-0.6, -1.4, 1.0], "look_at": [0, 0, 0],
               "power": 60, "color": [1.0, 0.96, 0.9]}
BACK_LIGHT = {"type": "area", "shape": "DISK", "size": 0.5, "position": [0.2, 1.5, 1.0], "look_at": [0, 0, 0],
              "power": 60, "color": [1.0, 0.96, 0.9]}
LIGHTINGS = {"front": [FRONT_LIGHT], "back": [BACK_LIGHT], "both": [FRONT_LIGHT, BACK_LIGHT]}

WIDTH, HEIGHT = 96, 48
REFERENCE_SPP, REFERENCE_SEED = 128, 1
CHECK_SPP, CHECK_SEED = 128, 2
FIT_SPP, FIT_SEED, FIT_ITERATIONS, FIT_BLOCK = 8, 7, 6, 2
FIT_PARAMS = "kxB,kyB,sigma_t,ply_shadow_floor,fiber_shadow_floor"


def source_scene(name, lighting):
    """The Fig. 7 3-ply yarn; the fit starts from neutral grey body albedos."""
    return {
        "version": 1,
        "camera": {"position": [0.0, -1.4, 0.05], "look_at": [0.0, 0.0, 0.0], "lens": 50, "clip_start": 0.01},
        "film": {"width": WIDTH, "height": HEIGHT},
        "render": {"spp": REFERENCE_SPP, "seed": REFERENCE_SEED, "max_depth": 8},
        "world": {"color": [0.0, 0.0, 0.0]},
        "lights": LIGHTINGS[lighting],
        "yarns": [{
            "name": "yarn", "bcc": "../../scenes/fig7/single_yarn.bcc", "radius": 0.1,
            "material": {
                "model": "bysdf",
                "body_reflection_albedo": [0.3, 0.3, 0.3],
                "body_transmission_albedo": [0.5, 0.5, 0.5],
                "yarn": {"preset": "prototype", "ply_count": 3, "ply_radius": 0.464102, "ply_distance": 0.535898},
                "fiber": {"preset": name},
            },
        }],
    }


def render(core, scene, base_dir, model, spp, seed, exr=None):
    """Linear RGB (H, W, 3) of the Combined pass; also written to `exr` when given."""
    job = core.RenderJob(scene, None, str(base_dir), model)
    job.start(spp=spp, seed=seed)
    job.wait()
    if exr:
        job.write(str(exr))
    return np.asarray(job.passes()["Combined"])[..., :3].astype(np.float32)


def srgb(linear):
    c = np.clip(linear, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055).astype(np.float32)


def flip(reference, test):
    import flip_evaluator
    _, mean, _ = flip_evaluator.evaluate(srgb(reference), srgb(test), "LDR", inputsRGB=True, applyMagma=False)
    return float(mean)


def mse(a, b):
    return float(np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2))


def make_preset(core, purl, name, work):
    scene_paths = {}
    for lighting in LIGHTINGS:
        path = SOURCES / f"{name}_{lighting}.json"
        path.write_text(json.dumps(source_scene(name, lighting), indent=2) + "\n")
        scene_paths[lighting] = path
    started = time.time()
    fiber = {}
    for lighting, path in scene_paths.items():
        exr = work / f"{name}_{lighting}_fiber.exr"
        fiber[lighting] = render(core, json.loads(path.read_text()), SOURCES, "fiber", REFERENCE_SPP,
                                 REFERENCE_SEED, exr)
    reference_seconds = time.time() - started
    print(f"{name}: explicit-fiber references in {reference_seconds:.1f} s", flush=True)

    output = PRESETS / f"{name}.json"
    command = [str(purl), "fit", str(scene_paths["front"]), str(scene_paths["back"]),
               "--target", str(work / f"{name}_front_fiber.exr"), "--target", str(work / f"{name}_back_fiber.exr"),
               "--params", FIT_PARAMS, "--spp", str(FIT_SPP), "--seed", str(FIT_SEED),
               "--iterations", str(FIT_ITERATIONS), "--block", str(FIT_BLOCK), "--name", name, "-o", str(output)]
    subprocess.run(command, check=True)
    preset = json.loads(output.read_text())

    check = {"spp": CHECK_SPP, "seed": CHECK_SEED, "mse_vs_fiber": {}, "flip_vs_fiber": {}, "flip_vs_ply": {},
             "flip_ply_vs_fiber": {}}
    for lighting, path in scene_paths.items():
        scene = json.loads(path.read_text())
        scene["yarns"][0]["material"] = preset["material"]
        fitted = render(core, scene, SOURCES, "bysdf", CHECK_SPP, CHECK_SEED)
        ply = render(core, scene, SOURCES, "ply", CHECK_SPP, CHECK_SEED)
        check["mse_vs_fiber"][lighting] = mse(fitted, fiber[lighting])
        check["flip_vs_fiber"][lighting] = flip(fiber[lighting], fitted)
        check["flip_vs_ply"][lighting] = flip(ply, fitted)
        check["flip_ply_vs_fiber"][lighting] = flip(fiber[lighting], ply)

    # Provenance with repository-relative paths (the references are regenerated, not kept).
    provenance = preset["provenance"]
    for target, lighting in zip(provenance["targets"], ("front", "back")):
        target["scene"] = f"presets/sources/{name}_{lighting}.json"
        target["image"] = (f"explicit-fiber render of {target['scene']} "
                           f"(purl render --model fiber --spp {REFERENCE_SPP} --seed {REFERENCE_SEED})")
    provenance["reference"] = {
        "model": "fiber",
        "fiber_bcsdf": f"{name} (Khungurn et al. 2015 fit, native fiber preset)",
        "geometry": "scenes/fig7/single_yarn.bcc, 3 plies (prototype yarn with the Fig. 7 ply layout), "
                    f"{WIDTH} x {HEIGHT} px",
        "spp": REFERENCE_SPP, "seed": REFERENCE_SEED,
    }
    provenance["check"] = check
    provenance["generated_by"] = "scripts/make_presets.py"
    preset["description"] = (f"BYSDF fitted to explicit-fiber renders of a 3-ply yarn with the '{name}' fiber "
                             "parameters of Khungurn et al. 2015 (front- and back-lit)")
    preset["source"] = "scripts/make_presets.py"
    output.write_text(json.dumps(preset, indent=2) + "\n")
    total = time.time() - started
    print(f"{name}: fit {provenance['seconds']:.1f} s, {provenance['iterations']} iterations, "
          f"mse {provenance['final_mse']:.4g}; front+back mse {check['mse_vs_fiber']['both']:.4g}, "
          f"FLIP vs fiber {check['flip_vs_fiber']['both']:.4f}, vs ply {check['flip_vs_ply']['both']:.4f}; "
          f"{total:.0f} s in all", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--purl", default=str(REPO / "build" / "purl"), help="the purl binary")
    parser.add_argument("--only", default="", help="comma-separated preset names (default: all)")
    parser.add_argument("--work", default="", help="folder for the reference renders (default: temporary)")
    args = parser.parse_args()
    import purlcore
    names = [n for n in args.only.split(",") if n] or list(NAMES)
    for n in names:
        if n not in NAMES:
            sys.exit(f"make_presets.py: unknown preset '{n}' (known: {', '.join(NAMES)})")
    SOURCES.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as temporary:
        work = Path(args.work or temporary)
        work.mkdir(parents=True, exist_ok=True)
        for n in names:
            make_preset(purlcore, args.purl, n, work)


if __name__ == "__main__":
    main()
