"""Multi-scale BYSDF from Python: the mode argument, the parameter table, stats and the
far-mode warning (docs/multiscale.md)."""
import json
import os
import subprocess
import warnings

import pytest

import purlcore


def yarn_scene(distance, multiscale=None, width=16, height=12):
    """A plain weave of 0.1 m yarns seen from `distance` m (3 m: a yarn spans ~1.5 pixels of 16)."""
    scene = {
        "camera": {"position": [0, -distance, 0], "look_at": [0, 0, 0]},
        "film": {"width": width, "height": height},
        "render": {"spp": 1, "seed": 1},
        "lights": [{"type": "sun", "strength": 3, "position": [0, -1, 1], "look_at": [0, 0, 0]}],
        "yarns": [{"generate": {"kind": "plain", "warps": 3, "wefts": 3, "radius": 0.1},
                   "material": {"model": "bysdf"}}],
    }
    if multiscale is not None:
        scene["render"]["multiscale"] = multiscale
    return scene


def run_job(scene, **kwargs):
    job = purlcore.RenderJob(scene, **kwargs)
    job.start()
    job.wait()
    assert job.error is None
    return job.stats()


def test_parameter_table_and_modes_are_exposed():
    names = [p["name"] for p in purlcore.multiscale_parameters()]
    assert "multiscale_roughness_c" in names and "multiscale_max_h_samples" in names
    assert "multiscale_far_limit" in names
    assert purlcore.multiscale_modes() == ["near", "multi", "far", "auto"]


def test_stats_count_camera_hits_by_mode():
    near = run_job(yarn_scene(1.0), mode="near")
    assert near["multiscale_hits"]["near"] > 0
    assert near["multiscale_hits"]["multi"] == near["multiscale_hits"]["far"] == 0
    assert near["mean_h_samples"] == 1.0
    # The scene's own setting, when no mode is passed.
    multi = run_job(yarn_scene(1.0, {"mode": "multi", "multiscale_max_h_samples": 5}))
    assert multi["multiscale_hits"]["multi"] > 0 and multi["multiscale_hits"]["near"] == 0
    assert 1.0 < multi["mean_h_samples"] <= 6.0  # at most 5 cells, one more at a silhouette


def test_forcing_far_on_wide_yarns_warns_once():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        purlcore.render(yarn_scene(1.0), mode="far")
    messages = [str(w.message) for w in caught if "far" in str(w.message)]
    assert len(messages) == 1, messages
    stats = run_job(yarn_scene(1.0), mode="far")
    assert len(stats["warnings"]) == 1 and "wider than a pixel" in stats["warnings"][0]
    assert run_job(yarn_scene(1.0), mode="auto")["warnings"] == []


def test_bad_modes_and_settings_are_rejected():
    with pytest.raises(ValueError, match="mode"):
        purlcore.render(yarn_scene(1.0), mode="closeup")
    with pytest.raises(purlcore.Error, match="multiscale"):
        purlcore.render(yarn_scene(1.0, {"mode": "auto", "unknown_key": 1}))


def test_cli_mode_flag_and_stats(tmp_path):
    build = os.environ.get("PURL_BUILD_DIR", "build")
    purl = os.path.join(os.path.dirname(__file__), "..", "..", build, "purl")
    if not os.path.exists(purl):
        pytest.skip("no purl binary next to purlcore")
    scene = tmp_path / "yarn.json"
    scene.write_text(json.dumps(yarn_scene(1.0)))
    out = subprocess.run([purl, "render", str(scene), "-o", str(tmp_path / "y.exr"), "--mode", "far", "--stats"],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stderr.count("wider than a pixel") == 1
    assert "multiscale: camera hits near 0, multi 0, far" in out.stderr
    bad = subprocess.run([purl, "render", str(scene), "-o", str(tmp_path / "y.exr"), "--mode", "closeup"],
                         capture_output=True, text=True)
    assert bad.returncode != 0
