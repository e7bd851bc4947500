"""Camera, film, lights, world and meshes: exported values match Blender's, and points projected
through Purl's camera convention land where Blender's own projection puts them (< 0.01 px)."""
import math
from importlib import import_module

import bpy
import numpy as np
import pytest
from mathutils import Vector

from builders import add_camera, add_light, add_plane, compat, depsgraph
from curve_math import placed_arrays


def export(purl):
    return import_module(purl.__name__ + ".export").export_scene(depsgraph())


# --- camera --------------------------------------------------------------------------------

def blender_projection(scene, camera_object, points):
    """Pixel positions (x right, y down from the top-left corner) by Blender's own matrices."""
    render = scene.render
    width = render.resolution_x * render.resolution_percentage // 100
    height = render.resolution_y * render.resolution_percentage // 100
    projection = camera_object.calc_matrix_camera(depsgraph(), x=width, y=height,
                                                  scale_x=render.pixel_aspect_x,
                                                  scale_y=render.pixel_aspect_y)
    view = camera_object.matrix_world.normalized().inverted()
    result = []
    for p in points:
        clip = projection @ view @ Vector((*p, 1.0))
        ndc_x, ndc_y = clip.x / clip.w, clip.y / clip.w
        result.append(((ndc_x + 1.0) * 0.5 * width, (1.0 - ndc_y) * 0.5 * height))
    return np.array(result)


def purl_projection(camera, film, points):
    """Purl's camera convention (docs/scene-format.md), written out from the exported values only:
    Blender's view plane with sensor fit, pixel aspect and shift in units of the fitted side."""
    width, height = film["width"], film["height"]
    aspect_x, aspect_y = film["pixel_aspect_x"], film["pixel_aspect_y"]
    fit = camera["sensor_fit"]
    sensor = camera["sensor_height"] if fit == "VERTICAL" else camera["sensor_width"]
    if fit == "AUTO":
        fit = "HORIZONTAL" if aspect_x * width >= aspect_y * height else "VERTICAL"
    y_correction = aspect_y / aspect_x
    fitted_side = width if fit == "HORIZONTAL" else y_correction * height
    pixels_per_unit = camera["lens"] / sensor * fitted_side  # on the plane at distance 1
    to_world = np.array(camera["matrix_world"]).reshape(4, 4)
    to_camera = np.linalg.inv(to_world)
    result = []
    for p in points:
        x, y, z = (to_camera @ np.array([*p, 1.0]))[:3]
        plane_x, plane_y = x / -z * pixels_per_unit, y / -z * pixels_per_unit
        px = plane_x + 0.5 * width - camera["shift_x"] * fitted_side
        py_up = (plane_y + 0.5 * y_correction * height - camera["shift_y"] * fitted_side) / y_correction
        result.append((px, height - py_up))
    return np.array(result)


CAMERA_CASES = [
    # (resolution, pixel aspect, sensor_fit, shift)
    ((64, 48), (1.0, 1.0), "AUTO", (0.0, 0.0)),
    ((48, 64), (1.0, 1.0), "AUTO", (0.1, -0.2)),
    ((80, 40), (1.0, 1.0), "HORIZONTAL", (0.3, 0.05)),
    ((40, 80), (1.0, 1.0), "HORIZONTAL", (-0.1, 0.2)),
    ((80, 40), (1.0, 1.0), "VERTICAL", (0.2, 0.1)),
    ((64, 64), (2.0, 1.0), "AUTO", (0.05, 0.05)),
    ((60, 50), (1.0, 1.6), "VERTICAL", (-0.2, -0.1)),
    ((50, 60), (1.3, 1.0), "HORIZONTAL", (0.0, 0.3)),
]


@pytest.mark.parametrize("resolution, aspect, fit, shift", CAMERA_CASES)
def test_purl_camera_projects_like_blender(purl, scene, resolution, aspect, fit, shift):
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.pixel_aspect_x, scene.render.pixel_aspect_y = aspect
    cam = add_camera(scene, location=(0.7, -5.0, 1.2), rotation=(1.35, 0.05, 0.2), lens=42.0,
                     sensor_width=32.0, sensor_height=20.0, sensor_fit=fit, shift_x=shift[0],
                     shift_y=shift[1])
    cam.scale = (1.0, 2.0, 0.5)  # Blender ignores the camera's scale
    add_plane(scene)
    rng = np.random.default_rng(7)
    points = rng.uniform(-1.0, 1.0, size=(20, 3))
    exported = export(purl)
    expected = blender_projection(scene, cam, points)
    got = purl_projection(exported.scene["camera"], exported.scene["film"], points)
    assert np.abs(got - expected).max() < 0.01


