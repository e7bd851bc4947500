"""Set up for Cycles: gives yarn (hair Curves) objects the Purl look in Cycles through the OSL
shader in osl/purl_bysdf.osl (docs/osl.md).

The operator writes two point attributes on each selected Curves object (the arc length from the
root and a rotation-minimizing reference normal, in object space, so the ply phase follows the
yarn the way the native core's frames do) and one curve attribute (the native curve number, so
fibers migrate as in the native core) and builds, in each of its materials, a Script node wired
by drivers to the same Purl material settings the native engine reads (parameters, presets, ply
colours): switching engine keeps the look, and editing a setting updates both.
"""
import glob
import hashlib
import os
import sys

import bpy
import numpy as np

from . import compat, native, parameters
from .export.materials import yarn_material

HERE = os.path.dirname(os.path.abspath(__file__))
SHADER_PATH = os.path.join(HERE, "osl", "purl_bysdf.osl")
SHADER_TEXT_NAME = "purl_bysdf.osl"
ARC_LENGTH_ATTRIBUTE = "purl_arc_length"
NORMAL_ATTRIBUTE = "purl_reference_normal"
CURVE_KEY_ATTRIBUTE = "purl_curve_key"
SCRIPT_NODE_NAME = "Purl BYSDF (OSL)"
# Yarn structure inputs of the shader; their defaults come from the native yarn description.
STRUCTURE_INPUTS = ("ply_count", "ply_radius", "ply_distance", "ply_twist", "ply_handedness",
                    "fiber_count", "fiber_radius", "fiber_twist", "fiber_handedness", "migration_frequency")
MAPS_BEGIN, MAPS_END = "// PURL_MAPS_BEGIN\n", "// PURL_MAPS_END\n"


def osl_available():
    """(True, "") when this Blender's Cycles can compile and run OSL, else (False, reason)."""
    options = bpy.app.build_options
    if not getattr(options, "cycles", False):
        return False, "this Blender is built without Cycles"
    if not getattr(options, "cycles_osl", False):
        return False, "this Blender {} is built without OSL (bpy.app.build_options.cycles_osl is False)".format(
            bpy.app.version_string)
    return True, ""


def _make_oslquery_importable():
    """Cycles compiles Script nodes with the `oslquery` module it bundles; the PyPI `bpy` module
    ships it in its own site-packages but does not put that on sys.path."""
    try:
        import oslquery  # noqa: F401
        return
    except ImportError:
        pass
    pattern = os.path.join(bpy.utils.resource_path("LOCAL"), "python", "lib", "python3*", "site-packages")
    for folder in glob.glob(pattern):
        if os.path.isdir(os.path.join(folder, "oslquery")) and folder not in sys.path:
            sys.path.append(folder)


# --- centre-line frames ----------------------------------------------------------------------

def _catmull_rom_neighbours(points):
    """Points with one extrapolated point before and after, as Cycles extends open curves."""
    if len(points) == 1:
        return np.repeat(points, 3, axis=0)
    return np.concatenate([2 * points[:1] - points[1:2], points, 2 * points[-1:] - points[-2:-1]])


def _segment_lengths(points):
    """Length of each uniform Catmull-Rom segment between consecutive points (4-point Gauss-Legendre)."""
    q = _catmull_rom_neighbours(points)
    p0, p1, p2, p3 = q[:-3], q[1:-2], q[2:-1], q[3:]
    nodes = (0.5 - 0.4305681558, 0.5 - 0.1699905218, 0.5 + 0.1699905218, 0.5 + 0.4305681558)
    weights = (0.1739274226, 0.3260725774, 0.3260725774, 0.1739274226)
    total = np.zeros(len(p0))
    for t, w in zip(nodes, weights):
        derivative = 0.5 * ((p2 - p0) + 2 * t * (2 * p0 - 5 * p1 + 4 * p2 - p3) + 3 * t * t * (-p0 + 3 * p1 - 3 * p2 + p3))
        total += w * np.linalg.norm(derivative, axis=1)  # weights on [0, 1] sum to 1
    return total


