"""Yarn centre-lines from Blender objects: hair Curves, particle hair and curve objects.

Every function returns YarnCurves in world space, one per (object, basis, material), as the flat
arrays that purlcore.RenderJob takes. Bulk data is read with foreach_get; only particle hair is read
point by point, because Blender has no bulk API for it.
"""
from dataclasses import dataclass

import numpy as np

from .transforms import to_numpy, transform_points, uniform_scale

HAIR_DEFAULT_RADIUS = 0.005  # what Cycles uses when a Curves object has no radius attribute
DEFAULT_COLOR_ATTRIBUTE = "purl_color"  # read when the material names no colour attribute
# Fewest points a curve of each basis needs (closed B-splines need 3; they are wrapped natively).
MIN_POINTS = {"bspline": 4, "catmull_rom": 4, "bezier": 4, "polyline": 2}


@dataclass
class YarnCurves:
    name: str             # object name (and part), for reports
    basis: str            # "bspline", "catmull_rom", "bezier" or "polyline"
    points: np.ndarray    # float32 (N, 3), world space
    radii: np.ndarray     # float32 (N,), world space
    offsets: np.ndarray   # int32 (C + 1,): curve c is points[offsets[c]:offsets[c+1]]
    closed: np.ndarray    # bool (C,)
    material: object      # bpy.types.Material or None
    source: str = ""      # the original object's name (composite mode hides it from Cycles' camera)
    colors: np.ndarray = None  # float32 (C, 3) linear RGB per curve, or None

    @property
    def curve_count(self):
        return len(self.offsets) - 1

    def arrays(self):
        """The dict purlcore.RenderJob expects for one named array set."""
        arrays = {"points": self.points, "radii": self.radii, "offsets": self.offsets,
                  "closed": self.closed, "basis": self.basis}
        if self.colors is not None:
            arrays["curve_colors"] = self.colors
        return arrays


def repeat_end_points(points, radii, offsets):
    """Catmull-Rom through all points: BCC's convention skips the first and last, so repeat them."""
    counts = np.diff(offsets)
    new_counts = counts + 2
    new_offsets = np.zeros(len(offsets), dtype=np.int32)
    np.cumsum(new_counts, out=new_offsets[1:])
    curve = np.repeat(np.arange(len(counts)), new_counts)
    local = np.arange(new_offsets[-1]) - new_offsets[:-1][curve]
    source = offsets[:-1][curve] + np.clip(local - 1, 0, counts[curve] - 1)
    return points[source], radii[source], new_offsets


def _original_name(ob):
    return ob.original.name if getattr(ob, "original", None) is not None else ob.name


def _first_material(ob):
    for slot in ob.material_slots:
        if slot.material is not None:
            return slot.material
    return None


def _slot_material(ob, index):
    if 0 <= index < len(ob.material_slots):
        return ob.material_slots[index].material
    return None


# --- hair Curves (Blender 3.3+) -------------------------------------------------------------

def color_attribute_name(material):
    """The colour attribute named on the yarn material, or the default name."""
    settings = getattr(material, "purl", None) if material is not None else None
    name = getattr(settings, "color_attribute", "") if settings is not None else ""
    return name or DEFAULT_COLOR_ATTRIBUTE


_COLOR_TYPES = {"FLOAT_COLOR": ("color", 4), "BYTE_COLOR": ("color", 4), "FLOAT_VECTOR": ("vector", 3)}