def test_native_camera_projects_like_blender(purl, core, scene):
    if not hasattr(core, "project_points"):
        pytest.skip("purlcore.project_points(scene, points) is not there yet (asked of the native module)")
    for resolution, aspect, fit, shift in CAMERA_CASES:
        scene.render.resolution_x, scene.render.resolution_y = resolution
        scene.render.pixel_aspect_x, scene.render.pixel_aspect_y = aspect
        cam = add_camera(scene, location=(0.7, -5.0, 1.2), rotation=(1.35, 0.05, 0.2),
                         sensor_fit=fit, shift_x=shift[0], shift_y=shift[1])
        add_plane(scene)
        points = np.random.default_rng(3).uniform(-1.0, 1.0, size=(20, 3)).astype(np.float32)
        exported = export(purl)
        got = np.asarray(core.project_points(exported.scene, points))
        assert np.abs(got - blender_projection(scene, cam, points)).max() < 0.01, (fit, shift)


def test_orthographic_camera_is_reported(purl, scene):
    scene.camera.data.type = "ORTHO"
    add_plane(scene)
    exported = export(purl)
    assert "camera" not in exported.scene and not exported.renderable
    assert any("perspective" in m for m in exported.problems.messages("ERROR"))


def test_film_size_percentage_and_transparency(purl, scene):
    scene.render.resolution_x, scene.render.resolution_y = 1001, 333
    scene.render.resolution_percentage = 50
    scene.render.film_transparent = True
    add_plane(scene)
    film = export(purl).scene["film"]
    assert (film["width"], film["height"], film["transparent"]) == (500, 166, True)


def test_render_settings_carry_the_multiscale_mode(purl, core, scene):
    add_plane(scene)
    assert export(purl).scene["render"]["multiscale"]["mode"] == "auto"  # the default
    scene.purl.multiscale_mode = "FAR"
    render = export(purl).scene["render"]
    assert render["multiscale"]["mode"] == "far" and render["multiscale"]["mode"] in core.multiscale_modes()


def test_render_settings_carry_the_ply_method(purl, core, scene):
    add_plane(scene)
    assert export(purl).scene["render"]["ply_method"] == "elliptical"  # the default
    items = [item.identifier for item in scene.purl.bl_rna.properties["ply_method"].enum_items]
    assert [i.lower() for i in items] == core.ply_methods()
    scene.purl.ply_method = "LOCAL"
    assert export(purl).scene["render"]["ply_method"] == "local"


# --- lights --------------------------------------------------------------------------------

def test_lights_carry_cycles_values(purl, scene):
    add_plane(scene)
    add_light(scene, "POINT", energy=100.0, shadow_soft_size=0.25, color=(1.0, 0.5, 0.25))
    add_light(scene, "SPOT", energy=50.0, spot_size=0.8, spot_blend=0.3, shadow_soft_size=0.1)
    add_light(scene, "SUN", energy=3.0, angle=0.05)
    area = add_light(scene, "AREA", name="Rect", energy=20.0, shape="RECTANGLE", size=2.0, size_y=0.5)
    area.scale = (2.0, 3.0, 1.0)
    square = add_light(scene, "AREA", name="Square", energy=10.0, shape="SQUARE", size=1.0)
    square.scale = (1.0, 2.0, 1.0)
    lights = export(purl).scene["lights"]
    # Area power is converted from Cycles 4.x's P / (pi A) radiance to Purl's P / (4 A).
    area_factor = import_module(purl.__name__ + ".export.lights").AREA_POWER_FACTOR
    for light in lights:
        if light["type"] == "area":
            light["power"] = round(light["power"] / area_factor, 4)
    by_power = {light.get("power", light.get("strength")): light for light in lights}
    point, spot, sun, rect, stretched = (by_power[p] for p in (100.0, 50.0, 3.0, 20.0, 10.0))
    assert point["type"] == "point" and point["radius"] == pytest.approx(0.25)
    assert point["color"] == pytest.approx([1.0, 0.5, 0.25])
    assert spot["spot_size"] == pytest.approx(0.8) and spot["spot_blend"] == pytest.approx(0.3)
    assert spot["radius"] == pytest.approx(0.1)
    assert sun["type"] == "sun" and sun["angle"] == pytest.approx(0.05)
    # Area sizes take the object's scale; a square scaled unevenly becomes a rectangle.
    assert rect["shape"] == "RECTANGLE"
    assert (rect["size"], rect["size_y"]) == pytest.approx((4.0, 1.5))
    assert stretched["shape"] == "RECTANGLE"
    assert (stretched["size"], stretched["size_y"]) == pytest.approx((1.0, 2.0))
    # Placement matrices keep rotation and translation only.
    m = np.array(rect["matrix_world"]).reshape(4, 4)
    assert np.linalg.norm(m[:3, :3], axis=0) == pytest.approx([1.0, 1.0, 1.0])
    assert m[:3, 3] == pytest.approx(list(area.matrix_world.translation))


