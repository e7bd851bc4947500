"""Render farms end to end on this machine, with Debian's Blender 3.4 (docs/farm.md): the Purl
Render Flamenco job type's commands on two worker processes at once, and the Open Job Description
template under `openjd run`, each rendering a three-frame animation; their frames must equal a
single-process render of the same frames on two threads bit for bit, rendered with one thread per task.

    python3 -m pytest tests/farm      (scripts/test_blender.sh farm builds the add-on zip first)

The add-on comes from PURL_LEGACY_ZIP (dist/purl-<v>-legacy.zip), or addon/ from the tree with
purlcore from PURL_BUILD_DIR. Workers get an empty Blender configuration folder: they start
without saved preferences, as farm workers do.
"""
import importlib.util
import json
import os
import pathlib
import shutil
import subprocess
import sys
import zipfile

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "farm" / "flamenco"))
import run_local  # noqa: E402  (farm/flamenco is not a package)

_exr_spec = importlib.util.spec_from_file_location("purl_addon_exr", REPO / "addon" / "exr.py")
exr = importlib.util.module_from_spec(_exr_spec)
_exr_spec.loader.exec_module(exr)

BLENDER = shutil.which("blender")
SIZE = (64, 48)
FRAMES = (1, 2, 3)
COMBINED = ["ViewLayer.Combined." + c for c in "RGBA"]

pytestmark = pytest.mark.skipif(BLENDER is None or shutil.which("node") is None,
                                reason="needs Debian's blender and node")


@pytest.fixture(scope="module")
def farm(tmp_path_factory):
    """A worker environment (the add-on installed, no preferences) and the three-frame scene."""
    root = tmp_path_factory.mktemp("farm")
    addons = root / "scripts" / "addons"
    addons.mkdir(parents=True)
    legacy_zip = os.environ.get("PURL_LEGACY_ZIP")
    if legacy_zip:
        zipfile.ZipFile(legacy_zip).extractall(addons)
    else:
        os.symlink(REPO / "addon", addons / "purl")
    env = dict(os.environ, BLENDER_USER_SCRIPTS=str(root / "scripts"), BLENDER_USER_CONFIG=str(root / "config"))
    blend = root / "knit.blend"
    _blender(env, "--factory-startup", "--addons", "purl", "--python", REPO / "tests" / "farm" / "make_scene.py",
             "--", blend)
    return {"root": root, "env": env, "blend": blend}


@pytest.fixture(scope="module")
def reference(farm):
    """The three frames rendered by one Blender process on two threads."""
    out = farm["root"] / "reference"
    _blender(farm["env"], "-t", "2", farm["blend"], "--addons", "purl", "-E", "PURL", "-o", out / "######",
             "-f", "1..3")
    return {frame: _combined(out / "{:06d}.exr".format(frame)) for frame in FRAMES}


def _blender(env, *args):
    argv = [BLENDER, "-b", *map(str, args)]
    result = subprocess.run(argv, capture_output=True, text=True, env=run_local.worker_env(BLENDER, env),
                            timeout=600)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return result


def _combined(path):
    channels = exr.read_exr(str(path))
    return np.stack([channels[name] for name in COMBINED], axis=-1)


def _check_frames(paths, reference):
    """Every frame exists, has the scene's size, shows lit yarns, and equals the reference."""
    for frame in FRAMES:
        image = _combined(paths[frame])
        assert image.shape == (SIZE[1], SIZE[0], 4), paths[frame]
        rgb = image[..., :3]
        # Not blank: the background is the grey world (0.02); the yarns are lit by the sun.
        assert np.all(np.isfinite(rgb)) and rgb.max() > 0.1 and rgb.std() > 0.01, paths[frame]
        assert np.array_equal(image, reference[frame]), "frame {} differs from the single-process render".format(
            frame)
    assert not np.array_equal(reference[1], reference[3]), "the animation should move between frames"


