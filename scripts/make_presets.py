#!/usr/bin/env python3
"""Regenerates presets/<name>.json: BYSDF parameters fitted to the explicit-fiber reference.

For each fiber BCSDF preset of Khungurn et al. 2015 (cotton, silk, polyester, fleece, gabardine),
and for `wool` (the gabardine fibers, a wool twill, on a 4-ply knitting-yarn layout):
  1. writes the source scenes presets/sources/<name>_{front,back,both}.json: the yarn of the
     paper's Fig. 7 (scenes/fig7/single_yarn.bcc), 96 x 48 px, whose explicit fibers use the
     published fiber parameters of that name;
  2. renders the explicit-fiber references (`--model fiber`) into the work folder (kept, so a
     second run resumes): the mean of YARN_SEEDS yarns whose fibers are placed with different
     seeds, so the target is the fiber model's expected look rather than one random placement,
     and one more yarn alone, whose distance from that mean (FLIP) is the floor below which no
     model that does not copy each fiber can go;
  3. fits the BYSDF to the front-lit and back-lit references with `purl fit`: every lobe's
     effective albedo (axS, ayS, axB, ayB: no direction that changes nothing), both
     extinctions and the three roughnesses, 17 unknowns, each target's error relative to its
     own mean square (`--error`; docs/fitting.md compares the measures); where a value on a
     bound is not the optimum (step 4), fits again from the better point;
  4. checks each unknown left on a bound: the fit's objective with it moved inward by 5 % of
     its range is worse (the optimum lies on the bound), better (the fit had stalled against
     the bound: step 3 starts again from there, at most MAX_RESTARTS times) or equal (undetermined: the images do not depend on it; a scalar goes back to its start);
  5. checks the fit without refitting: renders front, back and front+back lighting with the
     fitted BYSDF and compares with the explicit-fiber references and with explicit-ply renders
     of the fitted material: mean squared error and FLIP (PyPI flip-evaluator, LDR-FLIP on the
     clamped sRGB images), writes those numbers into the preset's provenance and draws
     docs/images/preset_<name>.png (fiber | ply | BYSDF per lighting).

    PYTHONPATH=build python3 scripts/make_presets.py [--purl build/purl] [--only cotton,wool] [--work DIR]
                                                     [--error linear|relative|srgb]

Needs purlcore (PYTHONPATH) and `pip install flip-evaluator`. About 5-10 minutes per preset on
two busy cores (the fit's progress and an estimate of the time left are shown).
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
IMAGES = REPO / "docs" / "images"
# Preset name -> (fiber BCSDF preset, plies). Wool: Khungurn's gabardine is a wool twill; its
# fibers on a 4-ply yarn, as knitting wool is usually plied (issue 28's knits need one).
SOURCES_OF = {"cotton": ("cotton", 3), "silk": ("silk", 3), "polyester": ("polyester", 3),
              "fleece": ("fleece", 3), "gabardine": ("gabardine", 3), "wool": ("gabardine", 4)}
NAMES = tuple(SOURCES_OF)

FRONT_LIGHT = {"type": "area", "size": 0.6, "position": [-0.6, -1.4, 1.0], "look_at": [0, 0, 0],
               "power": 60, "color": [1.0, 0.96, 0.9]}
BACK_LIGHT = {"type": "area", "shape": "DISK", "size": 0.5, "position": [0.2, 1.5, 1.0], "look_at": [0, 0, 0],
              "power": 60, "color": [1.0, 0.96, 0.9]}
LIGHTINGS = {"front": [FRONT_LIGHT], "back": [BACK_LIGHT], "both": [FRONT_LIGHT, BACK_LIGHT]}

WIDTH, HEIGHT = 96, 48
REFERENCE_SPP, REFERENCE_SEED = 256, 1  # per yarn seed
YARN_SEEDS = 8           # fiber placements averaged into each reference
LONE_SEED, LONE_SPP = YARN_SEEDS + 1, 1024  # the one yarn compared with their mean (the floor)
CHECK_SPP, CHECK_SEED = 128, 2
FIT_SPP, FIT_SEED, FIT_ITERATIONS, FIT_BLOCK, FIT_ERROR = 8, 7, 20, 2, "relative"
# What the Blender preset menu shows (addon/presets.py): a readable name and one line in an
# artist's words; the fit's own record is in "provenance". Names not listed keep the label and
# description their file already has.
DISPLAY = {
    "cotton": ("Cotton (white)", "Undyed cotton: white, soft and matte; light shines through thin yarns"),
    "silk": ("Silk (dyed red)", "Dyed silk: red where lit from the front, pale where light passes through"),
    "polyester": ("Polyester (purple)", "Dyed polyester: saturated purple with a bright white sheen"),
    "fleece": ("Fleece (blue)", "Blue polyester fleece: very translucent, glows blue when back-lit"),
    "gabardine": ("Gabardine (red)", "Red gabardine: deep red, translucent, soft sheen"),
    "wool": ("Wool (knit)", "Knitting wool: fuzzy, matte, with the soft sheen of wool fibers"),
}
FIT_PARAMS = "axS,ayS,axB,ayB,sigma_t,sigma_tS,alpha_x,alpha_y,alpha_t"
BOUND_STEP = 0.05  # of an unknown's range: how far inward a value on a bound is tried
MAX_RESTARTS = 3  # fits started again from a better point beside a bound


def ply_layout(count):
    """Plies touching their neighbours and the yarn surface (as scenes/fig7/make_scenes.py)."""
    s = np.sin(np.pi / count)
    radius = s / (1.0 + s)
    return {"ply_count": count, "ply_radius": round(float(radius), 6), "ply_distance": round(float(1 - radius), 6)}


def source_scene(name, lighting):
    """The Fig. 7 yarn; the fit starts from neutral grey body albedos."""
    fiber, plies = SOURCES_OF[name]
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
                "yarn": dict({"preset": "prototype"}, **ply_layout(plies)),
                "fiber": {"preset": fiber},
            },
        }],
    }


def render(core, scene, base_dir, model, spp, seed, exr=None):
    """Linear RGB (H, W, 3) of the Combined pass; also written to `exr` when given."""
    job = core.RenderJob(scene, None, str(base_dir), model)
    job.start(spp=spp, seed=seed)
    job.wait()
    rgb = np.asarray(job.passes()["Combined"])[..., :3].astype(np.float32)
    if exr:
        core.write_image(str(exr), rgb)
    return rgb


def reference_file(work, name, lighting):
    return work / f"{name}_{lighting}_fiber_{YARN_SEEDS}x{REFERENCE_SPP}.exr"


def fiber_reference(core, scene, exr, seeds=range(1, YARN_SEEDS + 1), spp=REFERENCE_SPP):
    """Mean explicit-fiber render over yarns with the given fiber-placement seeds (cached in `exr`)."""
    if exr.exists():
        return core.read_image(str(exr))
    total = 0
    for yarn_seed in seeds:
        scene["yarns"][0]["material"]["yarn"]["seed"] = yarn_seed
        total = total + render(core, scene, SOURCES, "fiber", spp, REFERENCE_SEED + yarn_seed)
    mean = (total / len(seeds)).astype(np.float32)
    core.write_image(str(exr), mean)
    return mean


def srgb(linear):
    c = np.clip(linear, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055).astype(np.float32)


def flip(reference, test):
    import flip_evaluator
    _, mean, _ = flip_evaluator.evaluate(srgb(reference), srgb(test), "LDR", inputsRGB=True, applyMagma=False)
    return float(mean)


def mse(a, b):
    return float(np.mean((a.astype(np.float64) - b.astype(np.float64)) ** 2))


def set_display_fields(preset, name, old):
    """label, description and source: from DISPLAY, else kept from `old` (the file being replaced)."""
    label, description = DISPLAY.get(name, (old.get("label", name.title()), old.get("description", "")))
    preset["label"] = label
    preset["description"] = description
    fiber, plies = SOURCES_OF[name]
    preset["source"] = (f"BYSDF fitted with purl fit to explicit-fiber renders (front- and back-lit) of a {plies}-ply "
                        f"yarn with the '{fiber}' fiber parameters of Khungurn et al. 2015; scripts/make_presets.py")


def block_mse(a, b, block=FIT_BLOCK):
    """The fit's objective for one target: MSE of block x block means, as FIT_ERROR says (purl fit --error)."""
    h, w = (a.shape[0] // block) * block, (a.shape[1] // block) * block
    def means(x):
        m = x[:h, :w].astype(np.float64).reshape(h // block, block, w // block, block, 3).mean(axis=(1, 3))
        return srgb(m) if FIT_ERROR == "srgb" else m
    error = float(np.mean((means(a) - means(b)) ** 2))
    return error / float(np.mean(means(b) ** 2)) if FIT_ERROR == "relative" else error


ALBEDOS = ("specular_reflection_albedo", "specular_transmission_albedo", "body_reflection_albedo",
           "body_transmission_albedo")


def with_lobe_energy(material, lobe, channel, value):
    """`material` with one channel of one lobe's effective albedo (axS, ayS, axB, ayB: lobe 0-3) set to
    `value`, the rest of the lobe energies kept: the same mapping as purl fit's (fit_params.cpp,
    set_lobe_energies; body_reflection_fresnel 0)."""
    m = json.loads(json.dumps(material))
    body, r0 = m["body_share"], m["body_reflection_share"]
    shares = (1 - body, 1 - body, r0 * body, (1 - r0) * body)
    energies = [np.clip(np.array(m[a], dtype=np.float64) * share, 0, 1) for a, share in zip(ALBEDOS, shares)]
    energies[lobe][channel] = np.clip(value, 0, 1)
    spec = max(energies[0].max(), energies[1].max())
    body_x, body_y = energies[2].max(), energies[3].max()
    total = spec + body_x + body_y
    if total > 1:  # the model cannot give more than all its energy
        energies = [e / total for e in energies]
        body_x, body_y = body_x / total, body_y / total
    m["body_share"] = float(min(max(body_x + body_y, 1e-6), 1.0))
    if body_x + body_y > 0:
        m["body_reflection_share"] = float(body_x / (body_x + body_y))
    spec_share = max(1 - m["body_share"], 1e-6)
    for a, e, lobe_share in zip(ALBEDOS, energies, (spec_share, spec_share, body_x, body_y)):
        albedo = e / lobe_share if lobe_share > 0 else np.zeros(3)
        m[a] = [float(v) for v in np.minimum(albedo, 1.0)]
    return m


def fitted_unknowns_on_bounds(core, name, preset, scene_paths, references):
    """For each fitted unknown on a bound: the objective there and with it moved inward; and the best
    moved material when one is better than the fit's (else None)."""
    tables = {p["name"]: p for p in core.material_parameters("bysdf")}
    lobes = {"axS": 0, "ayS": 1, "axB": 2, "ayB": 3}
    checks = {}
    material = preset["material"]

    def objective(m):
        total = 0.0
        for lighting in ("front", "back"):
            scene = json.loads(scene_paths[lighting].read_text())
            scene["yarns"][0]["material"] = m
            total += block_mse(render(core, scene, SOURCES, "bysdf", FIT_SPP, FIT_SEED), references[lighting]) / 2
        return total
    base, better, best = None, None, None
    for label, values in preset["provenance"]["parameters"].items():
        key, _, channel = label.partition("[")
        value = values["fitted"]
        if key in lobes:
            lo, hi = 0.0, 1.0
        else:
            lo, hi = tables[key]["min"], tables[key]["max"]
            if tables[key]["unit"] == "1/R":
                lo = max(lo, 0.01)
        on_low, on_high = value <= lo + 1e-6 * (hi - lo), value >= hi - 1e-6 * (hi - lo)
        if not (on_low or on_high):
            continue
        if base is None:
            base = objective(material)
        moved = json.loads(json.dumps(material))
        step = BOUND_STEP * (hi - lo) * (1 if on_low else -1)
        if key in lobes:  # move the lobe energy itself, as the fit sets it (B, r0 and albedos follow)
            moved = with_lobe_energy(moved, lobes[key], int(channel.rstrip("]")), value + step)
        elif key.startswith("sigma_t"):  # logarithmic: 5 % of the log range
            moved[key] = float(np.exp(np.log(max(value, lo)) + BOUND_STEP * np.log(hi / lo) * (1 if on_low else -1)))
        else:
            moved[key] = value + step
        inward = objective(moved)
        flat = abs(inward - base) <= 1e-9 * base
        verdict = "undetermined" if flat else ("optimum on the bound" if inward > base else "not the optimum")
        checks[label] = {"value": value, "objective": base, "objective_moved_inward": inward, "verdict": verdict}
        if inward < base and (best is None or inward < best):
            better, best = moved, inward
        if flat and key not in lobes:
            # The images do not depend on it (e.g. sigma_t_body once ayB is 0): keep its start.
            material[key] = values["start"]
            checks[label]["set_back_to_start"] = values["start"]
        print(f"  {name}: {label} = {value:.4g} on its bound; objective {base:.5g}, moved inward {inward:.5g}"
              f" ({verdict})", flush=True)
    return checks, better


def contact_sheet(name, images):
    """fiber | ply | BYSDF, one row per lighting."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(3, 3, figsize=(7.2, 2.2), dpi=110)
    for r, lighting in enumerate(LIGHTINGS):
        for c, model in enumerate(("fiber", "ply", "bysdf")):
            ax = axes[r][c]
            ax.imshow(srgb(images[lighting][model]), interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            if r == 0:
                ax.set_title({"fiber": "explicit fibers (target)", "ply": "explicit plies, fitted material",
                              "bysdf": "BYSDF, fitted"}[model], fontsize=8)
            if c == 0:
                ax.set_ylabel(lighting, fontsize=8)
    fig.suptitle(f"preset '{name}'", fontsize=9)
    fig.tight_layout(pad=0.3)
    out = IMAGES / f"preset_{name}.png"
    fig.savefig(out)
    plt.close(fig)
    return out


def make_preset(core, purl, name, work):
    scene_paths = {}
    for lighting in LIGHTINGS:
        path = SOURCES / f"{name}_{lighting}.json"
        path.write_text(json.dumps(source_scene(name, lighting), indent=2) + "\n")
        scene_paths[lighting] = path
    started = time.time()
    fiber, lone = {}, {}
    for lighting, path in scene_paths.items():
        fiber[lighting] = fiber_reference(core, json.loads(path.read_text()), reference_file(work, name, lighting))
        lone[lighting] = fiber_reference(core, json.loads(path.read_text()), work / f"{name}_{lighting}_seed{LONE_SEED}x{LONE_SPP}.exr",
                                         seeds=[LONE_SEED], spp=LONE_SPP)
    reference_seconds = time.time() - started
    print(f"{name}: explicit-fiber references in {reference_seconds:.1f} s", flush=True)

    output = PRESETS / f"{name}.json"
    previous = json.loads(output.read_text()) if output.exists() else {}  # `purl fit` replaces it
    fit_scenes, restarts = scene_paths, 0
    while True:
        command = [str(purl), "fit", str(fit_scenes["front"]), str(fit_scenes["back"]),
                   "--target", str(reference_file(work, name, "front")),
                   "--target", str(reference_file(work, name, "back")),
                   "--params", FIT_PARAMS, "--spp", str(FIT_SPP), "--seed", str(FIT_SEED),
                   "--iterations", str(FIT_ITERATIONS), "--block", str(FIT_BLOCK), "--error", FIT_ERROR,
                   "--name", name, "-o", str(output)]
        subprocess.run(command, check=True)
        preset = json.loads(output.read_text())
        bounds, better = fitted_unknowns_on_bounds(core, name, preset, scene_paths, fiber)
        if better is None or restarts == MAX_RESTARTS:
            break
        # A value on a bound that is not the optimum: the fit stalled against the box. Fit again
        # from the better point found beside it.
        restarts += 1
        print(f"  {name}: fitting again from the better point inside the bounds ({restarts}/{MAX_RESTARTS})")
        fit_scenes = {}
        for lighting in ("front", "back"):
            scene = json.loads(scene_paths[lighting].read_text())
            scene["yarns"][0]["material"] = better
            scene["yarns"][0]["bcc"] = str((SOURCES / scene["yarns"][0]["bcc"]).resolve())
            fit_scenes[lighting] = work / f"{name}_{lighting}_restart.json"
            fit_scenes[lighting].write_text(json.dumps(scene, indent=2))

    check = {"spp": CHECK_SPP, "seed": CHECK_SEED, "mse_vs_fiber": {}, "flip_vs_fiber": {}, "flip_vs_ply": {},
             "flip_ply_vs_fiber": {}, "flip_one_yarn_vs_fiber": {}, "mean_fiber": {}, "mean_bysdf": {}}
    images = {}
    for lighting, path in scene_paths.items():
        scene = json.loads(path.read_text())
        scene["yarns"][0]["material"] = preset["material"]
        fitted = render(core, scene, SOURCES, "bysdf", CHECK_SPP, CHECK_SEED)
        ply = render(core, scene, SOURCES, "ply", CHECK_SPP, CHECK_SEED)
        images[lighting] = {"fiber": fiber[lighting], "ply": ply, "bysdf": fitted}
        check["mse_vs_fiber"][lighting] = mse(fitted, fiber[lighting])
        check["flip_vs_fiber"][lighting] = flip(fiber[lighting], fitted)
        check["flip_vs_ply"][lighting] = flip(ply, fitted)
        check["flip_ply_vs_fiber"][lighting] = flip(fiber[lighting], ply)
        check["flip_one_yarn_vs_fiber"][lighting] = flip(fiber[lighting], lone[lighting])
        check["mean_fiber"][lighting] = [float(v) for v in fiber[lighting].reshape(-1, 3).mean(axis=0)]
        check["mean_bysdf"][lighting] = [float(v) for v in fitted.reshape(-1, 3).mean(axis=0)]
    sheet = contact_sheet(name, images)

    # Provenance with repository-relative paths (the references are regenerated, not kept).
    provenance = preset["provenance"]
    for target, lighting in zip(provenance["targets"], ("front", "back")):
        target["scene"] = f"presets/sources/{name}_{lighting}.json"
        target["image"] = (f"mean of {YARN_SEEDS} explicit-fiber renders of {target['scene']} with yarn seeds "
                           f"1-{YARN_SEEDS} (--model fiber, {REFERENCE_SPP} spp each)")
    fiber_name, plies = SOURCES_OF[name]
    fiber_parameters = {p["name"]: p["default"] for p in core.material_parameters("fiber")}
    fiber_parameters.update(preset["material"].get("fiber", {}))
    provenance["reference"] = {
        "model": "fiber",
        "fiber_bcsdf": f"{fiber_name} (Khungurn et al. 2015 fit, native fiber preset)",
        "fiber_parameters": fiber_parameters,
        "geometry": f"scenes/fig7/single_yarn.bcc, {plies} plies (prototype yarn with the Fig. 7 ply layout), "
                    f"{WIDTH} x {HEIGHT} px",
        "spp": REFERENCE_SPP, "seed": REFERENCE_SEED, "yarn_seeds": list(range(1, YARN_SEEDS + 1)),
        "floor": f"flip_one_yarn_vs_fiber: one more yarn (seed {LONE_SEED}, {LONE_SPP} spp) against that mean",
    }
    provenance["unknowns_on_bounds"] = bounds
    provenance["restarts"] = restarts
    provenance["check"] = check
    provenance["contact_sheet"] = str(sheet.relative_to(REPO))
    provenance["generated_by"] = "scripts/make_presets.py"
    set_display_fields(preset, name, previous)
    output.write_text(json.dumps(preset, indent=2) + "\n")
    total = time.time() - started
    print(f"{name}: fit {provenance['seconds']:.1f} s, {provenance['iterations']} iterations, "
          f"mse {provenance['final_mse']:.4g}; FLIP vs fiber front/back/both "
          + " / ".join(f"{check['flip_vs_fiber'][k]:.3f}" for k in LIGHTINGS)
          + f"; vs ply " + " / ".join(f"{check['flip_vs_ply'][k]:.3f}" for k in LIGHTINGS)
          + f"; one yarn vs fiber (floor) " + " / ".join(f"{check['flip_one_yarn_vs_fiber'][k]:.3f}" for k in LIGHTINGS)
          + f"; {total:.0f} s in all", flush=True)


def main():
    global FIT_ERROR
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--purl", default=str(REPO / "build" / "purl"), help="the purl binary")
    parser.add_argument("--only", default="", help="comma-separated preset names (default: all)")
    parser.add_argument("--error", default=FIT_ERROR, choices=("linear", "relative", "srgb"),
                        help="what the fit compares (purl fit --error)")
    parser.add_argument("--work", default=str(Path(tempfile.gettempdir()) / "purl_preset_references"),
                        help="folder for the reference renders (kept: a second run reuses them)")
    args = parser.parse_args()
    import purlcore
    FIT_ERROR = args.error
    names = [n for n in args.only.split(",") if n] or list(NAMES)
    for n in names:
        if n not in NAMES:
            sys.exit(f"make_presets.py: unknown preset '{n}' (known: {', '.join(NAMES)})")
    SOURCES.mkdir(parents=True, exist_ok=True)
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    for n in names:
        make_preset(purlcore, args.purl, n, work)


if __name__ == "__main__":
    main()
