"""Composite back into Cycles: one render in which Cycles draws the scene without the yarns, Purl
the yarns with meshes as holdouts, laid one over the other by the add-on."""

import bpy
import numpy as np
import pytest

from builders import add_curve, add_light, add_plane, compat, render_saved_file, save_render_result
from exr import read_channels

LAYER = "ViewLayer"
GREEN = (0.0, 1.0, 0.0)
BACKGROUND = (0.0, 0.0, 0.25)


def emission_material(name, color):
    material = bpy.data.materials.new(name)
    compat.enable_nodes(material)
    tree = material.node_tree
    tree.nodes.clear()
    emission = tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (*color, 1.0)
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
    return material


def composite_scene(scene):
    """A yarn across the view at z = 0 and a green emitting card in front of its left half."""
    add_curve(scene, "Yarn", [("POLY", [(-3.0, 0.0, 0.0), (3.0, 0.0, 0.0)], {})], bevel_depth=0.15)
    card = add_plane(scene, "Card", size=1.0, location=(-1.2, -1.0, 0.0))
    card.rotation_euler = (1.5707963, 0.0, 0.0)  # facing the camera
    card.scale = (2.0, 1.5, 1.0)
    card.data.materials.append(emission_material("Green", GREEN))
    add_light(scene, "SUN", energy=4.0).rotation_euler = (0.5, 0.0, 0.0)
    compat.enable_nodes(scene.world)
    background = next(n for n in scene.world.node_tree.nodes if n.bl_idname == "ShaderNodeBackground")
    background.inputs["Color"].default_value = (*BACKGROUND, 1.0)
    scene.view_layers[0].name = LAYER
    scene.purl.use_cycles_composite = True
    scene.purl.cycles_samples = 16
    return scene


def render_channels(scene, path):
    assert bpy.ops.render.render() == {"FINISHED"}
    return save_render_result(scene, path)


def check_composite(channels, width, height):
    rgb = np.stack([channels[LAYER + ".Combined." + c] for c in "RGB"], axis=-1)
    yarn_id = channels[LAYER + ".YarnID.X"]
    assert rgb.shape == (height, width, 3)
    centre = height // 2
    card_columns = slice(2, width * 3 // 10)       # the card covers x < ~0.3 of the width
    open_columns = slice(width * 6 // 10, width - 2)
    # Where the card is in front, its Cycles emission shows and the yarn is cut out.
    card = rgb[centre - 2:centre + 3, card_columns].reshape(-1, 3)
    assert np.allclose(card.mean(axis=0), GREEN, atol=0.08), card.mean(axis=0)
    assert not (yarn_id[centre - 2:centre + 3, card_columns] > 0).any()
    # Where nothing is in front, the yarn is Purl's (lit, not the background colour).
    yarn = rgb[centre - 1:centre + 2, open_columns].reshape(-1, 3)
    assert (yarn_id[centre - 1:centre + 2, open_columns] > 0).all()
    assert np.abs(yarn.mean(axis=0) - BACKGROUND).max() > 0.05, yarn.mean(axis=0)
    # Above the yarn and beside the card, Cycles' world.
    sky = rgb[2:5, open_columns].reshape(-1, 3)
    assert np.allclose(sky.mean(axis=0), BACKGROUND, atol=0.02), sky.mean(axis=0)
    # Depth: the card (3 m) in front, the yarn (about 4 m) behind.
    depth = channels[LAYER + ".Depth.Z"]
    assert np.median(depth[centre, card_columns]) == pytest.approx(3.0, abs=0.1)
    assert np.median(depth[centre, open_columns]) == pytest.approx(4.0, abs=0.3)


def test_composite_shows_the_mesh_from_cycles_in_front_of_the_yarn(purl, core, scene, tmp_path):
    composite_scene(scene)
    channels = render_channels(scene, tmp_path / "composite.exr")
    check_composite(channels, 64, 48)


def test_composite_yarn_casts_its_shadow_in_cycles(purl, core, scene, tmp_path):
    """The yarn is hidden from Cycles' camera, not from its shadow rays: a white wall behind it,
    lit from above and in front, is darker just below the yarn than further down."""
    composite_scene(scene)
    bpy.data.objects["Card"].location.x = -5.0  # out of view
    wall = add_plane(scene, "Wall", size=8.0, location=(0.0, 0.6, 0.0))
    wall.rotation_euler = (1.5707963, 0.0, 0.0)
    sun = bpy.data.objects["Sun"]
    # Light travelling mostly away from the camera and a little down: the yarn's shadow on the
    # wall 0.6 m behind it falls about 0.23 m lower, just below the yarn as the camera sees it.
    sun.rotation_euler = (1.2, 0.0, 0.0)
    sun.data.angle = 0.0
    channels = render_channels(scene, tmp_path / "shadow.exr")
    red = channels[LAYER + ".Combined.R"]
    yarn_rows = np.flatnonzero((channels[LAYER + ".YarnID.X"] > 0).any(axis=1))
    below = red[yarn_rows.max() + 1:yarn_rows.max() + 3, 8:-8].mean()
    far_below = red[-4:, 8:-8].mean()
    assert below < 0.5 * far_below, (below, far_below)


def test_composite_from_the_command_line(purl, core, scene, tmp_path):
    composite_scene(scene)
    settings = scene.render.image_settings
    compat.set_multilayer_exr(settings)
    settings.exr_codec, settings.color_depth = "NONE", "32"
    result = render_saved_file(purl, tmp_path)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    path = tmp_path / "out_0001.exr"
    assert path.is_file(), result.stdout[-2000:]
    check_composite(read_channels(str(path)), 64, 48)
