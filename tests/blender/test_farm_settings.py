"""The Flamenco job type's settings as the Flamenco add-on evaluates them in this Blender (3.4 and
the bpy module): every `eval` expression of farm/flamenco/purl_render.js runs against a Purl scene
and gives a value of the setting's type; the add-on's module name is the one Blender knows it by
("purl" as a legacy add-on, "bl_ext.<repository>.purl" as an extension). tests/farm runs the jobs."""
import importlib.util
import json
import os
import pathlib
import shutil
import subprocess

import bpy
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
FLAMENCO = REPO / "farm" / "flamenco"
_TYPES = {"string": str, "int32": int, "float": float, "bool": bool}


@pytest.fixture(scope="module")
def job_type():
    if shutil.which("node") is None:
        pytest.skip("needs node to read the job type")
    result = subprocess.run(["node", str(FLAMENCO / "local_manager.js"), str(FLAMENCO / "purl_render.js"),
                             "job-type"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


@pytest.fixture(scope="module")
def submit_settings():
    spec = importlib.util.spec_from_file_location("purl_submit_settings", FLAMENCO / "submit_settings.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_eval_expression_runs_and_gives_the_setting_type(purl, scene, job_type, submit_settings, tmp_path):
    scene.frame_start, scene.frame_end = 4, 9
    scene.purl.samples, scene.purl.seed, scene.purl.clamp = 24, 11, 2.5
    scene.purl.ply_method = "LOCAL"
    given = {"render_output_root": str(tmp_path), "blendfile": str(tmp_path / "knit.blend")}
    settings = submit_settings.submitted_settings(job_type, "knit", given)
    for setting in job_type["settings"]:
        value = settings[setting["key"]]
        assert isinstance(value, _TYPES[setting["type"]]), (setting["key"], value)
    assert settings["frames"] == "4-9"
    assert (settings["samples"], settings["seed"], settings["clamp"]) == (24, 11, 2.5)
    assert (settings["scale"], settings["ply_search"]) == ("AUTO", "LOCAL")
    assert settings["scene"] == scene.name
    assert settings["format"] == scene.render.image_settings.file_format
    assert settings["render_output_path"] == os.path.join(str(tmp_path), "knit", "######")
    # The module Blender enabled the add-on under: what workers pass to --addons.
    assert settings["addon_module"] == purl.__name__
    assert settings["addon_module"] in bpy.context.preferences.addons


def test_missing_input_files_lists_the_world_images_that_are_not_here(purl, scene, tmp_path):
    scripting = importlib.import_module(purl.__name__ + ".scripting")
    assert scripting.missing_input_files(scene) == []
    scene.world.use_nodes = True
    tree = scene.world.node_tree
    texture = tree.nodes.new("ShaderNodeTexEnvironment")
    tree.links.new(texture.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    sky = tmp_path / "sky.exr"
    image = bpy.data.images.new("sky", 8, 4, float_buffer=True)
    image.filepath_raw, image.file_format = str(sky), "OPEN_EXR"
    image.save()
    texture.image = bpy.data.images.load(str(sky))
    assert scripting.missing_input_files(scene) == []
    texture.image.pack()  # packed: inside the .blend, whatever happens to the file
    sky.unlink()
    assert scripting.missing_input_files(scene) == []
    texture.image.unpack(method="REMOVE")
    texture.image.filepath = str(sky)
    assert scripting.missing_input_files(scene) == [str(sky)]
