"""The "Fit to Image" operator (addon/fit.py): a tiny target rendered by Purl with known
parameters, a material started elsewhere, a short fit that moves it back and saves a preset."""
import json
from importlib import import_module

import bpy
import pytest

from builders import add_curve, add_light, depsgraph


@pytest.fixture
def yarn_material(core, scene):
    scene.render.resolution_x, scene.render.resolution_y = 32, 16
    material = bpy.data.materials.new("Fitted")
    material.purl.model = "bysdf"
    curve = add_curve(scene, "Yarn", [("POLY", [(-3.0, 0.0, 0.0), (3.0, 0.0, 0.0)], {})], bevel_depth=0.5)
    curve.data.materials.append(material)
    add_light(scene, "SUN", energy=3.0).rotation_euler = (0.6, 0.2, 0.0)
    return material


def _render_target(purl, core, params, tmp_path):
    """A target rendered with a red-brown body albedo; the material then starts grey."""
    params.body_reflection_albedo = (0.6, 0.3, 0.1)
    exported = import_module(purl.__name__ + ".export").export_scene(depsgraph())
    job = core.RenderJob(exported.scene, exported.arrays, "", None)
    job.start(spp=8, seed=5)
    job.wait()
    target = tmp_path / "target.exr"
    job.write(str(target))
    params.body_reflection_albedo = (0.2, 0.2, 0.2)
    return target, exported


def test_fit_to_image_moves_the_material_toward_the_target(purl, core, scene, yarn_material, tmp_path):
    params = yarn_material.purl.params_bysdf
    target, _ = _render_target(purl, core, params, tmp_path)
    preset_path = tmp_path / "fitted.json"
    with bpy.context.temp_override(material=yarn_material):
        result = bpy.ops.purl.fit_to_image(filepath=str(target), params="kxB", iterations=3, samples=4,
                                           preset_path=str(preset_path))
    assert result == {"FINISHED"}
    preset = json.loads(preset_path.read_text())
    assert preset["provenance"]["final_mse"] < preset["provenance"]["initial_mse"]
    red = params.body_reflection_albedo[0]
    assert abs(red - 0.6) < abs(0.2 - 0.6), "the red albedo should move toward the target's 0.6"
    assert list(preset["material"]["body_reflection_albedo"]) == pytest.approx(
        list(params.body_reflection_albedo), abs=1e-3)


def test_fit_to_image_reports_a_missing_target(core, scene, yarn_material, tmp_path):
    with bpy.context.temp_override(material=yarn_material):
        with pytest.raises(RuntimeError, match="no such target image"):
            bpy.ops.purl.fit_to_image(filepath=str(tmp_path / "absent.exr"), params="kxB", iterations=1)


def test_fit_job_runs_on_a_worker_thread_and_stops_early(purl, core, scene, yarn_material, tmp_path):
    """What the panel's modal operator drives: the fit on a thread, stopped by Esc after its first step."""
    fit = import_module(purl.__name__ + ".fit")
    target, exported = _render_target(purl, core, yarn_material.purl.params_bysdf, tmp_path)
    job = fit.FitJob(core, {"scene": exported.scene, "image": str(target)}, exported.arrays, "kxB",
                     iterations=50, samples=2, name="threaded")
    job.start()
    job.stop()
    job._thread.join(timeout=300)
    assert job.finished and job.error is None
    assert job.stopped, "the fit should have seen the stop request"
    assert job.result["provenance"]["iterations"] < 50
    assert job.state is not None and job.state["iteration"] <= job.result["provenance"]["iterations"]