def curve_colors(ob, data, offsets, problems, name):
    """float32 (n_curves, 3) linear RGB from a CURVE-domain colour attribute, or a POINT-domain one
    averaged over each curve's points; None when the object has no such attribute."""
    attribute = data.attributes.get(name)
    if attribute is None:
        if name != DEFAULT_COLOR_ATTRIBUTE and problems is not None:
            problems.warning(ob.name, "has no colour attribute '{}'; the material's colours are used".format(name))
        return None
    kind = _COLOR_TYPES.get(attribute.data_type)
    if kind is None or attribute.domain not in {"CURVE", "POINT"}:
        if problems is not None:
            problems.warning(ob.name, "colour attribute '{}' is {} on the {} domain; Purl reads colours "
                             "(or vectors) on the curve or point domain".format(name, attribute.data_type, attribute.domain))
        return None
    field, width = kind
    # BYTE_COLOR's `color` is already scene-linear (color_srgb is the sRGB one).
    values = np.empty(len(attribute.data) * width, dtype=np.float32)
    attribute.data.foreach_get(field, values)
    values = values.reshape(-1, width)[:, :3]
    if attribute.domain == "POINT":
        counts = np.maximum(np.diff(offsets), 1)[:, None]
        values = np.add.reduceat(values, offsets[:-1], axis=0) / counts
    return np.ascontiguousarray(values, dtype=np.float32)


def hair_curves(ob, matrix_world, problems=None):
    """A Curves object; Cycles renders each curve as Catmull-Rom through all its points."""
    data = ob.data
    n_points, n_curves = len(data.points), len(data.curves)
    if n_points == 0 or n_curves == 0:
        return []
    positions = np.empty(n_points * 3, dtype=np.float32)
    data.attributes["position"].data.foreach_get("vector", positions)
    offsets = np.empty(n_curves + 1, dtype=np.int32)
    data.curve_offset_data.foreach_get("value", offsets)
    radii = np.full(n_points, HAIR_DEFAULT_RADIUS, dtype=np.float32)
    radius = data.attributes.get("radius")
    if radius is not None and radius.domain == "POINT" and radius.data_type == "FLOAT":
        radius.data.foreach_get("value", radii)
    points = transform_points(positions.reshape(-1, 3), matrix_world)
    radii = radii * np.float32(uniform_scale(matrix_world))
    material = _first_material(ob)
    colors = curve_colors(ob, data, offsets, problems, color_attribute_name(material))
    points, radii, offsets = repeat_end_points(points, radii, offsets)
    return [YarnCurves(ob.name, "catmull_rom", points, radii, offsets,
                       np.zeros(n_curves, dtype=bool), material, _original_name(ob), colors)]


# --- particle hair -----------------------------------------------------------------------------

def _pad_short_paths(points):
    """co_hair returns (0,0,0) past the end of a shortened path: repeat the last valid point."""
    invalid = np.all(points == 0.0, axis=2)
    invalid[:, 0] = False
    steps = points.shape[1]
    last_valid = np.where(invalid, 0, np.arange(steps)[None, :])
    np.maximum.accumulate(last_valid, axis=1, out=last_valid)
    return points[np.arange(points.shape[0])[:, None], last_valid]


def _particle_radii(settings, points, scale):
    """Cycles' hair shape: root-to-tip radius along the strand's length, shaped by `shape`."""
    seg = np.linalg.norm(np.diff(points, axis=1), axis=2)
    along = np.concatenate([np.zeros((points.shape[0], 1)), np.cumsum(seg, axis=1)], axis=1)
    total = along[:, -1:]
    steps = points.shape[1]
    fallback = np.linspace(0.0, 1.0, steps)[None, :]
    t = np.where(total > 0.0, along / np.where(total > 0.0, total, 1.0), fallback)
    shape = min(max(settings.shape, -0.999), 0.999)
    if shape < 0.0:
        t = t ** (1.0 + shape)
    elif shape > 0.0:
        t = t ** (1.0 / (1.0 - shape))
    half = 0.5 * settings.radius_scale
    radii = half * (settings.root_radius * (1.0 - t) + settings.tip_radius * t)
    if settings.use_close_tip:
        radii[:, -1] = 0.0
    return (radii * scale).astype(np.float32)


