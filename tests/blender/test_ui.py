"""Panels: poll only for Purl, and every property a draw() shows exists (headless Blender has no
UILayout, so a recording stand-in takes its place)."""
from importlib import import_module
from types import SimpleNamespace

import bpy
import numpy as np
import pytest

from builders import add_light, compat


class RecordingLayout:
    """Accepts any layout call; checks that prop() names a real property of its data."""

    def __init__(self, shown):
        self.shown = shown

    def prop(self, data, name, **kwargs):
        assert name in data.bl_rna.properties, "{} has no property {}".format(data, name)
        self.shown.append(name)
        return self

    def __getattr__(self, name):
        if name in {"use_property_split", "active", "alert", "enabled"}:
            return False
        return lambda *args, **kwargs: self

    def __setattr__(self, name, value):
        object.__setattr__(self, name, value)


def draw(panel_class, context):
    shown = []
    panel = SimpleNamespace(layout=RecordingLayout(shown))
    panel_class.draw(panel, context)
    return shown


@pytest.fixture
def ui(purl):
    return import_module(purl.__name__ + ".ui")


def test_panels_poll_only_for_purl(ui, scene):
    material = bpy.data.materials.new("Wool")
    context = SimpleNamespace(engine="CYCLES", material=material, scene=scene, light=None)
    assert not ui.PURL_PT_material.poll(context) and not ui.PURL_PT_render.poll(context)
    context.engine = "PURL"
    assert ui.PURL_PT_material.poll(context) and ui.PURL_PT_render.poll(context)


def test_material_panel_shows_every_native_parameter(ui, core, scene):
    material = bpy.data.materials.new("Wool")
    context = SimpleNamespace(engine="PURL", material=material, scene=scene)
    shown = draw(ui.PURL_PT_material, context)
    if ui.PURL_PT_material_advanced.poll(context):  # the physics behind the artist controls
        shown += draw(ui.PURL_PT_material_advanced, context)
    names = {p["name"] for p in core.material_parameters(material.purl.model)}
    plies = set()
    if ui.PURL_PT_material_plies.poll(context):  # models that declare ply colours
        getattr(material.purl, "params_" + material.purl.model).ply_color_count = 3
        plies = set(draw(ui.PURL_PT_material_plies, context))
        assert {"ply_color_count", "ply_color_1", "ply_color_3"} <= plies and "ply_color_4" not in plies
    assert names - {n for n in names if n.startswith("ply_color_")} <= set(shown)
    assert {"model_choice", "color_attribute"} <= set(shown)


@pytest.mark.parametrize("kind", ["POINT", "SPOT", "SUN", "AREA"])
def test_light_panel_draws_each_type(ui, scene, kind):
    light = add_light(scene, kind).data
    shown = draw(ui.PURL_PT_light, SimpleNamespace(engine="PURL", light=light, scene=scene))
    assert "energy" in shown and "color" in shown


def test_render_and_world_panels_draw(ui, scene):
    context = SimpleNamespace(engine="PURL", scene=scene)
    assert {"samples", "multiscale_mode", "ply_method"} <= set(draw(ui.PURL_PT_render, context))
    compat.enable_nodes(scene.world)
    assert "default_value" in draw(ui.PURL_PT_world, context)


def test_blenders_own_panels_accept_purl(ui):
    assert "PURL" in bpy.types.RENDER_PT_format.COMPAT_ENGINES
    assert "PURL" in bpy.types.DATA_PT_lens.COMPAT_ENGINES


def test_whole_number_parameters_are_integer_fields(purl, core):
    declared = {p["name"] for p in core.yarn_parameters() if p["is_integer"]}
    assert {"ply_count", "fiber_count", "map_resolution", "migration_variants", "seed"} == declared
    material = bpy.data.materials.new("Wool")
    geometry = material.purl.yarn_geometry.bl_rna.properties
    assert all(geometry[name].type == "INT" for name in declared)
    assert geometry["ply_radius"].type == "FLOAT"
    assert material.purl.params_bysdf.bl_rna.properties["ply_color_count"].type == "INT"


def test_yarn_geometry_is_exported_and_read_natively(purl, core, scene):
    material = bpy.data.materials.new("Wool")
    material.purl.model = "bysdf"
    material.purl.yarn_geometry.ply_count = 4
    material.purl.yarn_geometry.fiber_count = 40
    panel = import_module(purl.__name__ + ".ui").PURL_PT_material_geometry
    context = SimpleNamespace(engine="PURL", material=material)
    assert panel.poll(context)
    assert {"ply_count", "fiber_count", "ply_twist"} <= set(draw(panel, context))
    exported = import_module(purl.__name__ + ".export.materials").yarn_material(material, None)
    assert exported["yarn"]["ply_count"] == 4.0 and exported["yarn"]["fiber_count"] == 40.0
    scene_object = {"version": 1, "camera": {"position": [0, -3, 0], "look_at": [0, 0, 0]},
                    "film": {"width": 8, "height": 8},
                    "yarns": [{"name": "y", "arrays": "y", "material": exported}]}
    arrays = {"y": {"points": np.array([[-1, 0, 0], [-0.3, 0, 0], [0.3, 0, 0], [1, 0, 0]], np.float32),
                    "radii": np.full(4, 0.1, np.float32), "offsets": np.array([0, 4], np.int32),
                    "basis": "bspline"}}
    core.RenderJob(scene_object, arrays)  # parses the material, yarn geometry included
