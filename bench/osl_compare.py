"""Cycles + Purl OSL shader vs the native core on the Fig. 7 single-yarn scenes.

Renders each scene (1, 3, 6 plies x front, back, both lights) at the scenes' own size with both
renderers from the same centre-line, light and camera, writes the images as .npy, and prints
render times. Run with the PyPI bpy (OSL on):

    PURL_BUILD_DIR=<build dir with purlcore> /opt/purl-bpy/bin/python bench/osl_compare.py OUT [SPP]
        [--scenes 3ply_back,...] [--material '{"body_share": 0}'] [--reference 1024]

(--material overrides material parameters in both renderers, e.g. to isolate one lobe, or
FIBER_PATTERN for the fiber-pattern comparison; --reference also renders SPP / 4 and a reference
at that count, for the time at equal quality. Per scene also the shader's ply outputs at 1 spp
and the native PlyIndex / PlyUV passes, for the ply metrics.)

then the image and ply metrics (RMSE, mean FLIP, same ply, u_ply / v_ply differences) with a
Python that has flip-evaluator:

    python bench/osl_compare.py --metrics OUT
"""
import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
SCENES = [(p, l) for p in (1, 3, 6) for l in ("front", "back", "both")]
# --material for the fiber-pattern comparison: Lambert body reflection with fiber shadowing only.
FIBER_PATTERN = {"body_share": 1, "body_reflection_share": 1, "body_reflection_fresnel": 0,
                 "ply_shadow_floor": 1, "fiber_shadow_floor": 0}
# Shader outputs rendered at 1 spp (osl_scenes.render_shader_outputs), compared with the native
# PlyIndex and PlyUV passes (sample 0's first ply hit).
SHADER_OUTPUTS = ["PlyIndex", "PlyU", "PlyV"]


