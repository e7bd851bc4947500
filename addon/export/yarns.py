"""Yarn centre-lines from Blender objects: hair Curves, particle hair and curve objects.

Every function returns YarnCurves in world space relative to their object's position (`origin`,
exported as the set's matrix_world), one per (object, basis, material), as the flat arrays that
purlcore.RenderJob takes. Bulk data is read with foreach_get; only particle hair is read
point by point, because Blender has no bulk API for it.
"""
from dataclasses import dataclass, field, replace

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
    points: np.ndarray    # float32 (N, 3), world space relative to `origin`
    radii: np.ndarray     # float32 (N,), world space
    offsets: np.ndarray   # int32 (C + 1,): curve c is points[offsets[c]:offsets[c+1]]
    closed: np.ndarray    # bool (C,)
    material: object      # bpy.types.Material or None
    source: str = ""      # the original object's name (composite mode hides it from Cycles' camera)
    colors: np.ndarray = None  # float32 (C, 3) linear RGB per curve, or None
    origin: np.ndarray = field(default_factory=lambda: np.zeros(3))  # float64 (3,), world space

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


def repeat_end_points(points, radii, offsets, closed=None):
    """Catmull-Rom through all points: BCC's convention skips the first and last, so repeat them
    (on the open curves only, when `closed` is given: a closed loop needs no extra points)."""
    counts = np.diff(offsets)
    extra = np.full(len(counts), 2) if closed is None else np.where(closed, 0, 2)
    new_counts = counts + extra
    new_offsets = np.zeros(len(offsets), dtype=np.int32)
    np.cumsum(new_counts, out=new_offsets[1:])
    curve = np.repeat(np.arange(len(counts)), new_counts)
    local = np.arange(new_offsets[-1]) - new_offsets[:-1][curve]
    source = offsets[:-1][curve] + np.clip(local - extra[curve] // 2, 0, counts[curve] - 1)
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


# Blender's curve types (the CURVE-domain attribute "curve_type"; absent means Catmull-Rom).
CATMULL_ROM, POLY, BEZIER, NURBS = 0, 1, 2, 3


def _attribute_values(data, name, domain, dtype, width, count, default):
    """An attribute as a numpy array of `count` x `width`, or `default` everywhere when absent."""
    attribute = data.attributes.get(name)
    if attribute is None or attribute.domain != domain:
        return np.full((count, width) if width > 1 else count, default, dtype=dtype)
    values = np.empty(count * width, dtype=dtype)
    attribute.data.foreach_get("vector" if width == 3 else "value", values)
    return values.reshape(-1, width) if width > 1 else values


def select_curves(offsets, chosen):
    """Point indices and new offsets of the curves `chosen` (bool per curve)."""
    counts = np.diff(offsets)[chosen]
    new_offsets = np.zeros(len(counts) + 1, dtype=np.int32)
    np.cumsum(counts, out=new_offsets[1:])
    starts = offsets[:-1][chosen]
    points = np.repeat(starts - new_offsets[:-1], counts) + np.arange(new_offsets[-1])
    return points, new_offsets


def bezier_control_points(knots, left, right, radius, offsets, closed):
    """Cubic Bezier control points [k0, right0, left1, k1, ...] of many curves at once: 3n+1 per
    open curve of n knots, 3n per closed one (its last segment ends at k0). Radii vary linearly
    along each segment, as thirds at the handles. Returns (points, radii, offsets)."""
    n = len(knots)
    curve = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    following = np.arange(n) + 1
    last = offsets[1:][curve] - 1 == np.arange(n)
    following[last] = offsets[:-1][curve[last]]  # wraps to the curve's first knot
    points = np.stack([knots, right, left[following]], axis=1).reshape(-1, 3)
    next_radius = radius[following]
    radii = np.stack([radius, radius * (2 / 3) + next_radius / 3, radius / 3 + next_radius * (2 / 3)],
                     axis=1).reshape(-1)
    keep = np.ones(3 * n, dtype=bool)
    open_last = np.flatnonzero(last & ~closed[curve])
    keep[3 * open_last + 1] = keep[3 * open_last + 2] = False  # an open curve ends at its last knot
    counts = 3 * np.diff(offsets) - np.where(closed, 0, 2)
    new_offsets = np.zeros(len(offsets), dtype=np.int32)
    np.cumsum(counts, out=new_offsets[1:])
    return points[keep], radii[keep].astype(np.float32), new_offsets


def hair_curves(ob, matrix_world, problems=None):
    """A Curves object, one yarn set per curve type: Catmull-Rom (Cycles' hair: through all
    points), poly, Bezier (with its handles) and uniform cubic NURBS, closed where `cyclic` is set."""
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
    points, origin = transform_points(positions.reshape(-1, 3), matrix_world)
    radii = radii * np.float32(uniform_scale(matrix_world))
    material = _first_material(ob)
    colors = curve_colors(ob, data, offsets, problems, color_attribute_name(material))
    types = _attribute_values(data, "curve_type", "CURVE", np.int32, 1, n_curves, CATMULL_ROM)
    cyclic = _attribute_values(data, "cyclic", "CURVE", bool, 1, n_curves, False)
    if np.any(types == NURBS):
        # Uniform cubic NURBS (order 4, knots "Normal", weights 1) is exactly a uniform B-spline.
        order = _attribute_values(data, "nurbs_order", "CURVE", np.int32, 1, n_curves, 4)
        knots_mode = _attribute_values(data, "knots_mode", "CURVE", np.int32, 1, n_curves, 0)
        weights = _attribute_values(data, "nurbs_weight", "POINT", np.float32, 1, n_points, 1.0)
        rational = np.maximum.reduceat(np.abs(weights - 1.0), offsets[:-1]) > 1e-6
        approximated = (types == NURBS) & ((order != 4) | (knots_mode != 0) | rational)
        if np.any(approximated) and problems is not None:
            problems.warning(ob.name, "{} NURBS curves are not uniform cubic (order 4, Normal knots, weight 1); "
                             "they render as Catmull-Rom curves through their control points".format(
                                 int(np.count_nonzero(approximated))))
        types = np.where(approximated, CATMULL_ROM, types)
    result = []
    for kind in (CATMULL_ROM, POLY, BEZIER, NURBS):
        chosen = types == kind
        if not np.any(chosen):
            continue
        index, part_offsets = select_curves(offsets, chosen)
        part_points, part_radii, closed = points[index], radii[index], cyclic[chosen]
        if kind == CATMULL_ROM:
            basis = "catmull_rom"
            part_points, part_radii, part_offsets = repeat_end_points(part_points, part_radii, part_offsets, closed)
        elif kind == BEZIER:
            basis = "bezier"
            # Relative to the same origin as the points: the same matrix.
            left, _ = transform_points(
                _attribute_values(data, "handle_left", "POINT", np.float32, 3, n_points, 0.0)[index], matrix_world)
            right, _ = transform_points(
                _attribute_values(data, "handle_right", "POINT", np.float32, 3, n_points, 0.0)[index], matrix_world)
            part_points, part_radii, part_offsets = bezier_control_points(part_points, left, right, part_radii,
                                                                          part_offsets, closed)
        else:
            basis = "polyline" if kind == POLY else "bspline"
        name = ob.name if np.all(chosen) else "{} ({})".format(ob.name, basis.replace("_", "-"))
        result.append(YarnCurves(name, basis, part_points, part_radii, part_offsets, closed.copy(), material,
                                 _original_name(ob), colors[chosen] if colors is not None else None, origin))
    return result


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
        flat_points, origin = transform_points(points.reshape(-1, 3), to_instance)
        points = flat_points.reshape(points.shape)
        radii = _particle_radii(settings, points, uniform_scale(to_instance))
        offsets = (np.arange(len(strands) + 1) * steps).astype(np.int32)
        flat_points, flat_radii, offsets = repeat_end_points(points.reshape(-1, 3), radii.reshape(-1), offsets)
        material = _slot_material(ob, settings.material - 1)
        result.append(YarnCurves("{} / {}".format(ob.name, psys.name), "catmull_rom", flat_points,
                                 flat_radii, offsets, np.zeros(len(strands), dtype=bool), material,
                                 origin=origin))
    return result


# --- curve objects -------------------------------------------------------------------------

def _bezier_spline(spline):
    """Cubic Bezier control points of one spline (bezier_control_points); a cyclic spline stays
    a closed curve."""
    n = len(spline.bezier_points)
    knots, right, left = (np.empty(n * 3, dtype=np.float32) for _ in range(3))
    radius = np.empty(n, dtype=np.float32)
    spline.bezier_points.foreach_get("co", knots)
    spline.bezier_points.foreach_get("handle_right", right)
    spline.bezier_points.foreach_get("handle_left", left)
    spline.bezier_points.foreach_get("radius", radius)
    closed = bool(spline.use_cyclic_u) and n > 1
    points, radii, _ = bezier_control_points(knots.reshape(-1, 3), left.reshape(-1, 3), right.reshape(-1, 3),
                                             radius, np.array([0, n]), np.array([closed]))
    return "bezier", points, radii, closed


def _spline_points(spline):
    n = len(spline.points)
    co = np.empty(n * 4, dtype=np.float32)
    radius = np.empty(n, dtype=np.float32)
    spline.points.foreach_get("co", co)
    spline.points.foreach_get("radius", radius)
    return co.reshape(-1, 4), radius


def _poly_spline(spline):
    co, radius = _spline_points(spline)
    return "polyline", co[:, :3].copy(), radius, bool(spline.use_cyclic_u) and len(co) > 2


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
        points, origin = transform_points(np.concatenate([p for p, _, _ in parts]), matrix_world)
        radii = np.concatenate([r for _, r, _ in parts]).astype(np.float32) * scale
        closed = np.array([c for _, _, c in parts], dtype=bool)
        name = ob.name if len(groups) == 1 else "{} ({})".format(ob.name, basis)
        result.append(YarnCurves(name, basis, points, radii, offsets, closed,
                                 _slot_material(ob, material_index), _original_name(ob), origin=origin))
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
        return replace(yarn, points=yarn.points[point_keep], radii=radii[point_keep], offsets=offsets,
                       closed=yarn.closed[keep], colors=colors)
    return replace(yarn, radii=radii)
