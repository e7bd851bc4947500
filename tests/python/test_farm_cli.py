"""The CLI on a render farm (docs/farm.md): `purl deps` lists what a scene reads besides itself,
and renders in separate processes with different thread counts are bit-identical."""
import json
import os
import shutil
import subprocess

import pytest

BUILD = os.path.join(os.path.dirname(__file__), "..", "..", os.environ.get("PURL_BUILD_DIR", "build"))
PURL = os.path.join(BUILD, "purl")

pytestmark = pytest.mark.skipif(not os.path.exists(PURL), reason="no purl binary in the build folder")


def purl(*args):
    return subprocess.run([PURL, *map(str, args)], capture_output=True, text=True, timeout=300)


@pytest.fixture
def shot(tmp_path):
    """A scene in shot/ with its BCC file in shot/curves/ and a preset file beside it."""
    (tmp_path / "shot" / "curves").mkdir(parents=True)
    assert purl("generate", "plain", "-o", tmp_path / "shot" / "curves" / "plain.bcc").returncode == 0
    (tmp_path / "shot" / "wool.json").write_text(json.dumps({"material": {"model": "bysdf", "eta": 1.55}}))
    scene = {"camera": {"position": [0, -0.04, 0.03], "look_at": [0, 0, 0], "clip_start": 0.001},
             "film": {"width": 24, "height": 16}, "render": {"spp": 2, "seed": 3},
             "world": {"color": [0.6, 0.6, 0.6]},
             "lights": [{"type": "sun", "strength": 3, "position": [0, -1, 1], "look_at": [0, 0, 0]}],
             "yarns": [{"bcc": "curves/plain.bcc", "radius": 0.0005, "material": {"preset_file": "wool.json"}}]}
    path = tmp_path / "shot" / "scene.json"
    path.write_text(json.dumps(scene))
    return path


def test_deps_lists_the_files_a_scene_reads(shot):
    result = purl("deps", shot)
    assert result.returncode == 0, result.stderr
    assert "3 files" in result.stdout and "0 outside the scene's folder, 0 missing" in result.stdout
    assert "curves/plain.bcc" in result.stdout and "yarns[0].material.preset_file" in result.stdout
    listed = json.loads(purl("deps", "--json", shot).stdout)
    assert [f["role"] for f in listed["files"]] == ["scene", "bcc", "preset_file"]
    assert all(f["exists"] and f["inside_scene_folder"] for f in listed["files"])
    assert listed["files"][1]["path"] == str(shot.parent / "curves" / "plain.bcc")


def test_deps_names_a_missing_file_and_exits_2(shot):
    scene = json.loads(shot.read_text())
    scene["world"]["texture"] = "/nonexistent/sky.exr"
    shot.write_text(json.dumps(scene))
    result = purl("deps", shot)
    assert result.returncode == 2
    assert "world.texture: file /nonexistent/sky.exr does not exist" in result.stderr
    assert "missing" in result.stdout and "outside the scene's folder" in result.stdout


@pytest.mark.skipif(shutil.which("idiff") is None, reason="needs idiff (openimageio-tools)")
def test_renders_in_separate_processes_are_bit_identical_for_any_thread_count(shot, tmp_path):
    images = []
    for threads in (1, 2):
        image = tmp_path / "threads{}.exr".format(threads)
        result = purl("render", shot, "-o", image, "--threads", threads)
        assert result.returncode == 0, result.stderr
        images.append(image)
    # idiff with zero thresholds fails on any difference in any channel (all passes).
    same = subprocess.run(["idiff", "-fail", "0", "-warn", "0", *map(str, images)], capture_output=True, text=True)
    assert same.returncode == 0, same.stdout
    # ... and does see one: another seed.
    other = tmp_path / "seed.exr"
    assert purl("render", shot, "-o", other, "--seed", 4).returncode == 0
    differs = subprocess.run(["idiff", "-fail", "0", "-warn", "0", str(images[0]), str(other)],
                             capture_output=True, text=True)
    assert differs.returncode != 0, differs.stdout
