#!/usr/bin/env python3
"""Writes the fuzzers' seed corpora and the small files scenes may refer to (tests/fuzz/data).

BCC seeds are the two shared data files trimmed to a few short curves (headers rewritten to
match), plus one small file per curve type; JSON seeds cover every key of the scene format and
of a yarn preset. Run again after changing the formats; the output is deterministic.
Usage: python3 tests/fuzz/make_seeds.py [shared data dir]
"""
import json
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def bcc_bytes(curve_type, up, curves, info=b""):
    """curves: [(closed, [(x, y, z), ...])] -> a BCC file whose size matches its header."""
    body = b""
    points = 0
    for closed, pts in curves:
        body += struct.pack("<i", -len(pts) if closed else len(pts))
        for p in pts:
            body += struct.pack("<3f", *p)
        points += len(pts)
    header = b"BCC" + bytes([0x44]) + curve_type + bytes([3, up])
    header += struct.pack("<QQ", len(curves), points) + info[:40].ljust(40, b"\0")
    return header + body


def read_bcc(path):
    data = open(path, "rb").read()
    curve_type, up = data[4:6], data[7]
    ncurves, _ = struct.unpack_from("<QQ", data, 8)
    pos, curves = 64, []
    for _ in range(ncurves):
        (n,) = struct.unpack_from("<i", data, pos)
        pos += 4
        pts = [struct.unpack_from("<3f", data, pos + 12 * i) for i in range(abs(n))]
        pos += 12 * abs(n)
        curves.append((n < 0, pts))
    return curve_type, up, curves


def trimmed(path, keep_curves, keep_points):
    curve_type, up, curves = read_bcc(path)
    short = [(closed, pts[:keep_points]) for closed, pts in curves[:keep_curves]]
    return bcc_bytes(curve_type, up, short, b"trimmed from " + os.path.basename(path).encode())


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(path, mode) as f:
        f.write(data)


def wave(n, dy=0.0, scale=1.0):
    return [(scale * 0.1 * i, scale * (dy + 0.02 * (i % 2)), 0.0) for i in range(n)]


def bcc_seeds(shared):
    out = os.path.join(HERE, "corpus", "bcc")
    for name, keep in (("glove.bcc", 2), ("knittubeinit.bcc", 2)):
        src = os.path.join(shared, name)
        if os.path.exists(src):
            write(os.path.join(out, name.replace(".bcc", "_trim.bcc")), trimmed(src, keep, 24))
        else:
            print("make_seeds: no", src, "- skipped", file=sys.stderr)
    write(os.path.join(out, "bs_open_zup.bcc"), bcc_bytes(b"BS", 2, [(False, wave(6))]))
    write(os.path.join(out, "c0_open_closed.bcc"), bcc_bytes(b"C0", 1, [(False, wave(5)), (True, wave(4, 1))]))
    write(os.path.join(out, "pl_open_closed.bcc"), bcc_bytes(b"PL", 2, [(False, wave(3)), (True, wave(3, 1))]))
    write(os.path.join(out, "bz_open_closed.bcc"), bcc_bytes(b"BZ", 2, [(False, wave(7)), (True, wave(6, 1))]))
    write(os.path.join(HERE, "data", "small.bcc"), bcc_bytes(b"BS", 2, [(False, wave(8, 0, 0.01)), (True, wave(5, 1, 0.01))]))
    write(os.path.join(HERE, "data", "small.obj"),
          "# a unit quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1 4/1\nf -1 -2 -3\n")


CAMERA = {"position": [0, -0.2, 0.1], "look_at": [0, 0, 0]}


