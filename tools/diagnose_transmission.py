#!/usr/bin/env python3
"""Where the BYSDF's back-lit light differs from the explicit plies: lobe by lobe, term by term.

For the Fig. 7 yarn (scenes/fig7, 1, 3 and 6 plies) it renders the implicit BYSDF and the
explicit-ply reference (`ply`, same parameters) under half-space environments instead of the
scene's lights, so that a pixel's value *is* a directional albedo of the yarn seen along that
camera ray, whatever happens inside it (several ply events for the explicit plies, one for the
BYSDF):
  - `back`:  white for directions behind the yarn (y > 0), black in front: transmission T;
  - `front`: white in front, black behind: reflection R.
Averaged over the pixels where every camera ray enters the yarn tube (YarnID pass of a plain tube).

Measured, each for the BYSDF and the plies:
  - pass-through share: every albedo 0, back world: the rays that cross the yarn unscattered;
  - per-lobe energy: only one lobe's albedo on (1), the others 0: R and T (pass share removed);
  - extinction path: body (or specular) transmission only, sigma_t 0 and 1 per R: the effective
    optical path L = -ln(T(1) / T(0)) in yarn radii the light crosses (N_i x chord for the BYSDF);
  - ply shadowing: body reflection only, G_p on (floor 0) or off (floor 1), against the plies' traced shadows;
  - the scene's own material (all lobes) under its front and back lights.

    PYTHONPATH=build python3 tools/diagnose_transmission.py [--spp 64] [--plies 1,3,6] [--ply-crossing 0|1] [-o out.json]

Prints a table per ply count and writes all numbers as JSON. Resumable: finished renders are
cached in --cache (a folder of .npy files keyed by the render's settings).
"""
import argparse
import copy
import hashlib
import json
import struct
import sys
import tempfile
import zlib
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
FIG7 = REPO / "scenes" / "fig7"
LOBES = ("specular_reflection_albedo", "specular_transmission_albedo", "body_reflection_albedo",
         "body_transmission_albedo")
LOBE_NAMES = {"specular_reflection_albedo": "f_x^S", "specular_transmission_albedo": "f_y^S",
              "body_reflection_albedo": "f_x^B", "body_transmission_albedo": "f_y^B"}