def test_flamenco_job_runs_on_two_workers_and_matches_one_process(farm, reference):
    given = {"chunk_size": 2, "render_output_root": str(farm["root"] / "flamenco"), "threads": 1}
    job = run_local.compile_job(run_local.submit(str(farm["blend"]), "knit", given, BLENDER, "purl", farm["env"]))
    assert [task["name"] for task in job["tasks"]] == ["render-1,2", "render-3"]
    settings = job["settings"]
    assert (settings["frames"], settings["format"], settings["scene"]) == ("1-3", "OPEN_EXR_MULTILAYER", "Scene")
    assert (settings["samples"], settings["seed"], settings["animated_seed"]) == (4, 5, True)
    assert settings["addon_module"] == "purl"

    variables = {"blender": BLENDER, "blenderArgs": "-b -y"}
    results, _ = run_local.run_tasks(job["tasks"], 2, variables, farm["env"])
    for result in results:
        assert result["returncode"] == 0, result["log"][-3000:]
    pattern = settings["render_output_path"].replace("######", "{:06d}.exr")
    paths = {frame: pathlib.Path(pattern.format(frame)) for frame in FRAMES}
    # The worker reports what Blender saved ("Saved: '...'" lines, as Flamenco Workers read them).
    assert sorted(saved for r in results for saved in r["saved"]) == [str(paths[f]) for f in FRAMES]
    _check_frames(paths, reference)


def test_job_settings_edited_on_the_farm_reach_the_render(farm, reference):
    """A job whose samples were changed in the Manager renders with them, not the .blend's: the
    frame differs from the reference (same file, seed and frame, 4 samples)."""
    given = {"frames": "2", "render_output_root": str(farm["root"] / "edited")}
    job = run_local.submit(str(farm["blend"]), "knit", given, BLENDER, "purl", farm["env"])
    job["settings"]["samples"] = 1
    task = run_local.compile_job(job)["tasks"][0]
    (result,), _ = run_local.run_tasks([task], 1, {"blender": BLENDER, "blenderArgs": "-b -y"}, farm["env"])
    assert result["returncode"] == 0, result["log"][-3000:]
    image = _combined(result["saved"][0])
    assert image.shape == reference[2].shape and image[..., :3].max() > 0.1
    assert not np.array_equal(image, reference[2])


def test_worker_without_the_addon_fails_with_a_message(farm):
    given = {"frames": "1", "render_output_root": str(farm["root"] / "no_addon")}
    job = run_local.compile_job(run_local.submit(str(farm["blend"]), "knit", given, BLENDER, "purl", farm["env"]))
    bare = farm["root"] / "bare_scripts"
    (bare / "addons").mkdir(parents=True)
    env = dict(farm["env"], BLENDER_USER_SCRIPTS=str(bare))
    (result,), _ = run_local.run_tasks(job["tasks"], 1, {"blender": BLENDER, "blenderArgs": "-b -y"}, env)
    assert result["returncode"] != 0
    assert "the add-on 'purl' is not installed on this worker" in result["log"]
    assert not (farm["root"] / "no_addon").exists()


def test_worker_missing_the_environment_image_fails_with_its_path(farm):
    """An Environment Texture image that is neither packed nor on the worker stops the task (the
    render alone would only warn and light the yarns with a white world)."""
    sky = farm["root"] / "sky.exr"
    _blender(farm["env"], "--python-expr", "import bpy; i = bpy.data.images.new('sky', 8, 4, float_buffer=True); "
             "i.filepath_raw = {!r}; i.file_format = 'OPEN_EXR'; i.save()".format(str(sky)))
    blend = farm["root"] / "sky.blend"
    _blender(farm["env"], "--factory-startup", "--addons", "purl", "--python",
             REPO / "tests" / "farm" / "make_scene.py", "--", blend, "--environment", sky)
    sky.unlink()
    given = {"frames": "1", "render_output_root": str(farm["root"] / "no_sky")}
    job = run_local.compile_job(run_local.submit(str(blend), "sky", given, BLENDER, "purl", farm["env"]))
    (result,), _ = run_local.run_tasks(job["tasks"], 1, {"blender": BLENDER, "blenderArgs": "-b -y"}, farm["env"])
    assert result["returncode"] != 0
    assert "Purl: files missing on this worker: {}".format(sky) in result["log"], result["log"][-2000:]
    assert not (farm["root"] / "no_sky").exists()
    if _openjd() is not None:
        out = farm["root"] / "openjd_no_sky"
        status, log = _openjd_run(farm["env"], BlendFile=blend, OutputDir=out, Frames="1")
        assert status != 0 and "Purl: files missing on this worker: {}".format(sky) in log, log[-2000:]
        assert not out.exists() or not any(out.iterdir())