def particle_hair(ob, matrix_world, render_mode):
    """Hair particle systems of a mesh object; with children, only the children render."""
    result = []
    # co_hair places points by the object's own matrix; re-place them when ob is an instance.
    own = to_numpy(ob.matrix_world)
    to_instance = to_numpy(matrix_world) @ np.linalg.inv(own)
    for psys in ob.particle_systems:
        settings = psys.settings
        if settings.type != "HAIR" or settings.render_type != "PATH":
            continue
        step_exponent = settings.render_step if render_mode else settings.display_step
        steps = (1 << step_exponent) + 1
        n_parents, n_children = len(psys.particles), len(psys.child_particles)
        if settings.child_type != "NONE" and n_children > 0:
            strands = range(n_parents, n_parents + n_children)
        else:
            strands = range(n_parents)
        if len(strands) == 0:
            continue
        points = np.empty((len(strands), steps, 3), dtype=np.float32)
        for row, strand in enumerate(strands):  # no bulk API for particle paths
            for step in range(steps):
                points[row, step] = psys.co_hair(object=ob, particle_no=strand, step=step)
        points = _pad_short_paths(points)
        points = transform_points(points.reshape(-1, 3), to_instance).reshape(points.shape)
        radii = _particle_radii(settings, points, uniform_scale(to_instance))
        offsets = (np.arange(len(strands) + 1) * steps).astype(np.int32)
        flat_points, flat_radii, offsets = repeat_end_points(points.reshape(-1, 3), radii.reshape(-1), offsets)
        material = _slot_material(ob, settings.material - 1)
        result.append(YarnCurves("{} / {}".format(ob.name, psys.name), "catmull_rom", flat_points,
                                 flat_radii, offsets, np.zeros(len(strands), dtype=bool), material))
    return result


# --- curve objects -------------------------------------------------------------------------

def _bezier_spline(spline):
    """Cubic Bezier control points [k0, right0, left1, k1, ...]; a cyclic spline gets its closing
    segment written out. Radii vary linearly along each segment, as thirds at the handles."""
    n = len(spline.bezier_points)
    knots, right, left = (np.empty(n * 3, dtype=np.float32) for _ in range(3))
    radius = np.empty(n, dtype=np.float32)
    spline.bezier_points.foreach_get("co", knots)
    spline.bezier_points.foreach_get("handle_right", right)
    spline.bezier_points.foreach_get("handle_left", left)
    spline.bezier_points.foreach_get("radius", radius)
    knots, right, left = knots.reshape(-1, 3), right.reshape(-1, 3), left.reshape(-1, 3)
    next_left, next_radius = np.roll(left, -1, axis=0), np.roll(radius, -1)
    points = np.stack([knots, right, next_left], axis=1).reshape(-1, 3)
    radii = np.stack([radius, radius * (2 / 3) + next_radius / 3,
                      radius / 3 + next_radius * (2 / 3)], axis=1).reshape(-1)
    if spline.use_cyclic_u:
        points = np.concatenate([points, knots[:1]])
        radii = np.concatenate([radii, radius[:1]])
    else:
        points, radii = points[:3 * (n - 1) + 1], radii[:3 * (n - 1) + 1]
    return "bezier", points, radii, False


def _spline_points(spline):
    n = len(spline.points)
    co = np.empty(n * 4, dtype=np.float32)
    radius = np.empty(n, dtype=np.float32)
    spline.points.foreach_get("co", co)
    spline.points.foreach_get("radius", radius)
    return co.reshape(-1, 4), radius


def _poly_spline(spline):
    co, radius = _spline_points(spline)
    points = co[:, :3]
    if spline.use_cyclic_u and len(points) > 2:  # close the loop explicitly
        points, radius = np.concatenate([points, points[:1]]), np.concatenate([radius, radius[:1]])
    return "polyline", points, radius, False