def write_png_gray(path, rows):
    """8-bit grey PNG from a 2D uint8 array (the environment masks; 0 and 255 only)."""
    h, w = rows.shape
    raw = b"".join(b"\x00" + rows[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    Path(path).write_bytes(png)


def half_space_worlds(folder):
    """Lat-long masks: u in [0, 0.5) looks toward +y (behind the yarn seen from the camera at -y)."""
    w, h = 256, 128
    back = np.zeros((h, w), np.uint8)
    back[:, : w // 2] = 255
    paths = {"back": folder / "world_back.png", "front": folder / "world_front.png"}
    write_png_gray(paths["back"], back)
    write_png_gray(paths["front"], 255 - back)
    return paths


class Renderer:
    def __init__(self, core, spp, cache):
        self.core, self.spp, self.cache = core, spp, cache
        cache.mkdir(parents=True, exist_ok=True)

    def __call__(self, scene, model, spp=None):
        spp = spp or self.spp
        key = hashlib.sha1(json.dumps([scene, model, spp], sort_keys=True).encode()).hexdigest()[:16]
        path = self.cache / f"{key}.npy"
        if path.exists():
            return np.load(path)
        job = self.core.RenderJob(scene, None, str(FIG7), model)
        job.start(spp=spp, seed=11)
        job.wait()
        passes = job.passes()
        image = np.concatenate([np.asarray(passes["Combined"])[..., :3], np.asarray(passes["YarnID"])],
                               axis=-1).astype(np.float32)
        np.save(path, image)
        return image


PLY_CROSSING = {"value": 1}


def scene_for(plies, light):
    s = json.loads((FIG7 / f"yarn_{plies}ply_{light}.json").read_text())
    s["yarns"][0]["material"]["ply_crossing"] = PLY_CROSSING["value"]
    return s


def with_world(scene, texture):
    s = copy.deepcopy(scene)
    s["lights"] = []
    s["world"] = {"color": [1.0, 1.0, 1.0], "texture": str(texture)}
    s["render"]["max_depth"] = 32  # every event inside the yarn counts toward its albedo
    return s


def with_material(scene, **changes):
    s = copy.deepcopy(scene)
    m = s["yarns"][0]["material"]
    m.update(changes)
    return s


def only_lobe(scene, lobe, **changes):
    zero = {name: [0.0, 0.0, 0.0] for name in LOBES}
    zero[lobe] = [1.0, 1.0, 1.0]
    zero.update(changes)
    return with_material(scene, **zero)


def tube_mask(render, scene):
    s = copy.deepcopy(scene)
    s["yarns"][0]["material"] = {"model": "placeholder", "color": [0.5, 0.5, 0.5]}
    yarn_id = render(s, "bysdf", spp=16)[..., 3]  # 1 where every sample met the tube
    return yarn_id > 0.999


def mean_rgb(image, mask):
    return [float(v) for v in image[mask][:, :3].mean(axis=0)]


def mean(image, mask):
    return float(image[mask][:, :3].mean())


def diagnose(render, plies, worlds):
    base = scene_for(plies, "back")
    mask = tube_mask(render, base)
    out = {"plies": plies, "pixels": int(mask.sum())}
    back, front = with_world(base, worlds["back"]), with_world(base, worlds["front"])
    for model in ("bysdf", "ply"):
        r = {}
        black = {name: [0.0, 0.0, 0.0] for name in LOBES}
        r["pass_through"] = mean(render(with_material(back, **black), model), mask)
        for lobe in LOBES:
            t = mean(render(only_lobe(back, lobe), model), mask) - r["pass_through"]
            rf = mean(render(only_lobe(front, lobe), model), mask)
            r[LOBE_NAMES[lobe]] = {"T": t, "R": rf}
        for lobe, sigma in (("body_transmission_albedo", "sigma_t_body"),
                            ("specular_transmission_albedo", "sigma_t_specular")):
            t0 = mean(render(only_lobe(back, lobe, **{sigma: 0.0}), model), mask) - r["pass_through"]
            t1 = mean(render(only_lobe(back, lobe, **{sigma: 1.0}), model), mask) - r["pass_through"]
            r[f"path_{LOBE_NAMES[lobe]}"] = {"T_sigma0": t0, "T_sigma1": t1,
                                            "L_eff": float(-np.log(max(t1, 1e-9) / max(t0, 1e-9)))}
        for floor in (0.0, 1.0):
            r[f"f_x^B_front_floor{floor:g}"] = mean(
                render(only_lobe(front, "body_reflection_albedo", ply_shadow_floor=floor, fiber_shadow_floor=1.0),
                       model), mask)
        for light in ("front", "back", "both"):
            r[f"scene_{light}"] = mean_rgb(render(scene_for(plies, light), model), np.ones(mask.shape, bool))
        out[model] = r
    return out


def print_table(d):
    b, p = d["bysdf"], d["ply"]
    print(f"\n## {d['plies']} plies ({d['pixels']} tube pixels)")
    print("| quantity | BYSDF | plies | BYSDF / plies |")
    print("|---|---|---|---|")

    def row(name, x, y):
        ratio = x / y if abs(y) > 1e-6 else float("nan")
        print(f"| {name} | {x:.4f} | {y:.4f} | {ratio:.2f} |")
    row("pass-through share (back world, black yarn)", b["pass_through"], p["pass_through"])
    for lobe in LOBE_NAMES.values():
        row(f"{lobe} alone: T (back world, pass removed)", b[lobe]["T"], p[lobe]["T"])
        row(f"{lobe} alone: R (front world)", b[lobe]["R"], p[lobe]["R"])
    for lobe in ("f_y^B", "f_y^S"):
        q, s = b[f"path_{lobe}"], p[f"path_{lobe}"]
        row(f"{lobe}: T at sigma_t 0", q["T_sigma0"], s["T_sigma0"])
        row(f"{lobe}: effective path L (R) = -ln T(1)/T(0)", q["L_eff"], s["L_eff"])
    row("f_x^B front world, G_p on (floor 0)", b["f_x^B_front_floor0"], p["f_x^B_front_floor0"])
    row("f_x^B front world, G_p off (floor 1)", b["f_x^B_front_floor1"], p["f_x^B_front_floor1"])
    for light in ("front", "back", "both"):
        row(f"scene {light}: mean image", float(np.mean(b[f"scene_{light}"])), float(np.mean(p[f"scene_{light}"])))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--plies", default="1,3,6")
    parser.add_argument("--cache", default=str(Path(tempfile.gettempdir()) / "purl_diagnose_cache"))
    parser.add_argument("--ply-crossing", type=int, default=1, help="0: the paper's tau^N_i and G_p; 1: traced")
    parser.add_argument("-o", "--output", default="")
    args = parser.parse_args()
    PLY_CROSSING["value"] = args.ply_crossing
    import purlcore
    render = Renderer(purlcore, args.spp, Path(args.cache))
    worlds = half_space_worlds(Path(args.cache))
    results = []
    for plies in (int(p) for p in args.plies.split(",")):
        d = diagnose(render, plies, worlds)
        print_table(d)
        sys.stdout.flush()
        results.append(d)
    if args.output:
        Path(args.output).write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