def test_blender_thread_count_reaches_purl(farm):
    """`blender -t 1` renders Purl on one thread (the export passes Blender's count on)."""
    script = ("import bpy, json; bpy.ops.render.render(); from purl.engine import PurlRenderEngine as E; "
              "print('PURL_THREADS', json.dumps(E.last_export.scene['render']['threads']))")
    for threads, expected in (("1", 1), ("0", 0)):
        result = _blender(farm["env"], "-t", threads, farm["blend"], "--addons", "purl", "--python-expr", script)
        line = [line for line in result.stdout.splitlines() if line.startswith("PURL_THREADS")]
        assert line and json.loads(line[0].split()[1]) == expected, result.stdout[-2000:]


def _openjd():
    # The openjd next to this Python, not a pyenv shim (a shim puts its own Python first on PATH).
    candidate = pathlib.Path(sys.executable).parent / "openjd"
    return str(candidate) if candidate.exists() else shutil.which("openjd")


def _openjd_run(env, **params):
    """`openjd run` of the template with these parameters: (exit status, log)."""
    argv = [_openjd(), "run", str(REPO / "farm" / "openjd" / "purl_render.yaml")]
    for key, value in dict({"BlenderExecutable": BLENDER}, **params).items():
        argv += ["-p", "{}={}".format(key, value)]
    result = subprocess.run(argv, capture_output=True, text=True, env=run_local.worker_env(BLENDER, env), timeout=600)
    return result.returncode, result.stdout + result.stderr


needs_openjd = pytest.mark.skipif(_openjd() is None, reason="needs openjd-cli (pip install openjd-cli)")


@needs_openjd
def test_openjd_template_renders_chunks_that_match_one_process(farm, reference):
    template = REPO / "farm" / "openjd" / "purl_render.yaml"
    check = subprocess.run([_openjd(), "check", str(template)], capture_output=True, text=True)
    assert check.returncode == 0, check.stdout + check.stderr
    out = farm["root"] / "openjd"
    status, log = _openjd_run(farm["env"], BlendFile=farm["blend"], OutputDir=out, Frames="1-3", ChunkSize=2,
                              Threads=1)
    assert status == 0, log[-4000:]
    assert "Chunks run: 2" in log, log[-2000:]
    _check_frames({frame: out / "{:06d}.exr".format(frame) for frame in FRAMES}, reference)


@needs_openjd
def test_openjd_scene_and_samples_parameters_reach_the_render(farm, reference):
    out = farm["root"] / "openjd_samples"
    status, log = _openjd_run(farm["env"], BlendFile=farm["blend"], OutputDir=out, Frames="2", Scene="Scene",
                              Samples=1)
    assert status == 0, log[-4000:]
    image = _combined(out / "000002.exr")
    assert image.shape == reference[2].shape and not np.array_equal(image, reference[2])


@needs_openjd
def test_openjd_worker_without_the_addon_fails_with_a_message(farm):
    bare = farm["root"] / "bare_openjd_scripts"
    (bare / "addons").mkdir(parents=True)
    out = farm["root"] / "openjd_no_addon"
    status, log = _openjd_run(dict(farm["env"], BLENDER_USER_SCRIPTS=str(bare)), BlendFile=farm["blend"],
                              OutputDir=out, Frames="1")
    assert status != 0
    assert "the add-on purl is not installed on this worker" in log
    assert not out.exists() or not any(out.iterdir())
