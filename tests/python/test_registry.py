"""The registry of choices and render settings (native/src/base/registry.h) as purlcore shows it,
and the `purl` command checking the same ranges and names."""
import os
import subprocess

import pytest

import purlcore

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
PURL = os.path.join(ROOT, os.environ.get("PURL_BUILD_DIR", "build"), "purl")


def settings():
    return {s["name"]: s for s in purlcore.render_settings()}


def test_render_settings_have_kinds_ranges_and_defaults():
    s = settings()
    assert set(s) >= {"spp", "seed", "max_depth", "threads", "clamp", "filter_glossy", "model", "integrator",
                      "ply_method"}
    assert (s["spp"]["kind"], s["spp"]["min"], s["spp"]["max"], s["spp"]["default"]) == ("integer", 1, 1 << 20, 64)
    assert s["seed"]["max"] == 2147483647 and s["seed"]["is_integer"]
    assert s["filter_glossy"]["kind"] == "float"
    assert s["ply_method"]["kind"] == "enum" and s["ply_method"]["default_name"] == "elliptical"
    assert [c["name"] for c in s["ply_method"]["choices"]] == purlcore.ply_methods()


def test_choices_are_the_lists_purlcore_names():
    c = purlcore.choices()
    names = lambda key: [x["name"] for x in c[key]["choices"]]  # noqa: E731
    assert names("render.ply_method") == purlcore.ply_methods() == ["elliptical", "local", "circular"]
    assert names("render.multiscale.mode") == purlcore.multiscale_modes()
    assert names("material.model") == purlcore.material_models()
    assert c["render.multiscale.mode"]["default"] == "auto"
    assert [x["value"] for x in c["handedness"]["choices"]] == [-1, 1]


def test_sign_parameters_are_enums_over_the_twist_directions():
    hand = next(p for p in purlcore.yarn_parameters() if p["name"] == "ply_handedness")
    assert hand["is_sign"] and hand["kind"] == "enum" and hand["default_name"] == "Z"
    count = next(p for p in purlcore.yarn_parameters() if p["name"] == "ply_count")
    assert count["kind"] == "integer" and count["is_integer"]


@pytest.mark.skipif(not os.path.exists(PURL), reason="no purl command in the build folder")
@pytest.mark.parametrize("option,bad", [("--spp", "0"), ("--seed", "2147483648"), ("--ply-method", "oval"),
                                        ("--mode", "medium"), ("--integrator", "bidir"), ("--model", "mesh")])
def test_the_command_rejects_what_the_registry_does_not_declare(tmp_path, option, bad):
    run = subprocess.run([PURL, "render", "scene.json", "-o", str(tmp_path / "x.exr"), option, bad],
                         capture_output=True, text=True)
    assert run.returncode == 2, run.stderr


@pytest.mark.skipif(not os.path.exists(PURL), reason="no purl command in the build folder")
def test_the_command_help_lists_the_registry_choices():
    help_text = subprocess.run([PURL, "render", "--help"], capture_output=True, text=True).stdout
    for choice in purlcore.choices()["render.ply_method"]["choices"]:
        assert choice["name"] + ": " + choice["doc"] in " ".join(help_text.split())
