"""purlcore.fit and `purl fit` (docs/fitting.md): small targets, short fits, clear errors."""
import json
import os
import subprocess

import numpy as np
import pytest

import purlcore


def yarn_scene(albedo, width=32, height=16):
    return {
        "camera": {"position": [0, -3, 0], "look_at": [0, 0, 0]},
        "film": {"width": width, "height": height},
        "render": {"spp": 4, "seed": 1},
        "lights": [{"type": "sun", "strength": 3, "position": [0, -1, 1], "look_at": [0, 0, 0]}],
        "yarns": [{"generate": {"kind": "plain", "warps": 3, "wefts": 3, "radius": 0.1},
                   "material": {"model": "bysdf", "body_reflection_albedo": albedo}}],
    }


def combined(scene, spp=16, seed=9):
    return purlcore.render(scene, spp=spp, seed=seed)["Combined"][..., :3]


def test_fit_moves_the_albedo_toward_a_synthetic_target():
    truth = [0.6, 0.3, 0.1]
    target = combined(yarn_scene(truth), spp=4, seed=2)  # the fit's seed and spp: shared noise
    seen = []
    preset = purlcore.fit([{"scene": yarn_scene([0.2, 0.2, 0.2]), "image": target}], params="kxB",
                          iterations=4, spp=4, seed=2, progress=lambda state: seen.append(state) or True)
    fitted = preset["material"]["body_reflection_albedo"]
    fit = preset["provenance"]
    assert fit["final_mse"] < 0.2 * fit["initial_mse"]
    assert all(abs(f - t) < abs(0.2 - t) for f, t in zip(fitted, truth))
    assert seen and seen[0]["event"] == "start"
    assert set(fit["parameters"]) == {"body_reflection_albedo[0]", "body_reflection_albedo[1]",
                                      "body_reflection_albedo[2]"}


def test_progress_returning_false_stops_the_fit():
    target = combined(yarn_scene([0.6, 0.3, 0.1]))
    preset = purlcore.fit([{"scene": yarn_scene([0.2, 0.2, 0.2]), "image": target}], params="kxB",
                          iterations=50, spp=2, progress=lambda state: False)
    assert preset["provenance"]["stop_reason"] == "stopped"


@pytest.mark.parametrize("image, message", [
    (np.zeros((8, 8, 3), np.float32), "the target is 8 x 8 pixels but its scene renders 32 x 16"),
    (np.full((16, 32, 3), np.nan, np.float32), "pixel (0, 0): value is not finite"),
    ("/nonexistent/target.exr", "/nonexistent/target.exr: no such file"),
])
def test_bad_targets_are_clear_errors(image, message):
    with pytest.raises(purlcore.Error, match=message.replace("(", r"\(").replace(")", r"\)")):
        purlcore.fit([{"scene": yarn_scene([0.2, 0.2, 0.2]), "image": image}], params="kxB", iterations=1)


def test_unknown_parameter_is_a_clear_error():
    target = np.zeros((16, 32, 3), np.float32)
    with pytest.raises(purlcore.Error, match="not a bysdf parameter"):
        purlcore.fit([{"scene": yarn_scene([0.2, 0.2, 0.2]), "image": target}], params="kxB,shine")


def purl_binary():
    path = os.path.join(os.path.dirname(purlcore.__file__), "purl")
    if not os.path.exists(path):
        pytest.skip("the purl binary is not next to purlcore")
    return path


def test_cli_fit_writes_a_preset_that_scenes_can_use(tmp_path):
    purl = purl_binary()
    scene_path = tmp_path / "scene.json"
    scene_path.write_text(json.dumps(yarn_scene([0.6, 0.3, 0.1])))
    target = tmp_path / "target.exr"
    subprocess.run([purl, "render", str(scene_path), "-o", str(target), "--spp", "16"], check=True,
                   capture_output=True)
    scene_path.write_text(json.dumps(yarn_scene([0.2, 0.2, 0.2])))
    preset_path = tmp_path / "wool.json"
    run = subprocess.run([purl, "fit", str(scene_path), "--target", str(target), "--params", "kxB",
                          "--iterations", "3", "--spp", "4", "-o", str(preset_path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "iteration" in run.stderr and "wrote" in run.stderr
    preset = json.loads(preset_path.read_text())
    assert preset["name"] == "wool" and preset["provenance"]["targets"][0]["image"] == str(target)
    using = yarn_scene([0.2, 0.2, 0.2])
    using["yarns"][0]["material"] = {"preset_file": "wool.json"}
    scene_path.write_text(json.dumps(using))
    subprocess.run([purl, "render", str(scene_path), "-o", str(tmp_path / "check.png"), "--spp", "1"], check=True,
                   capture_output=True)


def test_cli_fit_missing_target_exits_with_the_file_named(tmp_path):
    scene_path = tmp_path / "scene.json"
    scene_path.write_text(json.dumps(yarn_scene([0.2, 0.2, 0.2])))
    run = subprocess.run([purl_binary(), "fit", "--target", str(tmp_path / "gone.exr"), str(scene_path),
                          "-o", str(tmp_path / "out.json")], capture_output=True, text=True)
    assert run.returncode == 2
    assert "gone.exr: no such file" in run.stderr
