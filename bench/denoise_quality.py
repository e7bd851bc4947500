#!/usr/bin/env python3
"""Denoising: relative MSE against the converged image at 4, 16 and 64 spp, with and without
Open Image Denoise, on three scenes, and the time denoising adds (docs/denoising.md).

    PYTHONPATH=build python3 bench/denoise_quality.py [--work /tmp/purl-denoise] [--reference-spp 128]

Each scene is rendered once per sample count with render.denoise on: the "Noisy Image" pass is the
undenoised image and "Combined" the denoised one, from the same samples. The converged image is
two independent halves (bench/metrics.py subtracts its own noise from the error); they are
cached in --work, so a second run only renders the test images. Writes bench/results/denoise.json
and docs/images/denoise.png (16 spp: noisy, denoised, converged).
"""
import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO / "bench"))
from metrics import relative_mse  # noqa: E402

SPPS = (4, 16, 64)
FILTER_GLOSSY = 1.0  # the default; named so the converged halves are shared with bench/fireflies.py
TEST_SEED, REFERENCE_SEEDS = 1, (1001, 1002)


# The shared cloth models sit beside the checkout (../shared/data), or beside the worktrees' parent.
SHARED = next((p for p in (REPO.parent / "shared" / "data", REPO.parent.parent / "shared" / "data") if p.exists()),
              REPO.parent / "shared" / "data")


def scenes():
    """(name, scene dict, base folder): the demo knit, a Fig. 7 yarn lit from both sides, the glove."""
    def load(path, width, height):
        scene = json.loads((REPO / path).read_text())
        scene["film"].update({"width": width, "height": height})
        for yarn in scene["yarns"]:
            if "bcc" in yarn and "shared/data/" in yarn["bcc"]:
                yarn["bcc"] = str(SHARED / yarn["bcc"].split("shared/data/")[1])
        return scene, str((REPO / path).parent)
    return [("demo knit (BYSDF)",) + load("scenes/demo_knit.json", 160, 120),
            ("3-ply yarn, front + back light (BYSDF)",) + load("scenes/fig7/yarn_3ply_both.json", 192, 96),
            ("glove (placeholder)",) + load("scenes/glove.json", 150, 200)]


def render(core, scene, base, spp, seed, denoise, filter_glossy=None):
    if filter_glossy is not None:
        scene = dict(scene, render=dict(scene.get("render", {}), filter_glossy=filter_glossy))
    job = core.RenderJob(scene, None, base)
    job.start(spp=spp, seed=seed, denoise=denoise)
    job.wait()
    if job.error:
        raise RuntimeError(job.error)
    passes = {k: np.asarray(v)[..., :3].astype(np.float64) for k, v in job.passes().items()
              if k in ("Combined", "Noisy Image")}
    return passes, job.stats()


