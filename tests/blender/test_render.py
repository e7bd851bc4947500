"""Rendering through the Purl engine: an image with the expected passes, cancel, bad input that
is reported without stopping the render, scripted and animation renders."""
import os
import time
from importlib import import_module

import bpy
import numpy as np
import pytest

from builders import add_curve, add_light, compat, render_saved_file, save_render_result
from curve_math import placed_arrays
from exr import channel_names

LAYER = "ViewLayer"


def yarn_scene(scene):
    """Three horizontal yarns across the view, a sun and a grey world."""
    for z in (-0.4, 0.0, 0.4):
        add_curve(scene, "Yarn{:+.1f}".format(z),
                  [("BEZIER", [(-3.0, 0.0, z), (0.0, 0.2, z + 0.1), (3.0, 0.0, z)], {})], bevel_depth=0.12)
    add_light(scene, "SUN", energy=3.0).rotation_euler = (0.6, 0.2, 0.0)
    scene.world.color = (0.05, 0.05, 0.05)
    scene.view_layers[0].name = LAYER
    return scene


def test_render_produces_an_image_with_all_passes(core, scene, tmp_path):
    yarn_scene(scene)
    assert bpy.ops.render.render() == {"FINISHED"}
    channels = save_render_result(scene, tmp_path / "result.exr")
    for name in ("Combined.R", "Combined.G", "Combined.B", "Combined.A", "Depth.Z",
                 "Normal.X", "Normal.Y", "Normal.Z", "YarnID.X", "PlyIndex.X", "PlyUV.U", "PlyUV.V"):
        assert "{}.{}".format(LAYER, name) in channels, sorted(channels)
    alpha = channels[LAYER + ".Combined.A"]
    red = channels[LAYER + ".Combined.R"]
    depth = channels[LAYER + ".Depth.Z"]
    yarn_id = channels[LAYER + ".YarnID.X"]
    assert alpha.shape == (48, 64)
    hit = yarn_id > 0
    assert 0.1 < hit.mean() < 0.9, "the yarns should cover part of the image"
    assert red[hit].mean() > 0.0 and np.all(np.isfinite(red))
    # The camera is 4 m from the yarns, which are 0.12 m thick.
    assert np.median(depth[hit]) == pytest.approx(4.0, abs=0.3)
    normal_length = np.sqrt(sum(channels[LAYER + ".Normal." + c] ** 2 for c in "XYZ"))
    assert np.median(normal_length[hit]) == pytest.approx(1.0, abs=0.05)
    assert np.all(channels[LAYER + ".PlyIndex.X"][~hit] == -1), "no ply where no yarn"


def test_passes_show_in_the_compositor(core, scene):
    yarn_scene(scene)
    if hasattr(scene, "compositing_node_group"):  # Blender 5.0
        tree = bpy.data.node_groups.new("Compositing", "CompositorNodeTree")
        scene.compositing_node_group = tree
        node = tree.nodes.new("CompositorNodeRLayers")
    else:
        scene.use_nodes = True
        node = next(n for n in scene.node_tree.nodes if n.bl_idname == "CompositorNodeRLayers")
    enabled = {socket.name for socket in node.outputs if socket.enabled}
    assert {"Image", "Alpha", "Depth", "Normal", "YarnID", "PlyIndex", "PlyUV"} <= enabled


def test_bad_objects_are_reported_and_the_rest_renders(purl, core, scene, tmp_path):
    yarn_scene(scene)
    broken = add_curve(scene, "Broken", [("POLY", [(0, 0, 0), (1, 0, 0), (2, 0, 0)], {})])
    broken.data.splines[0].points[1].co = (float("nan"), 0.0, 0.0, 1.0)
    empty = bpy.data.curves.new("Empty", "CURVE")
    empty.bevel_depth = 0.1
    scene.collection.objects.link(bpy.data.objects.new("Empty", empty))
    assert bpy.ops.render.render() == {"FINISHED"}
    engine = import_module(purl.__name__ + ".engine").PurlRenderEngine
    messages = " | ".join(engine.last_export.problems.messages())
    assert "Broken" in messages and "Empty" in messages
    channels = save_render_result(scene, tmp_path / "result.exr")
    assert (channels[LAYER + ".YarnID.X"] > 0).any()


