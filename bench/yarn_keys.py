"""A scene's yarn centre-lines as Cycles hair keys, for the benchmark's `cycles-yarn` method (Cycles
on the very tubes the BYSDF shades; bench/cycles_worker.py reads the .npz).

Each yarn set is read as Purl reads it (purlcore.load_bcc for "bcc", `purl generate` for
"generate"); every cubic B-spline segment of its segment table is sampled at its start and
half-way, and each curve's last segment at its end too, so chains and the separate segments of
converted Catmull-Rom curves both come out as one run of keys per curve.
"""
import json
import os
import pathlib
import subprocess

import numpy as np


def segment_keys(points, radii, segments, segment_offsets):
    """Keys (points, radii, counts per curve) of B-spline curves given by their segment tables."""
    out_points, out_radii, counts = [], [], []
    ts = np.array([0.0, 0.5])
    basis_mid = np.array([[(1 - t) ** 3 / 6, (3 * t**3 - 6 * t**2 + 4) / 6,
                           (-3 * t**3 + 3 * t**2 + 3 * t + 1) / 6, t**3 / 6] for t in ts])
    basis_end = np.array([0.0, 1 / 6, 4 / 6, 1 / 6])
    values = np.concatenate([points, radii[:, None]], axis=1)
    for c in range(len(segment_offsets) - 1):
        firsts = segments[segment_offsets[c]:segment_offsets[c + 1]]
        if len(firsts) == 0:
            continue
        controls = values[firsts[:, None] + np.arange(4)]  # (segments, 4, 4)
        keys = np.einsum("tk,skd->std", basis_mid, controls).reshape(-1, 4)
        keys = np.concatenate([keys, (basis_end @ controls[-1])[None]])
        out_points.append(keys[:, :3])
        out_radii.append(keys[:, 3])
        counts.append(len(keys))
    if not counts:
        return np.zeros((0, 3)), np.zeros(0), np.zeros(0, int)
    return np.concatenate(out_points), np.concatenate(out_radii), np.array(counts)


def yarn_set_curves(yarn, base_dir, purl, work):
    """One yarn set's curves as purlcore.load_bcc returns them."""
    import purlcore

    if "matrix_world" in yarn:
        raise SystemExit("yarn_keys: yarn %r: matrix_world is not supported here" % yarn.get("name"))
    if "bcc" in yarn:
        return purlcore.load_bcc(os.path.join(base_dir, yarn["bcc"]), float(yarn["radius"]))
    generate = yarn.get("generate")
    if generate is None or set(generate) - {"kind", "radius"}:
        raise SystemExit("yarn_keys: yarn %r needs bcc, or generate with kind and radius only (what `purl "
                         "generate` takes)" % yarn.get("name"))
    path = pathlib.Path(work) / ("%s.bcc" % yarn.get("name", "yarn"))
    cmd = [str(purl), "generate", generate.get("kind", "knit"), "-o", str(path)]
    if "radius" in generate:
        cmd += ["--radius", repr(float(generate["radius"]))]
    subprocess.run(cmd, check=True, capture_output=True)
    radius = float(generate.get("radius", 0.5e-3))
    return purlcore.load_bcc(str(path), radius)


def write_yarn_keys(scene_path, out_npz, purl, work):
    """All yarn sets of the scene as one .npz of keys; returns the number of curves."""
    scene = json.loads(pathlib.Path(scene_path).read_text(encoding="utf-8"))
    base_dir = os.path.dirname(os.path.abspath(scene_path))
    parts = [segment_keys(c["points"], c["radii"], c["segments"], c["segment_offsets"])
             for c in (yarn_set_curves(y, base_dir, purl, work) for y in scene.get("yarns", []))]
    points, radii, counts = (np.concatenate(a) for a in zip(*parts))
    np.savez(out_npz, points=points.astype(np.float32), radii=radii.astype(np.float32), counts=counts)
    return len(counts)