def reference(core, name, scene, base, spp, work, filter_glossy=None):
    """The two converged halves (cached in `work`); filter_glossy None: the scene's setting."""
    halves = []
    tag = "" if filter_glossy is None else "_fg{:g}".format(filter_glossy)
    for seed in REFERENCE_SEEDS:
        path = work / "{}_{}_{}{}.npy".format(name.split(" (")[0].replace(" ", "_").replace(",", ""), spp, seed, tag)
        if not path.exists():
            started = time.time()
            passes, _ = render(core, scene, base, spp, seed, False, filter_glossy)
            np.save(path, passes["Combined"])
            print("  reference half, seed {}: {:.0f} s".format(seed, time.time() - started), flush=True)
        halves.append(np.load(path))
    return halves


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--work", default="/tmp/purl-denoise", help="cache of the converged halves")
    parser.add_argument("--reference-spp", type=int, default=128, help="samples per pixel of each half")
    parser.add_argument("--output", default=str(REPO / "bench" / "results" / "denoise.json"))
    parser.add_argument("--image", default=str(REPO / "docs" / "images" / "denoise.png"))
    parser.add_argument("--timing", action="store_true",
                        help="only time purlcore.denoise on the full-size demo knit (480 x 360), median of 7")
    args = parser.parse_args()
    import purlcore
    status = purlcore.denoiser()
    if not status["available"]:
        sys.exit("denoise_quality.py: " + status["message"])
    if args.timing:
        timing = json.dumps(time_denoise(purlcore), indent=2)
        Path(args.output).with_name("denoise_timing.json").write_text(timing + "\n")
        print(timing)
        return
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    results, strips = [], []
    for name, scene, base in scenes():
        print(name, flush=True)
        ref_a, ref_b = reference(purlcore, name, scene, base, args.reference_spp, work, FILTER_GLOSSY)
        row = {"scene": name, "size": [scene["film"]["width"], scene["film"]["height"]],
               "reference_spp": 2 * args.reference_spp, "points": []}
        for spp in SPPS:
            passes, stats = render(purlcore, scene, base, spp, TEST_SEED, True, FILTER_GLOSSY)
            noisy, denoised = passes["Noisy Image"], passes["Combined"]
            point = {"spp": spp, "relmse": relative_mse(noisy, ref_a, ref_b)[0],
                     "relmse_denoised": relative_mse(denoised, ref_a, ref_b)[0],
                     "render_seconds": stats["render_seconds"], "denoise_seconds": stats["denoise_seconds"]}
            row["points"].append(point)
            print("  {spp:3d} spp: relMSE {relmse:.4g} -> {relmse_denoised:.4g} denoised; render {render_seconds:.1f} s, "
                  "denoise {denoise_seconds:.2f} s".format(**point), flush=True)
            if spp == 16:
                strips.append((name, noisy, denoised, 0.5 * (ref_a + ref_b)))
        results.append(row)
    Path(args.output).write_text(json.dumps({"load": os.getloadavg(), "scenes": results}, indent=2) + "\n")
    draw(strips, args.image)
    print(table(results))


def time_denoise(core, repeats=7):
    """Seconds purlcore.denoise takes on a 480 x 360 image, with and without prefiltered guides,
    and the single-threaded render time of one sample per pixel of the same image for scale."""
    scene = json.loads((REPO / "scenes" / "demo_knit.json").read_text())
    job = core.RenderJob(scene, None, str(REPO / "scenes"))
    job.start(spp=1, seed=1)
    job.wait()
    passes = job.passes()
    result = {"size": [scene["film"]["width"], scene["film"]["height"]], "load": os.getloadavg(),
              "render_seconds_1spp": job.stats()["render_seconds"]}
    for prefilter in (True, False):
        times = []
        for _ in range(repeats):
            started = time.perf_counter()
            core.denoise(passes, prefilter_guides=prefilter)
            times.append(time.perf_counter() - started)
        result["prefilter" if prefilter else "no_prefilter"] = {"median": float(np.median(times)),
                                                                "min": float(min(times))}
    return result


def table(results):
    lines = ["| scene | spp | relMSE | relMSE denoised | ratio | render s | denoise s |",
             "|---|---|---|---|---|---|---|"]
    for row in results:
        for p in row["points"]:
            lines.append("| {} | {} | {:.4f} | {:.4f} | {:.1f}x | {:.1f} | {:.2f} |".format(
                row["scene"], p["spp"], p["relmse"], p["relmse_denoised"], p["relmse"] / p["relmse_denoised"],
                p["render_seconds"], p["denoise_seconds"]))
    return "\n".join(lines)


def draw(strips, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from metrics import srgb
    fig, axes = plt.subplots(len(strips), 3, figsize=(12, 3.4 * len(strips)))
    for row, (name, *images) in zip(axes, strips):
        for ax, image, title in zip(row, images, ("16 spp", "16 spp, denoised", "converged")):
            ax.imshow(srgb(image))
            ax.set_title("{}: {}".format(name, title), fontsize=9)
            ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=80)


if __name__ == "__main__":
    main()
