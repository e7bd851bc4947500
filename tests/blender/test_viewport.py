"""The rendered viewport without a window: the region's projection becomes the same camera, the
scene cache re-exports only what changed, and the worker renders coarse then 1, 2, 4, ... samples,
restarts on a new view or scene, and stops cleanly."""
import time
from importlib import import_module
from types import SimpleNamespace

import bpy
import numpy as np
import pytest

from builders import add_curve, depsgraph
from test_render import yarn_scene


@pytest.fixture
def vp(purl):
    return import_module(purl.__name__ + ".viewport")


@pytest.fixture
def vscene(purl):
    return import_module(purl.__name__ + ".viewport_scene")


@pytest.mark.parametrize("fit, shift", [("AUTO", (0.0, 0.0)), ("VERTICAL", (0.1, -0.2)), ("HORIZONTAL", (-0.3, 0.05))])
def test_the_region_projection_gives_the_same_camera(purl, core, vscene, scene, fit, shift):
    camera = scene.camera
    camera.data.sensor_fit = fit
    camera.data.shift_x, camera.data.shift_y = shift
    camera.data.lens = 35.0
    camera.location, camera.rotation_euler = (1.0, -5.0, 2.0), (1.2, 0.1, 0.3)
    width, height = 96, 64
    graph = depsgraph()
    window_matrix = camera.evaluated_get(graph).calc_matrix_camera(graph, x=width, y=height)
    region = SimpleNamespace(width=width, height=height)
    region_data = SimpleNamespace(is_perspective=True, window_matrix=window_matrix,
                                  view_matrix=camera.matrix_world.normalized().inverted())
    view_camera, film = vscene.view_from_region(region, region_data)
    export = import_module(purl.__name__ + ".export")
    exported_camera = export.camera.export_camera(camera.evaluated_get(graph), export.Problems())
    points = np.random.default_rng(1).uniform(-2.0, 2.0, (50, 3)).astype(np.float32)
    expected = core.project_points({"camera": exported_camera, "film": {"width": width, "height": height}}, points)
    got = core.project_points({"camera": view_camera, "film": film}, points)
    assert np.allclose(got, expected, atol=1e-3)
    assert view_camera["clip_start"] == pytest.approx(camera.data.clip_start, rel=1e-3)
    assert view_camera["clip_end"] == pytest.approx(camera.data.clip_end, rel=1e-2)
    assert vscene.view_from_region(region, SimpleNamespace(is_perspective=False)) is None


def sync(cache, problems):
    """cache.sync as view_update calls it: depsgraph.updates are only filled while handlers run."""
    results = []

    def handler(_, graph):
        results.append(cache.sync(graph, problems))

    bpy.app.handlers.depsgraph_update_post.append(handler)
    try:
        graph = bpy.context.evaluated_depsgraph_get()
    finally:
        bpy.app.handlers.depsgraph_update_post.remove(handler)
    return results[-1] if results else cache.sync(graph, problems)


def test_the_cache_re_exports_only_what_changed(purl, core, vscene, scene):
    yarn_scene(scene)
    cache, problems = vscene.SceneCache(), import_module(purl.__name__ + ".export").Problems()
    assert sync(cache, problems) and cache.exports >= 3
    exported = cache.exports
    assert not sync(cache, problems) and cache.exports == exported, "nothing changed"
    bpy.data.objects["Yarn+0.4"].location.x += 0.5
    assert sync(cache, problems) and cache.exports == exported + 1
    material = bpy.data.materials.new("Blue")
    bpy.data.objects["Yarn-0.4"].data.materials.append(material)
    assert sync(cache, problems) and cache.exports == exported + 2
    material.purl.params_bysdf.ply_color_1 = (0.1, 0.2, 0.9)
    sync(cache, problems)
    assert cache.exports == exported + 3, "only the yarn with that material"
    bpy.data.objects.remove(bpy.data.objects["Yarn+0.0"])
    assert sync(cache, problems) and len([p for p in cache.parts.values() if p.yarns]) == 2
    sun = bpy.data.objects["Sun"]
    sun.data.energy = 5.0
    assert not sync(cache, problems), "lights are read every time, not re-exported as geometry"
    lights = cache.scene(depsgraph(), problems, None).scene["lights"]
    assert lights[0]["strength"] == pytest.approx(5.0)


