#!/usr/bin/env python3
"""Writes the single-yarn scenes of Khattar et al. 2024, Fig. 7: one gently waving yarn
(single_yarn.bcc, radius 0.1) with 1, 3 or 6 plies, lit from the front, from behind, or both.

    python3 scenes/fig7/make_scenes.py      # rewrites scenes/fig7/yarn_<plies>ply_<light>.json

The back light sits behind the yarn and above the frame, so the camera sees the yarn in
transmission against a dark world, as in the paper's back-lit column."""
import json
import math
from pathlib import Path

HERE = Path(__file__).resolve().parent

FRONT_LIGHT = {"type": "area", "size": 0.6, "position": [-0.6, -1.4, 1.0], "look_at": [0, 0, 0],
               "power": 60, "color": [1.0, 0.96, 0.9]}
BACK_LIGHT = {"type": "area", "shape": "DISK", "size": 0.5, "position": [0.2, 1.5, 1.0], "look_at": [0, 0, 0],
              "power": 60, "color": [1.0, 0.96, 0.9]}
LIGHTINGS = {"front": [FRONT_LIGHT], "back": [BACK_LIGHT], "both": [FRONT_LIGHT, BACK_LIGHT]}


def ply_layout(count):
    """Ply radius and centre distance (yarn radii) for `count` plies touching their
    neighbours and the yarn's surface; one ply fills most of the yarn."""
    if count == 1:
        return {"ply_count": 1, "ply_radius": 0.9, "ply_distance": 0.0}
    s = math.sin(math.pi / count)
    radius = s / (1.0 + s)
    return {"ply_count": count, "ply_radius": round(radius, 6), "ply_distance": round(1.0 - radius, 6)}


def scene(plies, lighting):
    return {
        "version": 1,
        "camera": {"position": [0.0, -1.4, 0.05], "look_at": [0.0, 0.0, 0.0], "lens": 50, "clip_start": 0.01},
        "film": {"width": 192, "height": 96},
        "render": {"spp": 64, "seed": 1, "max_depth": 8},
        "world": {"color": [0.0, 0.0, 0.0]},
        "lights": LIGHTINGS[lighting],
        "yarns": [{
            "name": "yarn", "bcc": "single_yarn.bcc", "radius": 0.1,
            "material": {
                "model": "bysdf",
                "body_reflection_albedo": [0.3, 0.1, 0.02],
                "body_transmission_albedo": [0.6, 0.25, 0.06],
                "ply_crossing": 2,  # the spread crossing (docs/bysdf.md): closest to the explicit plies
                "yarn": dict({"preset": "prototype"}, **ply_layout(plies)),
                "fiber": {"preset": "fleece", "transmission_color": [0.9, 0.45, 0.15]},
            },
        }],
    }


def main():
    for plies in (1, 3, 6):
        for lighting in LIGHTINGS:
            path = HERE / f"yarn_{plies}ply_{lighting}.json"
            path.write_text(json.dumps(scene(plies, lighting), indent=2) + "\n")
            print(path.relative_to(HERE.parent.parent))


if __name__ == "__main__":
    main()
