"""purlcore and the CLI: artist controls on a BYSDF material, the denoising passes and Open Image
Denoise (docs/artist-controls.md, docs/denoising.md)."""
import json
import os
import subprocess

import numpy as np
import pytest

import purlcore
from test_fit import purl_binary
from test_purlcore import scene, yarn_arrays


def bysdf_scene(material, **render):
    s = scene(width=32, height=24, spp=4)
    s["render"].update(render)
    s["yarns"][0]["material"] = dict({"model": "bysdf"}, **material)
    return s


def yarn_mean(passes):
    """Mean RGB of the pixels that see a yarn."""
    mask = passes["YarnID"][..., 0] > 0
    assert mask.sum() > 20
    return passes["Combined"][mask][:, :3].mean(axis=0)


def test_artist_parameters_declare_label_range_and_rule():
    table = {p["name"]: p for p in purlcore.artist_parameters()}
    assert list(table) == ["color", "sheen", "softness", "translucency"]
    assert table["color"]["is_color"] and table["color"]["label"] == "Yarn Colour"
    for name in ("sheen", "softness", "translucency"):
        assert table[name]["default"] == 1.0 and table[name]["min"] == 0.0
        assert "Multiplies" in table[name]["doc"]  # the rule is in the declaration


def test_resolve_material_applies_the_rules_and_is_neutral_by_default():
    plain = purlcore.resolve_material({"body_transmission_albedo": [0.4, 0.2, 0.1]})
    assert purlcore.resolve_material({"body_transmission_albedo": [0.4, 0.2, 0.1], "sheen": 1.0,
                                      "softness": 1.0, "translucency": 1.0}) == plain
    red = purlcore.resolve_material({"body_transmission_albedo": [0.4, 0.2, 0.1], "color": [1.0, 0.0, 0.0]})
    assert red["body_transmission_albedo"] == pytest.approx((0.4, 0.0, 0.0))
    assert red["specular_reflection_albedo"] == plain["specular_reflection_albedo"]
    with pytest.raises(ValueError, match="not presets"):
        purlcore.resolve_material({"preset": "cotton", "color": [1.0, 0.0, 0.0]})


def test_one_colour_makes_a_red_yarn_on_a_preset():
    arrays = {"knit": yarn_arrays()}
    red = yarn_mean(purlcore.render(bysdf_scene({"preset": "cotton", "color": [0.8, 0.05, 0.05]}), arrays))
    white = yarn_mean(purlcore.render(bysdf_scene({"preset": "cotton"}), arrays))
    # The white sheen and the sky's reflection stay: the colour shifts the hue, it does not paint.
    assert red[0] > 1.8 * red[1] and red[0] > 1.8 * red[2]
    assert white[0] < 1.3 * white[1]


def test_denoising_passes_are_written():
    passes = purlcore.render(bysdf_scene({}), {"knit": yarn_arrays()})
    albedo, normal = passes["Denoising Albedo"], passes["Denoising Normal"]
    assert albedo.shape[-1] == 3 and normal.shape[-1] == 3
    yarn = passes["YarnID"][..., 0] > 0
    assert (albedo[yarn] > 0).any(axis=-1).all()
    assert (albedo <= 1).all() and (albedo >= 0).all()
    lengths = np.linalg.norm(normal[yarn], axis=-1)
    assert np.median(lengths) > 0.5 and (lengths <= 1.0001).all()
    assert np.median(normal[yarn][:, 2]) > 0  # camera space: facing the viewer


def needs_denoiser():
    status = purlcore.denoiser()
    if not status["available"]:
        pytest.skip(status["message"])


def test_job_denoises_and_keeps_the_noisy_image():
    needs_denoiser()
    job = purlcore.RenderJob(bysdf_scene({}), {"knit": yarn_arrays()})
    job.start(denoise=True)
    job.wait()
    passes, stats = job.passes(), job.stats()
    assert "Noisy Image" in passes
    assert not np.array_equal(passes["Combined"][..., :3], passes["Noisy Image"][..., :3])
    np.testing.assert_array_equal(passes["Combined"][..., 3], passes["Noisy Image"][..., 3])
    assert stats["denoise_seconds"] > 0


def test_denoise_function_takes_a_passes_dict():
    needs_denoiser()
    passes = purlcore.render(bysdf_scene({}), {"knit": yarn_arrays()})
    out = purlcore.denoise(passes)
    np.testing.assert_array_equal(out["Noisy Image"], passes["Combined"])
    with pytest.raises(ValueError, match="differ in size"):
        purlcore.denoise({"Combined": passes["Combined"], "Depth": passes["Depth"][:5]})


def test_cli_denoise_and_a_missing_library(tmp_path):
    purl = purl_binary()
    scene_path = tmp_path / "scene.json"
    s = bysdf_scene({})
    s["yarns"][0] = {"generate": {"kind": "plain"}, "material": {"model": "bysdf", "color": [0.2, 0.4, 0.9]}}
    scene_path.write_text(json.dumps(s))
    missing = subprocess.run([purl, "render", str(scene_path), "-o", str(tmp_path / "a.exr"), "--denoise"],
                             capture_output=True, text=True, env=dict(os.environ, PURL_OIDN_LIBRARY="/nowhere/libOIDN.so"))
    assert missing.returncode == 2
    assert "pip install pyoidn" in missing.stderr and "/nowhere/libOIDN.so" in missing.stderr
    assert not (tmp_path / "a.exr").exists()
    if not purlcore.denoiser()["available"]:
        return
    done = subprocess.run([purl, "render", str(scene_path), "-o", str(tmp_path / "b.exr"), "--denoise"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "denoised with Open Image Denoise" in done.stderr