def curve_frames(points):
    """(arc_length (N,), reference_normal (N, 3)) at the points of one Catmull-Rom curve.

    Rotation-minimizing frames by double reflection (Wang et al. 2008), the native core's method;
    the root normal points toward the centroid of the points (a straight curve: a world axis), so
    moving or rotating the curve moves its frames with it."""
    points = np.asarray(points, dtype=np.float64)
    n = len(points)
    arc = np.zeros(n)
    if n < 2:
        return arc, np.tile([0.0, 0.0, 1.0], (n, 1))
    arc[1:] = np.cumsum(_segment_lengths(points))
    q = _catmull_rom_neighbours(points)
    tangents = q[2:] - q[:-2]
    tangents /= np.maximum(np.linalg.norm(tangents, axis=1, keepdims=True), 1e-30)

    root, t0 = points[0], tangents[0]
    r = points.mean(axis=0) - root
    r -= t0 * np.dot(r, t0)
    extent = float(np.max(points.max(axis=0) - points.min(axis=0)))
    if np.linalg.norm(r) <= 1e-3 * extent:  # straight: any axis away from the tangent
        axis = np.array([0.0, 0.0, 1.0]) if abs(t0[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
        r = axis - t0 * np.dot(axis, t0)
    normals = np.zeros((n, 3))
    normals[0] = r / np.linalg.norm(r)
    for i in range(n - 1):
        v1 = points[i + 1] - points[i]
        c1 = np.dot(v1, v1)
        if c1 < 1e-30:
            normals[i + 1] = normals[i]
            continue
        r_l = normals[i] - (2 / c1) * np.dot(v1, normals[i]) * v1
        t_l = tangents[i] - (2 / c1) * np.dot(v1, tangents[i]) * v1
        v2 = tangents[i + 1] - t_l
        c2 = np.dot(v2, v2)
        normal = r_l - (2 / c2) * np.dot(v2, r_l) * v2 if c2 > 1e-30 else r_l
        normal -= tangents[i + 1] * np.dot(normal, tangents[i + 1])
        normals[i + 1] = normal / max(np.linalg.norm(normal), 1e-30)
    return arc, normals


def curve_key_bases(context):
    """Object name -> the native curve key of its first curve: the Purl engine numbers the curves
    of all yarn sets in export order, and the fiber-migration hash depends on that number."""
    from .export import collect_yarns
    from .export.problems import Problems
    bases, key = {}, 0
    for yarn in collect_yarns(context.evaluated_depsgraph_get(), Problems()):
        bases.setdefault(yarn.source or yarn.name, key)
        key += yarn.curve_count
    return bases


def write_curve_attributes(curves, key_base=0):
    """Writes purl_arc_length and purl_reference_normal (object space) on a hair Curves datablock,
    and purl_curve_key (curve domain: key_base + curve index, exact in a float below 2^24)."""
    count = len(curves.points)
    positions = np.empty(count * 3, dtype=np.float32)
    curves.position_data.foreach_get("vector", positions)
    positions = positions.reshape(-1, 3)
    offsets = np.empty(len(curves.curves) + 1, dtype=np.int32)
    curves.curve_offset_data.foreach_get("value", offsets)
    arc = np.zeros(count, dtype=np.float32)
    normals = np.zeros((count, 3), dtype=np.float32)
    for c in range(len(offsets) - 1):
        a, b = offsets[c], offsets[c + 1]
        arc[a:b], normals[a:b] = curve_frames(positions[a:b])
    keys = key_base + np.arange(len(offsets) - 1, dtype=np.float32)
    for name, kind, domain, values, key in ((ARC_LENGTH_ATTRIBUTE, "FLOAT", "POINT", arc, "value"),
                                            (NORMAL_ATTRIBUTE, "FLOAT_VECTOR", "POINT", normals, "vector"),
                                            (CURVE_KEY_ATTRIBUTE, "FLOAT", "CURVE", keys, "value")):
        attribute = curves.attributes.get(name)
        if attribute is not None and (attribute.data_type != kind or attribute.domain != domain):
            curves.attributes.remove(attribute)
            attribute = None
        if attribute is None:
            attribute = curves.attributes.new(name, kind, domain)
        attribute.data.foreach_set(key, values.ravel())
    curves.update_tag()


# --- the material -----------------------------------------------------------------------------

def bake_maps(structure):
    """The native fiber and ply-shadowing maps of a yarn structure (purlcore.bake_yarn_maps), or
    None when the native core (or that function) is missing: the shader then uses its analytic
    fiber ring and profiles."""
    core = native.purlcore()
    if core is None or not hasattr(core, "bake_yarn_maps"):
        return None
    names = {p["name"] for p in core.yarn_parameters()}
    yarn = {k: float(_scalar(v)) for k, v in structure.items() if k in names}
    if "preset" in structure:
        yarn["preset"] = structure["preset"]
    return core.bake_yarn_maps(yarn)


def _maps_block(maps):
    """The shader's map block: the baked arrays as OSL constants (one macro line)."""
    fiber = np.asarray(maps["fiber"], dtype=np.float64)
    variants, resolution = fiber.shape[0], fiber.shape[1]

    def array(name, values):
        values = np.asarray(values).ravel()
        return "float {}[{}] = {{{}}};".format(name, len(values), ",".join("{:.6g}".format(v) for v in values))

    data = " ".join([array("purl_fiber_normal", fiber[..., 0]), array("purl_fiber_phase", fiber[..., 1]),
                     array("purl_fiber_distance", fiber[..., 2]), array("purl_fiber_shadow", fiber[..., 3]),
                     array("purl_ply_map", maps["ply_shadowing"])])
    return "{}#define PURL_MAP_RESOLUTION {}\n#define PURL_MAP_VARIANTS {}\n#define PURL_MAP_DATA {}\n{}".format(
        MAPS_BEGIN, resolution, variants, data, MAPS_END)


def shader_text(maps=None):
    """The shader as a Text datablock (INTERNAL script: the .blend holds it, no absolute path),
    with the baked maps of one yarn structure written in (one text per distinct structure)."""
    with open(SHADER_PATH, encoding="utf-8") as f:
        source = f.read()
    name = SHADER_TEXT_NAME
    if maps is not None:
        start, end = source.index(MAPS_BEGIN), source.index(MAPS_END) + len(MAPS_END)
        source = source[:start] + _maps_block(maps) + source[end:]
        digest = hashlib.sha1(source.encode("utf-8")).hexdigest()[:8]
        name = "{} {}.osl".format(SHADER_TEXT_NAME[:-4], digest)
    text = bpy.data.texts.get(name) or bpy.data.texts.new(name)
    if text.as_string() != source:
        text.clear()
        text.write(source)
    return text


def structure_defaults():
    """Yarn structure inputs from the native yarn description's defaults (prototype yarn)."""
    core = native.purlcore()
    if core is None:
        return {}
    return {p["name"]: p["default"] for p in core.yarn_parameters() if p["name"] in STRUCTURE_INPUTS}


def _scalar(value):
    return float(value[0] if isinstance(value, (list, tuple)) else value)


def _set_input(socket, value):
    if isinstance(socket.default_value, (int, float)):
        socket.default_value = type(socket.default_value)(round(_scalar(value)) if isinstance(
            socket.default_value, int) else _scalar(value))
    else:
        values = list(value) if isinstance(value, (list, tuple)) or hasattr(value, "__len__") else [value] * 3
        socket.default_value = (list(values) + [1.0] * 4)[:len(socket.default_value)]


def _drive(node_tree, socket, material, data_path, components):
    """A driver copying material[data_path] onto the socket (a simple expression: it runs even
    where Python drivers are disabled)."""
    target_path = socket.path_from_id("default_value")
    node_tree.driver_remove(target_path)
    indices = range(components) if components > 1 else [-1]
    for index in indices:
        fcurve = node_tree.driver_add(target_path, index) if index >= 0 else node_tree.driver_add(target_path)
        driver = fcurve.driver
        driver.type = "SCRIPTED"
        driver.expression = "v"
        variable = driver.variables.new()
        variable.name = "v"
        variable.type = "SINGLE_PROP"
        variable.targets[0].id_type = "MATERIAL"
        variable.targets[0].id = material
        variable.targets[0].data_path = data_path + ("[{}]".format(index) if index >= 0 else "")


def build_material(material, structure=None, use_drivers=True):
    """Builds the Cycles node tree of a Purl material: Script node + Attribute nodes -> Output.

    `structure` overrides the yarn structure inputs (ply_count, ...); the appearance inputs are
    the material's Purl settings (model "bysdf"), driven so later edits and presets carry over.
    Cycles must be the scene's render engine (it compiles the shader). Returns the Script node."""
    _make_oslquery_importable()
    compat.enable_nodes(material)
    tree = material.node_tree
    nodes, links = tree.nodes, tree.links
    for node in [n for n in nodes if n.name.startswith("Purl ")]:
        nodes.remove(node)
    output = next((n for n in nodes if n.bl_idname == "ShaderNodeOutputMaterial"), None)
    if output is None:
        output = nodes.new("ShaderNodeOutputMaterial")

    values = dict(structure_defaults())
    values.update(structure or {})
    script = nodes.new("ShaderNodeScript")
    script.name = script.label = SCRIPT_NODE_NAME
    script.mode = "INTERNAL"
    script.script = shader_text(bake_maps(values))
    script.location = (output.location.x - 300, output.location.y)
    if "BSDF" not in script.outputs:  # compilation failed: Cycles' OSL is missing or the shader is broken
        raise RuntimeError("the Purl OSL shader did not compile in this Blender ({}); see the console".format(
            bpy.app.version_string))

    def attribute_node(name, attribute, socket, location_y, output_name):
        node = nodes.new("ShaderNodeAttribute")
        node.name = node.label = name
        node.attribute_type = "GEOMETRY"
        node.attribute_name = attribute
        node.location = (script.location.x - 250, location_y)
        links.new(node.outputs[output_name], script.inputs[socket])

    attribute_node("Purl arc length", ARC_LENGTH_ATTRIBUTE, "arc_length", script.location.y, "Fac")
    attribute_node("Purl reference normal", NORMAL_ATTRIBUTE, "reference_normal", script.location.y - 180, "Vector")
    attribute_node("Purl curve key", CURVE_KEY_ATTRIBUTE, "curve_key", script.location.y - 360, "Fac")
    settings = getattr(material, "purl", None)
    if settings is not None and settings.color_attribute:
        attribute_node("Purl yarn colour", settings.color_attribute, "yarn_color", script.location.y - 540, "Color")

    for name, value in values.items():
        if name in script.inputs:
            _set_input(script.inputs[name], value)

    params = getattr(settings, "params_bysdf", None) if settings is not None else None
    if params is not None:
        # The artist controls (yarn colour, sheen, ...) folded into the physics values by the
        # native rule; a value they change is set as it is, the others stay driven.
        core = native.purlcore()
        resolved = core.resolve_material(yarn_material(material, None)) if hasattr(core, "resolve_material") else {}
        for parameter in parameters.parameters("bysdf"):
            name = parameter["name"]
            if name not in script.inputs:
                continue
            socket = script.inputs[name]
            physics = [float(v) for v in np.ravel(getattr(params, name))]
            value = [float(v) for v in np.ravel(resolved.get(name, physics))]
            _set_input(socket, value[0] if parameter["components"] == 1 else value)
            if use_drivers and np.allclose(value, physics, rtol=1e-6, atol=1e-7):
                _drive(tree, socket, material, "purl.params_bysdf." + name, int(parameter["components"]))
    links.new(script.outputs["BSDF"], output.inputs["Surface"])
    # The shader's Displacement output makes Cycles run it as the material's bump pass, where it
    # sets the shading normal of the hit to the fiber normal (see the shader and docs/osl.md).
    if hasattr(material, "displacement_method"):  # Blender 4.1+; before, a Cycles material setting
        material.displacement_method = "BUMP"
    elif hasattr(getattr(material, "cycles", None), "displacement_method"):
        material.cycles.displacement_method = "BUMP"
    links.new(script.outputs["Displacement"], output.inputs["Displacement"])
    return script


def setup_objects(context, objects, structure=None):
    """Writes the curve attributes and builds the materials of `objects`; returns (done, skipped)
    with a reason per skipped object. Switches the scene to Cycles with OSL on the CPU."""
    ok, reason = osl_available()
    if not ok:
        raise RuntimeError(reason)
    # Cycles compiles a Script node only while it is the scene's engine (RenderEngine.update_script_node).
    scene = context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.shading_system = True
    # The shader models a round tube: P on it and N its normal, at P's own cross-section. Ribbons
    # (the default) put P on a flat strip through the centre-line, about a yarn radius deeper
    # along the view ray, so the plies and fibers were looked up at the wrong cross-section.
    scene.cycles_curves.shape = "THICK"
    done, skipped, materials = [], [], []
    bases = curve_key_bases(context)
    for ob in objects:
        if ob.type not in {"CURVES"}:
            skipped.append((ob.name, "only hair Curves objects carry the attributes the shader reads "
                            "(convert curve objects and particle hair to Curves)"))
            continue
        write_curve_attributes(ob.data, bases.get(ob.name, 0))
        for material in ob.data.materials:
            if material is not None and material not in materials:
                materials.append(material)
        if not ob.data.materials:
            material = bpy.data.materials.new(ob.name + " yarn")
            ob.data.materials.append(material)
            materials.append(material)
        done.append(ob.name)
    for material in materials:
        build_material(material, structure)
    return done, skipped


class PURL_OT_setup_cycles(bpy.types.Operator):
    """Give the selected yarn (hair Curves) objects the Purl look in Cycles with the OSL shader"""
    bl_idname = "purl.setup_cycles"
    bl_label = "Set up for Cycles"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        objects = list(context.selected_objects) or ([context.active_object] if context.active_object else [])
        try:
            done, skipped = setup_objects(context, objects)
        except RuntimeError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        for name, reason in skipped:
            self.report({"WARNING"}, "{}: {}".format(name, reason))
        if not done:
            self.report({"ERROR"}, "no hair Curves object selected")
            return {"CANCELLED"}
        self.report({"INFO"}, "Purl OSL shader set up on {}".format(", ".join(done)))
        return {"FINISHED"}


def register():
    bpy.utils.register_class(PURL_OT_setup_cycles)


def unregister():
    bpy.utils.unregister_class(PURL_OT_setup_cycles)