def scene_seeds():
    out = os.path.join(HERE, "corpus", "scene_json")
    scenes = {
        "minimal": {"camera": CAMERA, "yarns": [{"generate": {"kind": "plain", "warps": 2, "wefts": 2}}]},
        "bcc_placeholder": {
            "version": 1,
            "camera": {"matrix_world": [1, 0, 0, 0, 0, 0, -1, -0.3, 0, 1, 0, 0, 0, 0, 0, 1], "lens": 35,
                       "sensor_fit": "VERTICAL", "sensor_height": 20, "shift_x": 0.1, "clip_start": 0.01,
                       "clip_end": 100},
            "film": {"width": 32, "height": 24, "pixel_aspect_x": 1, "pixel_aspect_y": 2, "transparent": True},
            "render": {"spp": 4, "seed": 7, "max_depth": 3, "threads": 1, "clamp": 10, "model": "bysdf"},
            "world": {"color": [0.1, 0.2, 0.3], "strength": 2, "rotation_z": 1.5},
            "yarns": [{"name": "b", "bcc": "small.bcc", "radius": 0.002, "id": 3,
                       "matrix_world": [2, 0, 0, 0.1, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1],
                       "material": {"model": "placeholder", "color": [0.8, 0.1, 0.1], "roughness": 0.4,
                                    "specular": 0.5}}],
        },
        "lights_meshes": {
            "camera": CAMERA,
            "lights": [
                {"type": "point", "position": [0, 0, 1], "look_at": [0, 0, 0], "power": 100, "radius": 0.1},
                {"type": "spot", "position": [1, 0, 1], "look_at": [0, 0, 0], "spot_size": 0.5, "spot_blend": 0.2,
                 "color": [1, 0.9, 0.8]},
                {"type": "sun", "position": [0, 0, 1], "look_at": [0, 0, 0], "strength": 3, "angle": 0.1},
                {"type": "area", "position": [0, 1, 1], "look_at": [0, 0, 0], "shape": "RECTANGLE", "size": 0.5,
                 "size_y": 0.2, "power": 50},
                {"type": "area", "position": [0, 1, 1], "look_at": [0, 0, 0], "up": [1, 0, 0], "shape": "DISK"},
            ],
            "meshes": [
                {"obj": "small.obj", "color": [0.5, 0.5, 0.5], "holdout": True},
                {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "triangles": [[0, 1, 2]],
                 "matrix_world": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, -0.1, 0, 0, 0, 1]},
                {"arrays": "mesh"},
            ],
        },
        "generate_all": {
            "camera": CAMERA,
            "yarns": [
                {"generate": {"kind": "knit", "radius": 0.0005, "courses": 2, "wales": 2}},
                {"generate": {"kind": "twill", "warps": 3, "wefts": 3, "twill_over": 2, "twill_under": 2,
                              "spacing": 0.003}},
                {"generate": {"kind": "satin", "warps": 5, "wefts": 5}},
                {"arrays": "yarn", "radius_scale": 0.5},
            ],
        },
        "bysdf_material": {
            "camera": CAMERA,
            "render": {"model": "ply"},
            "yarns": [{"generate": {"kind": "plain", "warps": 2, "wefts": 2},
                       "material": {"model": "bysdf", "eta": 1.6, "body_share": 0.4,
                                    "body_reflection_albedo": [0.1, 0.05, 0.02], "ply_color_count": 2,
                                    "ply_color_2": [0.2, 0.4, 0.9],
                                    "yarn": {"preset": "B", "ply_count": 3, "fiber_count": 40,
                                             "map_resolution": 64, "migration_variants": 2}}}],
        },
    }
    for name, scene in scenes.items():
        write(os.path.join(out, name + ".json"), json.dumps(scene, indent=1) + "\n")


def preset_seeds():
    out = os.path.join(HERE, "corpus", "preset")
    presets = {
        "placeholder": {"name": "Red wool", "description": "plain tube", "source": "by eye",
                        "material": {"model": "placeholder", "color": [0.8, 0.2, 0.1]},
                        "blender": {"mode": "AUTO", "color_attribute": ""}},
        "zhao_a": {"name": "Zhao A", "material": {"model": "bysdf", "yarn": {"preset": "A"}}},
        "prototype_full": {
            "name": "Prototype, every field",
            "material": {
                "model": "bysdf", "eta": 1.5, "specular_roughness_along": 0.2, "specular_roughness_across": 0.3,
                "transmission_roughness": 0.9, "specular_reflection_albedo": [1, 1, 1],
                "specular_transmission_albedo": [1, 1, 1], "body_share": 0.5, "body_reflection_share": 0.5,
                "body_reflection_fresnel": 0.0, "body_reflection_albedo": [0.045, 0.015, 0],
                "body_transmission_albedo": [0.27, 0.09, 0], "lommel_seeliger_weight": 1, "sigma_t_specular": 11,
                "sigma_t_body": 0.2, "ply_shadow_floor": 0.6, "fiber_shadow_floor": 0.5, "ply_color_count": 3,
                "ply_color_1": [1, 1, 1], "ply_color_3": [0.5, 0.5, 0.5],
                "yarn": {"preset": "prototype", "ply_count": 3, "ply_radius": 0.45, "ply_distance": 0.5196,
                         "ply_twist": 0.6667, "ply_handedness": 1, "fiber_count": 25, "fiber_radius": 0.1414,
                         "fiber_twist": 0.6667, "fiber_handedness": -1, "migration_rho_min": 0.8,
                         "migration_rho_max": 1, "migration_frequency": 1.5, "density_eps": 0.1,
                         "density_beta": 0.5, "map_resolution": 256, "migration_variants": 4, "seed": 1}}},
        "single_ply": {"name": "one ply", "material": {"yarn": {"ply_count": 1, "ply_distance": 0, "ply_radius": 1}}},
    }
    for name, preset in presets.items():
        write(os.path.join(out, name + ".json"), json.dumps(preset, indent=1) + "\n")


if __name__ == "__main__":
    shared = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "..", "..", "shared", "data")
    bcc_seeds(shared)
    scene_seeds()
    preset_seeds()
