"""F12 in progressive sample passes: every pass shows in the result, the finished image is the
one-shot render of all samples, Esc keeps the passes rendered so far, and a background render
prints its status at most once a second."""
import time
from importlib import import_module

import bpy
import numpy as np
import pytest

from builders import save_render_result
from test_render import LAYER, yarn_scene


@pytest.fixture
def engine(purl):
    return import_module(purl.__name__ + ".engine").PurlRenderEngine


def record_passes(engine, monkeypatch):
    """The `final` flag of every _write_result call, in order."""
    shown = []
    original = engine._write_result

    def recording(self, result, job, passes, temp_dir, layer_name, final):
        shown.append(final)
        return original(self, result, job, passes, temp_dir, layer_name, final)

    monkeypatch.setattr(engine, "_write_result", recording)
    monkeypatch.setattr(engine, "shows_passes", lambda self: True)  # as with a window
    return shown


def test_passes_show_as_they_finish_and_add_up_to_the_one_shot_render(purl, core, engine, scene, tmp_path,
                                                                      monkeypatch):
    yarn_scene(scene)
    scene.purl.samples = 12
    engine.keep_last_arrays = True
    shown = record_passes(engine, monkeypatch)
    try:
        assert bpy.ops.render.render() == {"FINISHED"}
    finally:
        engine.keep_last_arrays = False
    # 1, 1, 2, 4, 4 samples: the image after 1, 2, 4, 8 and 12; only the last is final. (Passes
    # in between are left out when showing one would cost more than a quarter of the time.)
    assert shown[-1] is True and not any(shown[:-1]) and len(shown) >= 3
    exported = engine.last_export
    one_shot = core.render(exported.scene, exported.arrays)["Combined"][::-1]  # rows bottom to top
    channels = save_render_result(scene, tmp_path / "result.exr")
    got = np.stack([channels["{}.Combined.{}".format(LAYER, c)] for c in "RGBA"], axis=-1)[::-1]
    assert np.allclose(got, one_shot, atol=2e-5)


def test_escape_keeps_the_passes_rendered_so_far(purl, core, engine, scene, tmp_path, monkeypatch):
    yarn_scene(scene)
    scene.purl.samples = 1 << 12
    shown = record_passes(engine, monkeypatch)
    monkeypatch.setattr(engine, "_user_cancelled", lambda self: len(shown) >= 2)
    assert bpy.ops.render.render() == {"FINISHED"}
    # Esc is seen while a pass runs (passes that end before a poll still show); the render
    # stopped long before its 4096 samples, so no final image was written.
    assert len(shown) >= 2 and not any(shown)
    channels = save_render_result(scene, tmp_path / "result.exr")
    alpha = channels[LAYER + ".Combined.A"]
    assert alpha.mean() > 0.99, "the cancelled render keeps its image (opaque world)"
    assert channels[LAYER + ".Combined.R"].max() > 0


class FakeEngine:
    def __init__(self):
        self.stats, self.progress = [], []

    def update_stats(self, _, text):
        self.stats.append(text)

    def update_progress(self, value):
        self.progress.append(value)


def test_background_renders_show_only_the_final_image(purl, core, engine, scene, monkeypatch):
    yarn_scene(scene)
    scene.purl.samples = 8
    shown = []
    original = engine._write_result
    monkeypatch.setattr(engine, "_write_result", lambda self, *args: shown.append(args[-1]) or original(self, *args))
    assert bpy.ops.render.render() == {"FINISHED"}
    assert shown == [True]


def test_background_status_lines_at_most_once_a_second(purl):
    progressive = import_module(purl.__name__ + ".progressive")
    background, window = FakeEngine(), FakeEngine()
    lines = [progressive.StatusLine(background, background=True), progressive.StatusLine(window, background=False)]
    start = time.monotonic()
    while time.monotonic() - start < 0.3:
        for line in lines:
            line.show("rendering", 0.5)
    lines[0].show("done", 1.0, force=True)
    assert background.stats == ["rendering", "done"]
    assert len(window.stats) > 10


def test_pass_plan_doubles_and_caps_long_passes(purl):
    plan = import_module(purl.__name__ + ".progressive").PassPlan(100, max_seconds=2.0)
    steps = []
    while (step := plan.next()) is not None:
        steps.append(step)
        plan.finished(step[1], 0.5 * step[1])  # half a second per sample
    assert steps[:4] == [(0, 1), (1, 1), (2, 2), (4, 4)]
    assert max(count for _, count in steps) == 4 and sum(count for _, count in steps) == 100


def test_far_field_tabulation_shows_in_the_status(purl, core, engine, scene, monkeypatch):
    yarn_scene(scene)
    scene.purl.samples = 1
    scene.purl.multiscale_mode = "FAR"
    material = bpy.data.materials.new("Fresh")  # a material no table was built for in this process
    material.purl.params_bysdf.eta = 1.5 + 1e-3 * (time.time() % 97)
    for ob in scene.objects:
        if ob.type == "CURVE":
            ob.data.materials.append(material)
    progressive = import_module(purl.__name__ + ".progressive")
    texts = []
    original = progressive.StatusLine.show
    monkeypatch.setattr(progressive.StatusLine, "show",
                        lambda self, text, *args, **kwargs: texts.append(text) or original(self, text, *args, **kwargs))
    assert bpy.ops.render.render() == {"FINISHED"}
    assert any("tabulating the far field" in text for text in texts), texts[:5]