def session_scene(purl, scene):
    yarn_scene(scene)
    exported = import_module(purl.__name__ + ".export").export_scene(depsgraph())
    return exported.scene, exported.arrays


def wait_for(condition, timeout=60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(0.01)
    return False


def test_the_worker_renders_coarse_then_doubling_samples_and_restarts(purl, core, vp, scene):
    scene_dict, arrays = session_scene(purl, scene)
    camera, film = scene_dict["camera"], dict(scene_dict["film"], width=160, height=120)
    session = vp.ViewportSession(core)
    try:
        session.set_scene(scene_dict, arrays, samples=8, mode="near")
        session.set_view(camera, film)
        assert wait_for(lambda: session.idle)
        # The images published on the way (each one replaces the last): check the final one and
        # that coarse sizes came first by rendering again while recording.
        assert session.image.samples == 8 and session.image.pixels.shape == (120, 160, 4)
        assert vp.coarse_scales(160, 120) == [2]
        assert not session.set_view(camera, film), "the same view again changes nothing"

        moved = dict(camera, matrix_world=list(camera["matrix_world"]))
        moved["matrix_world"][3] += 0.3  # x translation of the camera
        before = session.image
        started = session.passes_started
        assert session.set_view(moved, film)
        assert wait_for(lambda: session.image is not before)
        assert wait_for(lambda: session.idle)
        assert session.passes_started > started
        # The images published since the view changed, from the session's own log (polling the
        # image could miss the coarse one on a loaded machine: the next replaces it in ms).
        events = [what for what, _ in session.events]
        since_view = events[len(events) - 1 - events[::-1].index("view"):]
        images = [what for what in since_view if what.startswith("image")]
        assert images and images[0].endswith(", 0 samples"), ("a new view starts with a coarse image", images)
        assert not np.allclose(session.image.pixels, before.pixels), "the view moved"

        # A new scene (material colour) restarts too, and a long render is cancelled by newer work.
        blue = dict(scene_dict)
        blue["yarns"] = [dict(y, material=dict(y["material"], ply_color_1=[0.1, 0.2, 0.9]))
                         for y in scene_dict["yarns"]]
        session.set_scene(blue, arrays, samples=1 << 16, mode="near")
        assert wait_for(lambda: session.image is not None and session.image.samples >= 2)
        hit = session.image.pixels[..., 3] > 0.5
        assert session.image.pixels[..., 2].sum() > before.pixels[..., 2].sum(), "bluer"
        session.set_scene(scene_dict, arrays, samples=2, mode="near")
        assert wait_for(lambda: session.idle), "the long render was cancelled for the new scene"
        assert session.image.samples == 2 and hit.any()
    finally:
        session.stop(wait=5.0)
    assert not session._thread.is_alive()


def test_nothing_to_render_shows_the_reason(purl, core, vp, scene):
    session = vp.ViewportSession(core)
    try:
        session.set_scene(None, None, 0, "near")
        session.set_view({}, {"width": 4, "height": 4})
        assert wait_for(lambda: session.idle) and session.image is None
    finally:
        session.stop(wait=5.0)


def test_the_material_preview_renders_a_knitted_swatch_with_the_material(purl, core, scene):
    preview = import_module(purl.__name__ + ".preview")
    material = bpy.data.materials.new("Blue wool")
    settings = material.purl.params_bysdf  # white body lobes: the ply colour decides the colour
    settings.body_reflection_albedo, settings.body_transmission_albedo = (0.5, 0.5, 0.5), (0.8, 0.8, 0.8)
    settings.ply_color_1 = (0.1, 0.2, 0.9)
    add_curve(scene, "pSphere", [("POLY", [(0, 0, 0), (1, 0, 0)], {})]).data.materials.append(material)
    exported = preview.preview_export(depsgraph(), 96, 96)
    assert preview.previewed_material(depsgraph()).original == material
    assert exported.scene["yarns"][0]["material"]["ply_color_1"] == pytest.approx([0.1, 0.2, 0.9])
    passes = core.render(exported.scene, exported.arrays)
    yarn = passes["YarnID"][..., 0] > 0
    assert 0.3 < yarn.mean() < 0.98, "the swatch fills most of the preview"
    rgb = passes["Combined"][..., :3][yarn]
    assert rgb[:, 2].mean() > rgb[:, 0].mean(), "in the previewed material's colour"