def _bspline_basis(knots, order, t):
    """Cox-de Boor: (S, len(knots) - order) basis values at parameters t (S,)."""
    n_basis = len(knots) - 1
    basis = ((knots[None, :-1] <= t[:, None]) & (t[:, None] < knots[None, 1:])).astype(np.float64)
    for k in range(2, order + 1):
        n_basis -= 1
        left_den = knots[k - 1:k - 1 + n_basis] - knots[:n_basis]
        right_den = knots[k:k + n_basis] - knots[1:1 + n_basis]
        left = np.where(left_den > 0, (t[:, None] - knots[None, :n_basis]) / np.where(left_den > 0, left_den, 1), 0)
        right = np.where(right_den > 0, (knots[None, k:k + n_basis] - t[:, None]) / np.where(right_den > 0, right_den, 1), 0)
        basis = left * basis[:, :n_basis] + right * basis[:, 1:n_basis + 1]
    return basis


def _sample_nurbs(co, radius, order, endpoint, cyclic, resolution):
    """Evaluates a rational NURBS spline (Blender's uniform or endpoint knots) at `resolution`
    samples per segment. Returns (points, radii)."""
    n = len(co)
    weights = co[:, 3].astype(np.float64)
    xyz = co[:, :3].astype(np.float64)
    r = radius.astype(np.float64)
    if cyclic:  # wrap order-1 points; uniform knots make it periodic
        wrap = np.arange(n + order - 1) % n
        xyz, weights, r = xyz[wrap], weights[wrap], r[wrap]
    count = len(xyz)
    if endpoint and not cyclic:
        inner = np.arange(1, count - order + 1, dtype=np.float64)
        knots = np.concatenate([np.zeros(order), inner, np.full(order, count - order + 1.0)])
    else:
        knots = np.arange(count + order, dtype=np.float64)
    start, end = knots[order - 1], knots[count]
    segments = n if cyclic else max(count - order + 1, 1)
    samples = segments * max(resolution, 1) + (0 if cyclic else 1)
    t = np.linspace(start, end, samples, endpoint=not cyclic)
    t = np.minimum(t, np.nextafter(end, start))  # the last knot span is half-open
    basis = _bspline_basis(knots, order, t) * weights[None, :]
    denominator = basis.sum(axis=1, keepdims=True)
    points = (basis @ xyz) / denominator
    radii = (basis @ r) / denominator[:, 0]
    return points.astype(np.float32), radii.astype(np.float32)


def _nurbs_spline(spline):
    co, radius = _spline_points(spline)
    order = min(spline.order_u, len(co))
    cyclic = spline.use_cyclic_u
    rational = not np.allclose(co[:, 3], 1.0)
    if order == 4 and not rational and (cyclic or not (spline.use_endpoint_u or spline.use_bezier_u)):
        # Blender's uniform cubic NURBS is exactly a uniform cubic B-spline.
        return "bspline", co[:, :3].copy(), radius, cyclic
    endpoint = spline.use_endpoint_u or spline.use_bezier_u
    points, radii = _sample_nurbs(co, radius, order, endpoint, cyclic, spline.resolution_u)
    if cyclic:
        return "catmull_rom", points, radii, True
    offsets = np.array([0, len(points)], dtype=np.int32)
    points, radii, _ = repeat_end_points(points, radii, offsets)
    return "catmull_rom", points, radii, False


_SPLINE_READERS = {"BEZIER": _bezier_spline, "POLY": _poly_spline, "NURBS": _nurbs_spline}


