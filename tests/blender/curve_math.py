"""Independent evaluators for the curve bases Purl's arrays use, to check exported curves against
the geometry Blender itself evaluates (a curve without bevel converts to its centre polyline)."""
import numpy as np

BSPLINE = np.array([[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 0, 3, 0], [1, 4, 1, 0]]) / 6.0
CATMULL_ROM = np.array([[-1, 3, -3, 1], [2, -5, 4, -1], [-1, 0, 1, 0], [0, 2, 0, 0]]) / 2.0
BEZIER = np.array([[-1, 3, -3, 1], [3, -6, 3, 0], [-3, 3, 0, 0], [1, 0, 0, 0]], dtype=float)


def _segments(points, matrix, stride, samples):
    """Cubic segments with 4 control points each, `stride` points apart."""
    t = np.linspace(0.0, 1.0, samples)
    powers = np.stack([t ** 3, t ** 2, t, np.ones_like(t)], axis=1)
    weights = powers @ matrix
    out = []
    for start in range(0, len(points) - 3, stride):
        out.append(weights @ points[start:start + 4])
    return np.concatenate(out) if out else np.empty((0, 3))


def sample_curve(basis, points, closed=False, samples=64):
    """Dense points along one exported curve of the given basis."""
    points = np.asarray(points, dtype=np.float64)
    if basis == "bspline":
        if closed:
            points = np.concatenate([points, points[:3]])
        return _segments(points, BSPLINE, 1, samples)
    if basis == "catmull_rom":
        if closed:
            points = np.concatenate([points[-1:], points, points[:2]])
        return _segments(points, CATMULL_ROM, 1, samples)
    if closed and basis in ("bezier", "polyline"):  # the last segment ends at the first point
        points = np.concatenate([points, points[:1]])
    if basis == "bezier":
        return _segments(points, BEZIER, 3, samples)
    if basis == "polyline":
        t = np.linspace(0.0, 1.0, samples)[:, None]
        return np.concatenate([a + t * (b - a) for a, b in zip(points[:-1], points[1:])])
    raise ValueError(basis)


def max_distance_to(reference_points, dense_curve):
    """Largest distance from any reference point to the nearest point of a densely sampled curve."""
    d = np.linalg.norm(reference_points[:, None, :] - dense_curve[None, :, :], axis=2)
    return float(d.min(axis=1).max())


def placed_arrays(exported, entry):
    """The array set of a scene entry (yarn set or mesh) with its points or vertices in world space,
    in float64: the exporter gives them relative to the translation of the entry's matrix_world."""
    arrays = dict(exported.arrays[entry["arrays"]])
    translation = np.array(entry["matrix_world"], dtype=np.float64).reshape(4, 4)[:3, 3]
    key = "points" if "points" in arrays else "vertices"
    arrays[key] = arrays[key].astype(np.float64) + translation
    return arrays


def curves_of(arrays):
    """[(points, closed)] per curve of an exported array set."""
    offsets = arrays["offsets"]
    closed = arrays.get("closed")
    return [(arrays["points"][offsets[c]:offsets[c + 1]], bool(closed[c]) if closed is not None else False)
            for c in range(len(offsets) - 1)]