def test_light_exposure_and_unnormalized_power_follow_blender(purl, scene):
    light = add_light(scene, "AREA", energy=10.0, shape="DISK", size=2.0)
    if not hasattr(light.data, "exposure"):
        pytest.skip("exposure and normalize arrived in Blender 4.5")
    add_plane(scene)
    light.data.exposure = 1.0
    light.data.normalize = False
    (exported,) = export(purl).scene["lights"]
    unnormalized = 10.0 * 2.0 * (2.0 * 2.0 * math.pi / 4.0)
    assert exported["power"] == pytest.approx(unnormalized * 4.0 / math.pi, rel=1e-5)  # and 4.x's area radiance


# --- world ---------------------------------------------------------------------------------

def test_world_background_colour_and_strength(purl, scene):
    add_plane(scene)
    world = scene.world
    compat.enable_nodes(world)
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (0.2, 0.3, 0.4, 1.0)
    background.inputs["Strength"].default_value = 2.5
    exported = export(purl).scene["world"]
    assert exported["color"] == pytest.approx([0.2, 0.3, 0.4]) and exported["strength"] == pytest.approx(2.5)


def test_world_environment_texture_path_and_rotation(purl, scene, tmp_path):
    add_plane(scene)
    image = bpy.data.images.new("env", 8, 4, float_buffer=True)
    image.filepath_raw = str(tmp_path / "env.exr")
    image.file_format = "OPEN_EXR"
    image.save()
    world = scene.world
    compat.enable_nodes(world)
    tree = world.node_tree
    texture = tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image = image
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, 0.75)
    tree.links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    tree.links.new(texture.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    exported = export(purl).scene["world"]
    assert exported["texture"] == str(tmp_path / "env.exr")
    assert exported["rotation_z"] == pytest.approx(0.75)
    assert exported["color"] == [1.0, 1.0, 1.0]


# --- meshes --------------------------------------------------------------------------------

def test_mesh_triangles_colour_and_holdout(purl, scene):
    plane = add_plane(scene, size=2.0, location=(0.0, 0.0, 1.0))
    material = bpy.data.materials.new("Red")
    compat.enable_nodes(material)
    material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.9, 0.1, 0.1, 1.0)
    plane.data.materials.append(material)
    occluder = add_plane(scene, name="Occluder", size=1.0)
    occluder.is_holdout = True
    exported = export(purl)
    meshes = {m["name"]: m for m in exported.scene["meshes"]}
    red = meshes["Plane"]
    arrays = placed_arrays(exported, red)
    assert red["color"] == pytest.approx([0.9, 0.1, 0.1]) and not red["holdout"]
    assert arrays["triangles"].shape == (2, 3)
    np.testing.assert_allclose(arrays["vertices"][:, 2], 1.0)
    assert meshes["Occluder"]["holdout"] is True


def test_curve_bevel_tube_is_not_exported_as_a_mesh(purl, scene):
    data = bpy.data.curves.new("Yarn", "CURVE")
    data.bevel_depth = 0.05
    spline = data.splines.new("POLY")
    spline.points.add(1)
    spline.points[1].co = (1.0, 0.0, 0.0, 1.0)
    scene.collection.objects.link(bpy.data.objects.new("Yarn", data))
    exported = export(purl)
    assert [y["name"] for y in exported.scene["yarns"]] == ["Yarn"]
    assert exported.scene["meshes"] == []
