"""Yarn material settings come from the native parameter declaration; presets round-trip."""
import json
import os
from importlib import import_module

import bpy
import numpy as np
import pytest

from builders import add_curve, depsgraph


@pytest.fixture
def material(core, scene):
    material = bpy.data.materials.new("Wool")
    add_curve(scene, "Yarn", [("POLY", [(0, 0, 0), (1, 0, 0)], {})]).data.materials.append(material)
    return material


def _float32(value):
    return float(np.float32(value))


def test_every_native_parameter_is_a_property_with_its_range_default_and_doc(core, material):
    settings = material.purl
    for model in core.material_models():
        group = getattr(settings, "params_" + model)
        for parameter in core.material_parameters(model):
            prop = group.bl_rna.properties[parameter["name"]]
            assert prop.hard_min == pytest.approx(_float32(max(parameter["min"], -3e38)))
            assert prop.hard_max == pytest.approx(_float32(min(parameter["max"], 3e38)))
            default = parameter["default"]
            if parameter["components"] == 1:
                assert prop.default == pytest.approx(_float32(default))
            else:
                assert list(prop.default_array) == pytest.approx([_float32(v) for v in default])
                assert (prop.subtype == "COLOR") == bool(parameter["is_color"])
            assert parameter["doc"] in prop.description


@pytest.mark.parametrize("model", ["placeholder", "bysdf"])
def test_exported_material_carries_the_settings(purl, core, material, model):
    if model not in core.material_models():
        pytest.skip("purlcore has no '{}' model".format(model))
    material.purl.model = model
    group = getattr(material.purl, "params_" + model)
    for parameter in core.material_parameters(model):
        high = parameter["max"]
        setattr(group, parameter["name"], int(high) if isinstance(getattr(group, parameter["name"]), int)
                else high if parameter["components"] == 1 else [high] * parameter["components"])
    exported = import_module(purl.__name__ + ".export").export_scene(depsgraph())
    (yarn,) = exported.scene["yarns"]
    assert yarn["material"]["model"] == model
    for parameter in core.material_parameters(model):
        expected = parameter["max"] if parameter["components"] == 1 else [parameter["max"]] * parameter["components"]
        assert yarn["material"][parameter["name"]] == pytest.approx(expected, rel=1e-6), parameter["name"]


def test_preset_round_trip(purl, core, material, tmp_path):
    presets = import_module(purl.__name__ + ".presets")
    settings = material.purl
    names = [p["name"] for p in core.material_parameters(settings.model)]
    group = getattr(settings, "params_" + settings.model)
    before = {name: np.array(getattr(group, name), dtype=float).tolist() for name in names}
    settings.color_attribute = "yarn_colour"
    path = presets.save_preset(material, "Round trip", folder=str(tmp_path))
    with open(path) as f:
        saved = json.load(f)
    assert saved["name"] == "Round trip" and saved["material"]["model"] == settings.model
    for name in names:  # change everything, then load the preset back
        prop = group.bl_rna.properties[name]
        setattr(group, name, prop.hard_min if prop.array_length == 0 else [prop.hard_min] * prop.array_length)
    settings.color_attribute = ""
    assert presets.apply_preset(material, presets.read_preset(path)) == []
    after = {name: np.array(getattr(group, name), dtype=float).tolist() for name in names}
    for name in names:
        assert after[name] == pytest.approx(before[name]), name
    assert settings.color_attribute == "yarn_colour"


def test_presets_menu_lists_shipped_and_user_presets(purl, core, tmp_path, monkeypatch):
    presets = import_module(purl.__name__ + ".presets")
    monkeypatch.setattr(presets, "user_preset_dir", lambda create=False: str(tmp_path))
    (tmp_path / "mine.json").write_text(json.dumps({"name": "My wool", "material": {"model": "placeholder"}}))
    labels = [label for label, _ in presets.list_presets()]
    assert "My wool" in labels


def test_shipped_presets_apply_without_warnings(purl, core, material):
    presets = import_module(purl.__name__ + ".presets")
    shipped = [path for _, path in presets.list_presets() if os.path.basename(os.path.dirname(path)) == "presets"]
    assert len(shipped) >= 5
    for path in shipped:
        assert presets.apply_preset(material, presets.read_preset(path)) == [], path


def test_bad_presets_are_reported(purl, core, material, tmp_path):
    presets = import_module(purl.__name__ + ".presets")
    broken = tmp_path / "broken.json"
    broken.write_text("{not json")
    with pytest.raises(ValueError, match="broken.json: not valid JSON"):
        presets.read_preset(str(broken))
    no_material = tmp_path / "empty.json"
    no_material.write_text("{}")
    with pytest.raises(ValueError, match="needs a \"material\""):
        presets.read_preset(str(no_material))
    warnings = presets.apply_preset(material, {"material": {"model": "placeholder", "fluffiness": 3}})
    assert warnings == ["unknown parameter 'fluffiness' ignored"]
    assert presets.apply_preset(material, {"material": {"model": "velvet"}}) == [
        "model 'velvet' is not known to this version of Purl"]


def test_preset_operator_reports_instead_of_raising(purl, core, material, tmp_path):
    broken = tmp_path / "broken.json"
    broken.write_text("[]")
    # An operator's error report reaches a Python caller as RuntimeError; Blender itself goes on.
    with bpy.context.temp_override(material=material):
        with pytest.raises(RuntimeError, match="needs a \"material\""):
            bpy.ops.purl.preset_apply(filepath=str(broken))
