"""The Fig. 7 single-yarn scenes (scenes/fig7/*.json) rebuilt in Blender for Cycles + the Purl
OSL shader, and the same scene for the native core with the same centre-line, so the two
renders can be compared pixel for pixel (tests/blender/test_osl.py, bench/osl_compare.py)."""
import copy
import json
import os

import bpy
import numpy as np
from mathutils import Vector

from builders import compat
from exr import read_channels

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FIG7 = os.path.join(REPO, "scenes", "fig7")


def load_scene(plies, lighting):
    with open(os.path.join(FIG7, "yarn_{}ply_{}.json".format(plies, lighting)), encoding="utf-8") as f:
        return json.load(f)


def bspline_points_on_curve(core, bcc_path, radius, per_segment=2):
    """Points on the native core's B-spline centre-line (load_bcc), `per_segment` per segment:
    a Catmull-Rom curve through them follows the native curve closely. One curve per list."""
    data = core.load_bcc(bcc_path, radius)
    control, first = np.asarray(data["points"], dtype=np.float64), np.asarray(data["segments"])
    seg_offsets = np.asarray(data["segment_offsets"])
    curves = []
    for c in range(len(seg_offsets) - 1):
        samples = []
        segments = range(seg_offsets[c], seg_offsets[c + 1])
        for k, segment in enumerate(segments):
            p0, p1, p2, p3 = control[first[segment]:first[segment] + 4]
            ts = np.arange(per_segment + (1 if k == len(segments) - 1 else 0)) / per_segment
            for t in ts:
                b = ((1 - t) ** 3, 3 * t ** 3 - 6 * t ** 2 + 4, -3 * t ** 3 + 3 * t ** 2 + 3 * t + 1, t ** 3)
                samples.append((b[0] * p0 + b[1] * p1 + b[2] * p2 + b[3] * p3) / 6.0)
        curves.append(np.array(samples))
    return curves


def _place(ob, position, look_at):
    ob.location = Vector(position)
    direction = Vector(look_at) - Vector(position)
    ob.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()


def yarn_structure(description):
    """Shader structure inputs from a scene's material "yarn" object (prototype + overrides)."""
    structure = {}
    for key, value in description.items():
        if key != "preset":
            structure[key] = value
    return structure


def build_blender_scene(scene, core, json_scene, samples):
    """Camera, area lights, black world and the yarn as a hair Curves object, Cycles settings
    for the comparison; returns the yarn object. `scene` is emptied by the caller."""
    from importlib import import_module
    purl_setup = import_module(os.environ["PURL_ADDON_PACKAGE"] + ".cycles_setup")
    film, camera = json_scene["film"], json_scene["camera"]
    scene.render.resolution_x, scene.render.resolution_y = film["width"], film["height"]
    scene.render.resolution_percentage = 100
    cam = bpy.data.cameras.new("Camera")
    cam.lens = camera.get("lens", 50)
    cam.clip_start = camera.get("clip_start", 0.1)
    cam_ob = bpy.data.objects.new("Camera", cam)
    scene.collection.objects.link(cam_ob)
    _place(cam_ob, camera["position"], camera["look_at"])
    scene.camera = cam_ob
    # Purl's area light has radiance P / (4 A), Cycles 4.x's P / (pi A) (3.x's as Purl's): undo
    # the add-on's export factor, so both renderers get the same light.
    area_power_factor = import_module(os.environ["PURL_ADDON_PACKAGE"] + ".export.lights").AREA_POWER_FACTOR
    for i, light in enumerate(json_scene["lights"]):
        data = bpy.data.lights.new("Light{}".format(i), "AREA")
        data.shape = light.get("shape", "SQUARE")
        data.size = light["size"]
        data.energy = light["power"] / area_power_factor
        data.color = light.get("color", (1, 1, 1))
        ob = bpy.data.objects.new(data.name, data)
        scene.collection.objects.link(ob)
        _place(ob, light["position"], light["look_at"])
    world = scene.world or bpy.data.worlds.new("World")
    scene.world = world
    world.color = json_scene["world"]["color"]
    if compat.uses_nodes(world) and "Background" in world.node_tree.nodes:
        world.node_tree.nodes["Background"].inputs["Color"].default_value = list(json_scene["world"]["color"]) + [1]

    yarn = json_scene["yarns"][0]
    curves_points = bspline_points_on_curve(core, os.path.join(FIG7, yarn["bcc"]), yarn["radius"])
    data = bpy.data.hair_curves.new("Yarn")
    data.add_curves([len(p) for p in curves_points])
    points = np.concatenate(curves_points).astype(np.float32)
    data.position_data.foreach_set("vector", points.ravel())
    radius = data.attributes.get("radius") or data.attributes.new("radius", "FLOAT", "POINT")
    radius.data.foreach_set("value", np.full(len(points), yarn["radius"], np.float32))
    ob = bpy.data.objects.new("Yarn", data)
    scene.collection.objects.link(ob)

    material = bpy.data.materials.new("Yarn")
    params = material.purl.params_bysdf
    for name, value in yarn["material"].items():
        if hasattr(params, name):
            setattr(params, name, value)
    data.materials.append(material)
    purl_setup.setup_objects(bpy.context, [ob], yarn_structure(yarn["material"]["yarn"]))

    cycles = scene.cycles
    cycles.samples = samples
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.max_bounces = json_scene["render"].get("max_depth", 8)
    cycles.diffuse_bounces = cycles.glossy_bounces = cycles.transmission_bounces = cycles.max_bounces
    cycles.transparent_max_bounces = 16
    cycles.caustics_reflective = cycles.caustics_refractive = True
    cycles.blur_glossy = 0.0
    cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0.0
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0
    cycles.seed = int(os.environ.get("PURL_OSL_SEED", "1"))
    scene.view_settings.view_transform = "Standard"
    scene.render.film_transparent = True
    return ob, curves_points