def curve_object(ob, matrix_world, problems):
    """A curve object: its splines' control points with radius x bevel depth."""
    curve = ob.data
    if curve.bevel_depth <= 0.0:
        problems.warning(ob.name, "the curve has no bevel depth, so it has no radius and is "
                         "skipped; set Geometry > Bevel > Depth to the yarn radius")
        return []
    if getattr(curve, "bevel_mode", "ROUND") != "ROUND" or curve.bevel_object is not None:
        problems.warning(ob.name, "only round bevels are rendered as yarn; the bevel depth is "
                         "used as the radius and the profile is ignored")
    groups = {}  # (basis, material index) -> [(points, radii, closed)]
    for spline in curve.splines:
        reader = _SPLINE_READERS.get(spline.type)
        if reader is None or len(spline.bezier_points if spline.type == "BEZIER" else spline.points) == 0:
            continue
        basis, points, radii, closed = reader(spline)
        groups.setdefault((basis, spline.material_index), []).append((points, radii, closed))
    scale = np.float32(uniform_scale(matrix_world) * curve.bevel_depth)
    result = []
    for (basis, material_index), parts in sorted(groups.items()):
        counts = [len(points) for points, _, _ in parts]
        offsets = np.zeros(len(parts) + 1, dtype=np.int32)
        np.cumsum(counts, out=offsets[1:])
        points = transform_points(np.concatenate([p for p, _, _ in parts]), matrix_world)
        radii = np.concatenate([r for _, r, _ in parts]).astype(np.float32) * scale
        closed = np.array([c for _, _, c in parts], dtype=bool)
        name = ob.name if len(groups) == 1 else "{} ({})".format(ob.name, basis)
        result.append(YarnCurves(name, basis, points, radii, offsets, closed,
                                 _slot_material(ob, material_index), _original_name(ob)))
    if not result:
        problems.warning(ob.name, "the curve has no points")
    return result


# --- checks ----------------------------------------------------------------------------------

def checked(yarn, problems):
    """The yarn set made safe for the renderer, or None (with a report) when nothing is left."""
    if yarn.colors is not None and not np.all(np.isfinite(yarn.colors)):
        problems.warning(yarn.name, "the colour attribute holds values that are not finite numbers; "
                         "the material's colours are used")
        yarn.colors = None
    if yarn.colors is not None and (yarn.colors.min() < 0.0 or yarn.colors.max() > 1.0):
        problems.warning(yarn.name, "colour attribute values outside [0, 1] are clipped (purlcore "
                         "accepts curve colours in [0, 1] only)")
        yarn.colors = np.clip(yarn.colors, 0.0, 1.0)
    if not np.all(np.isfinite(yarn.points)):
        bad = int(np.count_nonzero(~np.all(np.isfinite(yarn.points), axis=1)))
        problems.warning(yarn.name, "{} point positions are not finite numbers (NaN or infinite); "
                       "the object is skipped".format(bad))
        return None
    if not np.all(np.isfinite(yarn.radii)) or not np.any(yarn.radii > 0.0):
        problems.warning(yarn.name, "the yarn radius is zero (or not a number) everywhere; "
                       "the object is skipped")
        return None
    # Zero radii at tips (closed hair tips, tapered ends) are legal in Blender; the renderer
    # needs radius > 0, so raise them to a thousandth of the largest radius.
    floor = np.float32(1e-3 * float(yarn.radii.max()))
    radii = np.maximum(yarn.radii, floor)
    counts = np.diff(yarn.offsets)
    minimum = np.where(yarn.closed, 3, MIN_POINTS[yarn.basis])
    keep = counts >= minimum
    if not np.all(keep):
        problems.warning(yarn.name, "{} curves with too few points for a {} curve are skipped".format(
            int(np.count_nonzero(~keep)), yarn.basis.replace("_", "-")))
        if not np.any(keep):
            return None
        point_keep = np.repeat(keep, counts)
        kept_counts = counts[keep]
        offsets = np.zeros(len(kept_counts) + 1, dtype=np.int32)
        np.cumsum(kept_counts, out=offsets[1:])
        colors = yarn.colors[keep] if yarn.colors is not None else None
        return YarnCurves(yarn.name, yarn.basis, yarn.points[point_keep], radii[point_keep],
                          offsets, yarn.closed[keep], yarn.material, yarn.source, colors)
    return YarnCurves(yarn.name, yarn.basis, yarn.points, radii, yarn.offsets, yarn.closed,
                      yarn.material, yarn.source, yarn.colors)
