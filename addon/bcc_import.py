"""File > Import > Yarn Curves (.bcc): Cem Yuksel's yarn-level cloth models and simulation exports.

purlcore reads the file (every check, the Y-up turn and the radius estimate are native); this module
only lays the curves out as Blender data, with numpy and foreach_set:
  Blender 4.x  a hair Curves object: BS -> NURBS (order 4, Normal knots: exactly BCC's uniform
               B-spline), PL -> poly, BZ -> Bezier with free handles, C0 -> Catmull-Rom when every curve
               is closed (the same curve), else Bezier (Blender's open Catmull-Rom runs through
               the end points, BCC's skips them; the Bezier form is exact);
  Blender 3.4  a curve object (its Curves cannot be filled from Python): BS -> NURBS splines,
               PL -> poly, BZ and C0 -> Bezier splines, bevel depth = yarn radius.
Closed loops get `cyclic` / `use_cyclic_u`, so the render closes them as the file does.
"""
import os

import bpy
import numpy as np

from . import native

ADD_CURVES = hasattr(bpy.types.Curves, "add_curves")  # Blender 4.x


class BccImportError(Exception):
    """A file that cannot be imported; the message names the file and the reason."""


def _per_curve(offsets):
    return np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))


def catmull_rom_as_bezier(points, offsets, closed):
    """Exact Bezier form of uniform Catmull-Rom curves: a knot at every point the curve passes
    through, handles a sixth of the neighbours' difference away. Open curves run from their second
    to their second-last point (BCC). Returns (knots, left, right, offsets)."""
    curve = _per_curve(offsets)
    index = np.arange(len(points))
    first, last = offsets[:-1][curve], offsets[1:][curve] - 1
    previous = np.where(index == first, last, index - 1)   # wraps on closed loops
    following = np.where(index == last, first, index + 1)
    tangent_sixth = (points[following] - points[previous]) / 6.0
    knot = closed[curve] | ((index != first) & (index != last))  # open curves drop their ends
    counts = np.diff(offsets) - np.where(closed, 0, 2)
    new_offsets = np.zeros(len(offsets), dtype=np.int64)
    np.cumsum(counts, out=new_offsets[1:])
    return (points[knot], (points - tangent_sixth)[knot], (points + tangent_sixth)[knot], new_offsets)


def bezier_file_curves(points, offsets, closed):
    """BCC 'BZ' curves (3k+1 points open, 3k closed) as knots and handles; an open curve's outer
    handles, which shape nothing, mirror its inner ones. Returns (knots, left, right, offsets)."""
    curve = _per_curve(offsets)
    local = np.arange(len(points)) - offsets[:-1][curve]
    is_knot = local % 3 == 0
    knots = points[is_knot]
    knot_curve = curve[is_knot]
    counts = np.bincount(knot_curve, minlength=len(offsets) - 1)
    new_offsets = np.zeros(len(offsets), dtype=np.int64)
    np.cumsum(counts, out=new_offsets[1:])
    knot_index = np.flatnonzero(is_knot)
    start, end = offsets[:-1][knot_curve], offsets[1:][knot_curve]
    after, before = knot_index + 1, knot_index - 1
    before = np.where(before < start, end - 1, before)  # closed: knot 0's left handle is the last point
    right = np.where((after < end)[:, None], points[np.minimum(after, len(points) - 1)], 0.0)
    left = points[before]
    open_curve = ~closed[knot_curve]
    first_knot = knot_index == start
    last_knot = after >= end
    left = np.where((open_curve & first_knot)[:, None], 2 * knots - right, left)
    right = np.where((open_curve & last_knot)[:, None], 2 * knots - left, right)
    return knots, left, right, new_offsets


def read(path):
    """The file through purlcore, or BccImportError with purlcore's reason."""
    core = native.purlcore()
    if core is None:
        raise BccImportError(native.load_error())
    try:
        return core.read_bcc(path)
    except (core.Error, RuntimeError, ValueError, OSError) as error:
        raise BccImportError(str(error)) from None


# --- Blender 4.x: a hair Curves object -------------------------------------------------------

def _set_attribute(curves, name, data_type, domain, field, values):
    attribute = curves.attributes.get(name) or curves.attributes.new(name, data_type, domain)
    attribute.data.foreach_set(field, np.ascontiguousarray(values).ravel())


def _curves_data(name, data, radius):
    kind, points, offsets, closed = data["type"], data["points"], data["offsets"].astype(np.int64), data["closed"]
    handles = None
    curve_type = {"BS": "NURBS", "PL": "POLY", "BZ": "BEZIER", "C0": "CATMULL_ROM"}[kind]
    if kind == "BZ" or (kind == "C0" and not np.all(closed)):
        convert = bezier_file_curves if kind == "BZ" else catmull_rom_as_bezier
        points, left, right, offsets = convert(points, offsets, closed)
        handles, curve_type = (left, right), "BEZIER"
    curves = bpy.data.hair_curves.new(name)
    curves.add_curves(np.diff(offsets).tolist())
    if curve_type != "CATMULL_ROM":  # the default
        curves.set_types(type=curve_type, indices=list(range(len(closed))))
    _set_attribute(curves, "position", "FLOAT_VECTOR", "POINT", "vector", points.astype(np.float32))
    _set_attribute(curves, "radius", "FLOAT", "POINT", "value", np.full(len(points), radius, dtype=np.float32))
    _set_attribute(curves, "cyclic", "BOOLEAN", "CURVE", "value", closed.astype(bool))
    if handles is not None:  # handle types stay Free (0), so Blender keeps these handles
        _set_attribute(curves, "handle_left", "FLOAT_VECTOR", "POINT", "vector", handles[0].astype(np.float32))
        _set_attribute(curves, "handle_right", "FLOAT_VECTOR", "POINT", "vector", handles[1].astype(np.float32))
    curves.update_tag()
    return curves