def native_scene(json_scene, curves_points, spp):
    """The same scene for purlcore.render: the yarn as Catmull-Rom arrays through the same points
    (end points repeated: the native Catmull-Rom skips the first and last, Cycles does not)."""
    scene = copy.deepcopy(json_scene)
    yarn = scene["yarns"][0]
    points, offsets = [], [0]
    for p in curves_points:
        padded = np.concatenate([p[:1], p, p[-1:]])
        points.append(padded)
        offsets.append(offsets[-1] + len(padded))
    points = np.concatenate(points).astype(np.float32)
    del yarn["bcc"]
    yarn["arrays"] = "yarn"
    # The shader implements the paper's ply crossing (tau^N_i and G_p, docs/osl.md), not the
    # native default's traced one: compare like with like.
    yarn.setdefault("material", {})["ply_crossing"] = 0
    scene["render"]["spp"] = spp
    arrays = {"yarn": {"points": points, "radii": np.full(len(points), yarn.pop("radius"), np.float32),
                       "offsets": np.asarray(offsets, np.int32), "closed": np.zeros(len(offsets) - 1, bool),
                       "basis": "catmull_rom"}}
    return scene, arrays


def render_shader_outputs(scene, yarn_object, outputs, path, offset=0.0):
    """Renders up to three float outputs of the yarn's Purl Script node as an emission colour
    (plus `offset`, as emission must not be negative), 1 spp; returns (values (H, W, len(outputs)),
    alpha (H, W)), rows top to bottom. Cycles' OSL backend does not write shader AOVs (its AOV
    output node is not compiled for OSL), hence this detour. The material is restored after."""
    from importlib import import_module
    script_name = import_module(os.environ["PURL_ADDON_PACKAGE"] + ".cycles_setup").SCRIPT_NODE_NAME
    restore = []
    for material in yarn_object.data.materials:
        tree = material.node_tree
        script = tree.nodes[script_name]
        output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
        combine = tree.nodes.new("ShaderNodeCombineXYZ")
        emission = tree.nodes.new("ShaderNodeEmission")
        for name, socket in zip(outputs, combine.inputs):
            add = tree.nodes.new("ShaderNodeMath")
            add.inputs[1].default_value = offset
            tree.links.new(script.outputs[name], add.inputs[0])
            tree.links.new(add.outputs[0], socket)
        tree.links.new(combine.outputs[0], emission.inputs["Color"])
        tree.links.new(emission.outputs[0], output.inputs["Surface"])
        restore.append((tree, script, output, [n for n in tree.nodes if n.bl_idname in
                                                ("ShaderNodeCombineXYZ", "ShaderNodeEmission", "ShaderNodeMath")]))
    samples = scene.cycles.samples
    scene.cycles.samples = 1
    try:
        rgba = render_cycles(scene, path)["Combined"]
    finally:
        scene.cycles.samples = samples
        for tree, script, output, added in restore:
            for node in added:
                tree.nodes.remove(node)
            tree.links.new(script.outputs["BSDF"], output.inputs["Surface"])
    return rgba[..., :len(outputs)] - offset, rgba[..., 3]


def render_cycles(scene, path):
    """Renders with Cycles to an uncompressed multilayer EXR; returns {pass: (H, W, C) float32},
    rows top to bottom: "Combined" (linear RGBA) and any AOVs."""
    scene.render.filepath = path
    compat.set_multilayer_exr(scene.render.image_settings)
    scene.render.image_settings.exr_codec = "NONE"  # the add-on's reader reads uncompressed files only
    bpy.ops.render.render(write_still=True)
    prefix = scene.view_layers[0].name + "."
    planes = read_channels(path)
    passes = {}
    for channel in sorted(planes):
        if channel.startswith(prefix):
            passes.setdefault(channel[len(prefix):].rsplit(".", 1)[0], []).append(channel)
    result = {name: np.stack([planes[c] for c in channels], axis=-1) for name, channels in passes.items()}
    result["Combined"] = np.stack([planes[prefix + "Combined." + c] for c in "RGBA"], axis=-1)
    return result
