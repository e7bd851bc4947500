"""Cycles + Purl OSL shader vs the native core on the Fig. 7 single-yarn scenes.

Renders each scene (1, 3, 6 plies x front, back, both lights) at the scenes' own size with both
renderers from the same centre-line, light and camera, writes the images as .npy, and prints
render times. Run with the PyPI bpy (OSL on):

    PURL_BUILD_DIR=<build dir with purlcore> /opt/purl-bpy/bin/python bench/osl_compare.py OUT [SPP]

then the image metrics (RMSE, mean FLIP) with a Python that has flip-evaluator:

    python bench/osl_compare.py --metrics OUT
"""
import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
SCENES = [(p, l) for p in (1, 3, 6) for l in ("front", "back", "both")]


def render_all(out, spp):
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
        for kind in ("objects", "hair_curves", "lights", "cameras", "materials", "texts", "images"):
            collection = getattr(bpy.data, kind)
            for block in list(collection):
                collection.remove(block)
        scene = bpy.context.scene
        json_scene = osl_scenes.load_scene(plies, lighting)
        _, curves = osl_scenes.build_blender_scene(scene, core, json_scene, samples=spp)
        scene.render.threads_mode = "FIXED"
        scene.render.threads = 2
        name = "{}ply_{}".format(plies, lighting)
        start = time.perf_counter()
        cycles = osl_scenes.render_cycles(scene, os.path.join(out, name + "_cycles.exr"))
        cycles_time = time.perf_counter() - start
        native_scene, arrays = osl_scenes.native_scene(json_scene, curves, spp)
        start = time.perf_counter()
        passes = core.render(native_scene, arrays, threads=2)
        native_time = time.perf_counter() - start
        np.save(os.path.join(out, name + "_cycles.npy"), cycles[..., :3])
        np.save(os.path.join(out, name + "_native.npy"), np.asarray(passes["Combined"])[..., :3])
        times[name] = {"cycles_s": cycles_time, "native_s": native_time, "spp": spp}
        print("{}: Cycles+OSL {:.2f} s, native {:.2f} s ({} spp, 2 threads)".format(name, cycles_time, native_time,
                                                                                     spp), flush=True)
    with open(os.path.join(out, "times.json"), "w") as f:
        json.dump(times, f, indent=1)


def metrics(out):
    import flip_evaluator as flip
    import numpy as np
    rows = []
    for plies, lighting in SCENES:
        name = "{}ply_{}".format(plies, lighting)
        cycles = np.load(os.path.join(out, name + "_cycles.npy")).astype(np.float32)
        native_img = np.load(os.path.join(out, name + "_native.npy")).astype(np.float32)
        rmse = float(np.sqrt(np.mean((cycles - native_img) ** 2)))
        peak = float(native_img.max())
        # HDR-FLIP on the linear images (reference = native).
        _, mean_flip, _ = flip.evaluate(native_img, cycles, "HDR")
        # The same at a quarter of the pixels (2 x 2 box): how much of the difference is fiber-scale detail.
        def half(img):
            h, w = img.shape[0] // 2 * 2, img.shape[1] // 2 * 2
            return img[:h, :w].reshape(h // 2, 2, w // 2, 2, 3).mean(axis=(1, 3)).astype(np.float32)
        _, mean_flip_half, _ = flip.evaluate(half(native_img), half(cycles), "HDR")
        ratio = float(cycles.mean() / max(native_img.mean(), 1e-12))
        rows.append((name, rmse, peak, float(mean_flip), float(mean_flip_half), ratio))
    print("| scene | RMSE | native max | mean FLIP (HDR) | FLIP at 1/2 res | mean Cycles / mean native |")
    print("|---|---|---|---|---|---|")
    for name, rmse, peak, f, fh, ratio in rows:
        print("| {} | {:.4f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} |".format(name, rmse, peak, f, fh, ratio))
    print("| mean | {:.4f} | | {:.3f} | {:.3f} | |".format(*[np.mean([r[i] for r in rows]) for i in (1, 3, 4)]))


if __name__ == "__main__":
    args = [a for a in sys.argv[1:]]
    if "--" in args:
        args = args[args.index("--") + 1:]
    if args and args[0] == "--metrics":
        metrics(args[1])
    else:
        render_all(args[0], int(args[1]) if len(args) > 1 else 64)