def render_all(out, spp, names=None, material=None, reference_spp=0):
    """Renders the scenes at `spp` (the images compared); with reference_spp also at spp / 4 and at
    reference_spp, for the time at equal quality (relMSE against each renderer's own reference)."""
    import tempfile
    import bpy
    import addon_utils
    import numpy as np
    sys.path.insert(0, os.path.join(REPO, "tests", "blender"))
    link_dir = tempfile.mkdtemp(prefix="purl_addon_")
    os.symlink(os.path.join(REPO, "addon"), os.path.join(link_dir, "purl"))
    sys.path.insert(0, link_dir)
    os.environ["PURL_ADDON_PACKAGE"] = "purl"
    addon_utils.enable("purl", default_set=True)
    import osl_scenes
    from purl import native
    core = native.purlcore()
    if core is None:
        sys.exit("purlcore did not load: " + native.load_error())
    os.makedirs(out, exist_ok=True)
    times = {}
    for plies, lighting in SCENES:
        name = "{}ply_{}".format(plies, lighting)
        if names and name not in names:
            continue
        for kind in ("objects", "hair_curves", "lights", "cameras", "materials", "texts", "images"):
            collection = getattr(bpy.data, kind)
            for block in list(collection):
                collection.remove(block)
        scene = bpy.context.scene
        json_scene = osl_scenes.load_scene(plies, lighting)
        json_scene["yarns"][0]["material"].update(material or {})
        yarn_object, curves = osl_scenes.build_blender_scene(scene, core, json_scene, samples=spp)
        scene.render.threads_mode = "FIXED"
        scene.render.threads = 2
        times[name] = {}
        for count, suffix in [(spp, "")] + ([(max(spp // 4, 1), "_low"), (reference_spp, "_ref")] if
                                            reference_spp else []):
            scene.cycles.samples = count
            start = time.perf_counter()
            cycles = osl_scenes.render_cycles(scene, os.path.join(out, name + "_cycles.exr"))
            cycles_time = time.perf_counter() - start
            native_scene, arrays = osl_scenes.native_scene(json_scene, curves, count)
            start = time.perf_counter()
            passes = core.render(native_scene, arrays, threads=2)
            native_time = time.perf_counter() - start
            np.save(os.path.join(out, name + "_cycles" + suffix + ".npy"), cycles["Combined"][..., :3])
            np.save(os.path.join(out, name + "_native" + suffix + ".npy"), np.asarray(passes["Combined"])[..., :3])
            if not suffix:  # where each renderer finds the plies, for ply_metrics
                shader = {}
                for k in range(0, len(SHADER_OUTPUTS), 3):
                    outputs = SHADER_OUTPUTS[k:k + 3]
                    values, alpha = osl_scenes.render_shader_outputs(
                        scene, yarn_object, outputs, os.path.join(out, name + "_outputs.exr"), offset=10.0)
                    shader.update({"cycles_" + o: values[..., i] for i, o in enumerate(outputs)})
                np.savez(os.path.join(out, name + "_plies.npz"), cycles_alpha=alpha,
                         native_ply=np.asarray(passes["PlyIndex"])[..., 0], native_uv=np.asarray(passes["PlyUV"]),
                         **shader)
            times[name][suffix or "main"] = {"cycles_s": cycles_time, "native_s": native_time, "spp": count}
            print("{}: Cycles+OSL {:.2f} s, native {:.2f} s ({} spp, 2 threads)".format(
                name, cycles_time, native_time, count), flush=True)
    with open(os.path.join(out, "times.json"), "w") as f:
        json.dump(times, f, indent=1)


def equal_quality_times(out, name):
    """Equal quality: the native render's relMSE at the main spp against its own reference. Returns
    (relMSE Cycles, relMSE native, Cycles spp and seconds for the native relMSE, native seconds),
    with relMSE taken as c / spp and time as a + b spp (from the main and the low render)."""
    import numpy as np
    path = os.path.join(out, "times.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        times = json.load(f).get(name, {})
    if "_ref" not in times or "_low" not in times:
        return None
    main, low = times["main"], times["_low"]
    rel_mse, cost = {}, {}
    for renderer in ("cycles", "native"):
        ref = np.load(os.path.join(out, "{}_{}_ref.npy".format(name, renderer))).astype(np.float64)
        img = np.load(os.path.join(out, "{}_{}.npy".format(name, renderer))).astype(np.float64)
        rel_mse[renderer] = float(np.mean((img - ref) ** 2 / (ref ** 2 + 1e-2)))
        per_spp = max((main[renderer + "_s"] - low[renderer + "_s"]) / (main["spp"] - low["spp"]), 1e-9)
        cost[renderer] = (max(main[renderer + "_s"] - per_spp * main["spp"], 0.0), per_spp)
    spp = main["spp"] * rel_mse["cycles"] / max(rel_mse["native"], 1e-12)
    return (rel_mse["cycles"], rel_mse["native"], spp, cost["cycles"][0] + cost["cycles"][1] * spp,
            main["native_s"])


def srgb(img):
    """The Standard view transform: clip to [0, 1], sRGB encoding (what a PNG of the render shows)."""
    import numpy as np
    c = np.clip(img, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055).astype(np.float32)


def ply_metrics(out, name):
    """Pixels whose 1-spp Cycles shading point and native sample 0 both lie on a ply: the share on
    the same ply, there the median |u_ply difference| (rad, wrapped) and |v_ply difference| (mm),
    and the correlation of the two images' luminance (the fiber pattern, when rendered with
    --material FIBER_PATTERN). None without the ply outputs."""
    import numpy as np
    path = os.path.join(out, name + "_plies.npz")
    if not os.path.exists(path):
        return None
    z = np.load(path)
    cycles_ply = np.round(z["cycles_PlyIndex"])
    both = (z["cycles_alpha"] > 0.999) & (cycles_ply >= 0) & (z["native_ply"] >= 0)
    same = both & (cycles_ply == z["native_ply"])
    du = np.angle(np.exp(1j * (z["cycles_PlyU"] - z["native_uv"][..., 0])))
    dv = z["cycles_PlyV"] - z["native_uv"][..., 1]
    lum = np.array([0.2126, 0.7152, 0.0722])
    cycles = np.load(os.path.join(out, name + "_cycles.npy")) @ lum
    native_img = np.load(os.path.join(out, name + "_native.npy")) @ lum
    corr = float(np.corrcoef(cycles[same], native_img[same])[0, 1])
    return (float(same.sum() / max(both.sum(), 1)), float(np.median(np.abs(du[same]))),
            1000 * float(np.median(np.abs(dv[same]))), corr)


def metrics(out):
    import flip_evaluator as flip
    import numpy as np
    rows = []
    for plies, lighting in SCENES:
        name = "{}ply_{}".format(plies, lighting)
        if not os.path.exists(os.path.join(out, name + "_cycles.npy")):
            continue
        cycles = np.load(os.path.join(out, name + "_cycles.npy")).astype(np.float32)
        native_img = np.load(os.path.join(out, name + "_native.npy")).astype(np.float32)
        rmse = float(np.sqrt(np.mean((cycles - native_img) ** 2)))
        # HDR-FLIP on the linear images (reference = native; FLIP picks the exposures from it);
        # LDR-FLIP on both through the same Standard view transform.
        _, mean_flip, _ = flip.evaluate(native_img, cycles, "HDR")
        _, mean_flip_ldr, _ = flip.evaluate(srgb(native_img), srgb(cycles), "LDR")
        ratio = float(cycles.mean() / max(native_img.mean(), 1e-12))
        quality = equal_quality_times(out, name)
        rows.append((name, float(mean_flip), float(mean_flip_ldr), rmse, ratio, quality, ply_metrics(out, name)))
    print("| scene | mean FLIP (HDR) | mean FLIP (LDR, sRGB) | RMSE | mean Cycles / mean native |"
          " relMSE Cycles / native | Cycles spp, s for the native relMSE | native s |"
          " same ply | median abs du_ply (rad) | median abs dv_ply (mm) | luminance correlation on the same ply |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, f, fl, rmse, ratio, q, plies in rows:
        extra = "{:.1e} / {:.1e} | {:.0f}, {:.1f} | {:.1f}".format(*q) if q else "- | - | -"
        extra += " | {:.4f} | {:.3f} | {:.2f} | {:.3f}".format(*plies) if plies else " | - | - | - | -"
        print("| {} | {:.3f} | {:.3f} | {:.4f} | {:.3f} | {} |".format(name, f, fl, rmse, ratio, extra))
    print("| mean | {:.3f} | {:.3f} | {:.4f} | | | | | | | | |".format(*[np.mean([r[i] for r in rows]) for i in (1, 2, 3)]))


if __name__ == "__main__":
    import argparse
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    if argv and argv[0] == "--metrics":
        metrics(argv[1])
    else:
        parser = argparse.ArgumentParser()
        parser.add_argument("out")
        parser.add_argument("spp", nargs="?", type=int, default=64)
        parser.add_argument("--scenes", help="comma-separated names, e.g. 3ply_back")
        parser.add_argument("--material", default="{}", help="JSON material overrides for both renderers")
        parser.add_argument("--reference", type=int, default=0, help="reference spp for the time at equal quality")
        a = parser.parse_args(argv)
        material = FIBER_PATTERN if a.material == "FIBER_PATTERN" else json.loads(a.material)
        render_all(a.out, a.spp, a.scenes.split(",") if a.scenes else None, material, a.reference)