def test_job_cancel_stops_quickly(core, purl, scene):
    yarn_scene(scene)
    exported = import_module(purl.__name__ + ".export").export_scene(bpy.context.evaluated_depsgraph_get())
    job = core.RenderJob(exported.scene, exported.arrays)
    job.start(spp=1 << 16)
    time.sleep(0.1)
    started = time.monotonic()
    job.cancel()
    assert job.wait(2.0)
    assert time.monotonic() - started < 0.5
    assert job.cancelled and job.error is None


def test_escape_in_blender_cancels_the_render_within_half_a_second(purl, core, scene, monkeypatch):
    engine = import_module(purl.__name__ + ".engine").PurlRenderEngine
    state = {}

    def user_presses_escape_after_a_fifth_of_a_second(self):
        now = time.monotonic()
        state.setdefault("first_poll", now)
        if now - state["first_poll"] > 0.2:
            state.setdefault("cancelled_at", now)
            return True
        return False

    monkeypatch.setattr(engine, "_user_cancelled", user_presses_escape_after_a_fifth_of_a_second)
    yarn_scene(scene)
    scene.purl.samples = 1 << 16
    assert bpy.ops.render.render() == {"FINISHED"}
    finished = time.monotonic()
    assert "cancelled_at" in state, "the render finished before the cancel"
    assert finished - state["cancelled_at"] < 0.5


def test_render_to_file_writes_png_and_multilayer_exr(purl, core, scene, tmp_path):
    yarn_scene(scene)
    scripting = import_module(purl.__name__ + ".scripting")
    png = scripting.render_to_file(str(tmp_path / "yarn.png"))
    exr = scripting.render_to_file(str(tmp_path / "yarn.exr"))
    assert os.path.getsize(png) > 0
    assert LAYER + ".YarnID.X" in channel_names(exr)
    assert scene.render.engine == "PURL" and scene.render.filepath != str(tmp_path / "yarn.exr")


def test_render_to_file_raises_when_nothing_renders(purl, core, scene, tmp_path):
    scripting = import_module(purl.__name__ + ".scripting")
    with pytest.raises(RuntimeError, match="nothing to render"):
        scripting.render_to_file(str(tmp_path / "empty.png"))


def test_animation_exports_every_frame(purl, core, scene, tmp_path):
    yarn_scene(scene)
    mover = bpy.data.objects["Yarn+0.0"]
    mover.location = (0.0, 0.0, 0.0)
    mover.keyframe_insert("location", frame=1)
    mover.location = (0.0, 0.0, 1.0)
    mover.keyframe_insert("location", frame=2)
    scene.frame_start, scene.frame_end = 1, 2
    scene.render.filepath = str(tmp_path / "frame_")
    compat.set_image_format(scene.render.image_settings, "PNG")
    engine = import_module(purl.__name__ + ".engine").PurlRenderEngine
    engine.keep_last_arrays = True
    try:
        assert bpy.ops.render.render(animation=True) == {"FINISHED"}
    finally:
        engine.keep_last_arrays = False
    assert sorted(os.listdir(tmp_path)) == ["frame_0001.png", "frame_0002.png"]
    moved = next(y for y in engine.last_export.scene["yarns"] if y["name"] == "Yarn+0.0")
    points = placed_arrays(engine.last_export, moved)["points"]
    assert points[:, 2].mean() == pytest.approx(1.0 + 0.1 * 2 / 3, abs=0.1)  # frame 2's position


def test_command_line_render_of_a_saved_file(purl, core, scene, tmp_path):
    yarn_scene(scene)
    result = render_saved_file(purl, tmp_path, "-F", "PNG")
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    assert (tmp_path / "out_0001.png").stat().st_size > 0, result.stdout[-2000:]