# --- Blender 3.4: a curve object ---------------------------------------------------------------

def _curve_data(name, data, radius):
    kind, points, offsets, closed = data["type"], data["points"], data["offsets"].astype(np.int64), data["closed"]
    curve = bpy.data.curves.new(name, "CURVE")
    curve.dimensions = "3D"
    curve.bevel_depth = radius    # the radius Purl reads (point radius 1 x bevel depth)
    curve.bevel_resolution = 0    # the bevel tube is only Blender's own display
    curve.resolution_u = 1        # light to evaluate and draw: Rendered shading draws Purl's image
    if kind in ("C0", "BZ"):
        convert = catmull_rom_as_bezier if kind == "C0" else bezier_file_curves
        knots, left, right, knot_offsets = convert(points, offsets, closed)
        for c in range(len(closed)):
            begin, end = knot_offsets[c], knot_offsets[c + 1]
            spline = curve.splines.new("BEZIER")
            spline.bezier_points.add(int(end - begin) - 1)
            for field, values in (("co", knots), ("handle_left", left), ("handle_right", right)):
                spline.bezier_points.foreach_set(field, values[begin:end].astype(np.float32).ravel())
            spline.bezier_points.foreach_set("handle_left_type", np.zeros(end - begin, dtype=np.int32))
            spline.bezier_points.foreach_set("handle_right_type", np.zeros(end - begin, dtype=np.int32))
            spline.use_cyclic_u = bool(closed[c])
        return curve
    for c in range(len(closed)):
        begin, end = offsets[c], offsets[c + 1]
        spline = curve.splines.new("POLY" if kind == "PL" else "NURBS")
        spline.points.add(int(end - begin) - 1)
        co = np.ones((end - begin, 4), dtype=np.float32)  # w = 1
        co[:, :3] = points[begin:end]
        spline.points.foreach_set("co", co.ravel())
        spline.use_cyclic_u = bool(closed[c])
        if kind == "BS":
            spline.order_u = 4
            spline.use_endpoint_u = spline.use_bezier_u = False
    return curve


def yarn_material(name="Yarn"):
    """A material rendered by Purl's default (BYSDF) yarn model."""
    material = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    return material


def import_bcc(context, path, radius=0.0, scale=1.0):
    """Adds the file as a new object in the active collection and selects it. radius <= 0 takes
    the file's estimate. Returns (object, file data). Raises BccImportError before touching the scene."""
    data = read(path)
    if not len(data["offsets"]) > 1:
        raise BccImportError("{}: the file holds no curves".format(path))
    if radius <= 0.0:
        radius = float(data["radius_estimate"])
        if not radius > 0.0:
            raise BccImportError("{}: the yarn radius cannot be estimated (no two yarns lie side by side); "
                               "give a radius".format(path))
    name = os.path.splitext(os.path.basename(path))[0]
    data = dict(data, points=data["points"].astype(np.float64) * scale)
    radius *= scale
    block = _curves_data(name, data, radius) if ADD_CURVES else _curve_data(name, data, radius)
    block.materials.append(yarn_material())
    ob = bpy.data.objects.new(name, block)
    context.collection.objects.link(ob)
    for other in context.selected_objects:
        other.select_set(False)
    ob.select_set(True)
    context.view_layer.objects.active = ob
    return ob, dict(data, radius=radius)


class PURL_OT_import_bcc(bpy.types.Operator):
    """Import a BCC yarn-curve file (Cem Yuksel's yarn-level cloth models) as yarns for Purl"""
    bl_idname = "purl.import_bcc"
    bl_label = "Import Yarn Curves"
    bl_options = {"REGISTER", "UNDO", "PRESET"}

    filepath: bpy.props.StringProperty(subtype="FILE_PATH")
    filter_glob: bpy.props.StringProperty(default="*.bcc", options={"HIDDEN"})
    use_estimated_radius: bpy.props.BoolProperty(
        name="Estimate Radius", default=True,
        description="Yarn radius from the file: half the median distance between neighbouring yarns")
    radius: bpy.props.FloatProperty(
        name="Radius", default=0.001, min=1e-7, soft_max=1.0, precision=5,
        description="Yarn radius in the file's units (BCC files carry none)")
    scale: bpy.props.FloatProperty(
        name="Scale", default=1.0, min=1e-6, soft_max=100.0,
        description="File units to Blender units (e.g. 0.01 for a file in centimetres)")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "use_estimated_radius")
        row = layout.row()
        row.active = not self.use_estimated_radius
        row.prop(self, "radius")
        layout.prop(self, "scale")

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        import time
        start = time.monotonic()
        try:
            ob, data = import_bcc(context, self.filepath, 0.0 if self.use_estimated_radius else self.radius, self.scale)
        except BccImportError as error:
            self.report({"ERROR"}, "Purl: " + str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, "Imported {}: {} curves ({}), {} points, radius {:.4g}{} in {:.2f} s".format(
            ob.name, len(data["closed"]), data["type"], len(data["points"]), data["radius"],
            " (estimated)" if self.use_estimated_radius else "", time.monotonic() - start))
        return {"FINISHED"}


def _menu_import(self, context):
    self.layout.operator(PURL_OT_import_bcc.bl_idname, text="Yarn Curves (.bcc)")


def register():
    bpy.utils.register_class(PURL_OT_import_bcc)
    bpy.types.TOPBAR_MT_file_import.append(_menu_import)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(_menu_import)
    bpy.utils.unregister_class(PURL_OT_import_bcc)
