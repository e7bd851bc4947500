"""Small builders for test scenes: cameras, lights, curves, planes."""
import os
import subprocess
from importlib import import_module

import bpy
import pytest

from exr import read_channels

# The add-on's Blender-version helpers (multilayer EXR settings, node trees on 5.0).
compat = import_module(os.environ["PURL_ADDON_PACKAGE"] + ".compat")


def link(scene, ob):
    scene.collection.objects.link(ob)
    return ob


def add_camera(scene, location, rotation, **settings):
    data = bpy.data.cameras.new("Camera")
    for key, value in settings.items():
        setattr(data, key, value)
    ob = link(scene, bpy.data.objects.new("Camera", data))
    ob.location, ob.rotation_euler = location, rotation
    scene.camera = ob
    return ob


def add_light(scene, kind, name=None, **settings):
    data = bpy.data.lights.new(name or kind.title(), kind)
    for key, value in settings.items():
        setattr(data, key, value)
    return link(scene, bpy.data.objects.new(name or kind.title(), data))


def add_curve(scene, name, splines, bevel_depth=0.05):
    """A curve object from [(type, points, options)]: points are (x, y, z) knots (Bezier gets
    automatic handles), options may set radius (list), cyclic, order, endpoint, weights."""
    data = bpy.data.curves.new(name, "CURVE")
    data.dimensions = "3D"
    data.bevel_depth = bevel_depth
    for kind, points, options in splines:
        spline = data.splines.new(kind)
        radii = options.get("radius", [1.0] * len(points))
        if kind == "BEZIER":
            spline.bezier_points.add(len(points) - 1)
            for point, co, radius in zip(spline.bezier_points, points, radii):
                point.co = co
                point.handle_left_type = point.handle_right_type = "AUTO"
                point.radius = radius
        else:
            spline.points.add(len(points) - 1)
            weights = options.get("weights", [1.0] * len(points))
            for point, co, radius, weight in zip(spline.points, points, radii, weights):
                point.co = (*co, weight)
                point.radius = radius
            if kind == "NURBS":
                spline.order_u = options.get("order", 4)
                spline.use_endpoint_u = options.get("endpoint", False)
        spline.use_cyclic_u = options.get("cyclic", False)
    return link(scene, bpy.data.objects.new(name, data))


def add_plane(scene, name="Plane", size=2.0, location=(0.0, 0.0, 0.0)):
    half = size / 2.0
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(-half, -half, 0), (half, -half, 0), (half, half, 0), (-half, half, 0)], [],
                     [(0, 1, 2, 3)])
    ob = link(scene, bpy.data.objects.new(name, mesh))
    ob.location = location
    return ob


def depsgraph():
    graph = bpy.context.evaluated_depsgraph_get()
    graph.update()
    return graph


def save_render_result(scene, path):
    """Saves Blender's Render Result as a 32-bit multilayer EXR and reads it back: {channel: array}."""
    settings = scene.render.image_settings
    compat.set_multilayer_exr(settings)
    settings.exr_codec, settings.color_depth = "NONE", "32"
    bpy.data.images["Render Result"].save_render(str(path), scene=scene)
    return read_channels(str(path))


def render_saved_file(purl, tmp_path, *arguments):
    """Saves the open file and renders frame 1 of it in a `blender -b` child with the add-on
    enabled, output to tmp_path/out_0001.*; skips where there is no blender binary (the bpy
    module). Returns the finished process."""
    binary = bpy.app.binary_path
    if not binary or not os.path.basename(binary).startswith("blender"):
        pytest.skip("needs the blender binary (the bpy module has none)")
    blend = tmp_path / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend), copy=True)
    scripts = tmp_path / "scripts"
    (scripts / "addons").mkdir(parents=True)
    os.symlink(os.path.dirname(purl.__file__), scripts / "addons" / "purl")
    env = dict(os.environ, BLENDER_USER_SCRIPTS=str(scripts))
    return subprocess.run([binary, "-b", str(blend), "--addons", "purl", "-E", "PURL",
                           "-o", str(tmp_path / "out_####"), *arguments, "-f", "1"],
                          env=env, capture_output=True, text=True, timeout=300)
