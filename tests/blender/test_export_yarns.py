"""Exported yarn curves equal the source data, per object type (hair Curves, particle hair,
curve objects), and bad curves are reported and skipped instead of failing the export."""
import math
from importlib import import_module

import bpy
import numpy as np
import pytest
from mathutils import Matrix, Vector

from builders import add_curve, add_plane, depsgraph
from curve_math import curves_of, max_distance_to, placed_arrays, sample_curve


def export(purl):
    return import_module(purl.__name__ + ".export").export_scene(depsgraph())


def yarn_arrays(exported, name_prefix):
    sets = [y for y in exported.scene["yarns"] if y["name"].startswith(name_prefix)]
    return [placed_arrays(exported, y) for y in sets]


def test_repeat_end_points_duplicates_each_curves_first_and_last_point(purl):
    yarns = import_module(purl.__name__ + ".export.yarns")
    points = np.arange(15, dtype=np.float32).reshape(5, 3)
    radii = np.arange(5, dtype=np.float32)
    new_points, new_radii, offsets = yarns.repeat_end_points(points, radii, np.array([0, 2, 5]))
    assert offsets.tolist() == [0, 4, 9]
    assert new_radii.tolist() == [0, 0, 1, 1, 2, 2, 3, 4, 4]
    assert np.array_equal(new_points[[0, 1, 2, 3]], points[[0, 0, 1, 1]])


# --- hair Curves ---------------------------------------------------------------------------

def make_hair(scene):
    bpy.ops.object.curves_random_add(location=(0.0, 0.0, 0.0))
    ob = bpy.context.active_object
    ob.location, ob.rotation_euler, ob.scale = (0.5, -0.2, 0.3), (0.3, 0.1, 0.7), (2.0, 2.0, 2.0)
    return ob


def test_hair_curves_points_radii_and_counts_match_the_source(purl, scene):
    ob = make_hair(scene)
    exported = export(purl)
    (arrays,) = yarn_arrays(exported, ob.name)
    assert arrays["basis"] == "catmull_rom"
    data, matrix = ob.data, ob.matrix_world
    offsets = arrays["offsets"]
    assert len(offsets) - 1 == len(data.curves)
    for c in (0, 1, len(data.curves) // 2, len(data.curves) - 1):
        curve = data.curves[c]
        first, count = curve.first_point_index, curve.points_length
        expected = np.array([matrix @ data.points[first + i].position for i in range(count)])
        exported_points = arrays["points"][offsets[c]:offsets[c + 1]]
        assert len(exported_points) == count + 2  # end points repeated for Catmull-Rom
        np.testing.assert_allclose(exported_points[1:-1], expected, atol=1e-5)
        np.testing.assert_allclose(exported_points[0], expected[0], atol=1e-5)
        np.testing.assert_allclose(exported_points[-1], expected[-1], atol=1e-5)
        expected_radii = np.array([2.0 * data.points[first + i].radius for i in range(count)])
        exported_radii = arrays["radii"][offsets[c] + 1:offsets[c + 1] - 1]
        tapered = expected_radii == 0.0  # zero tips are raised to a small positive radius
        np.testing.assert_allclose(exported_radii[~tapered], expected_radii[~tapered], rtol=1e-5)
        assert np.all(exported_radii[tapered] > 0.0)


def test_hair_curves_without_radius_attribute_use_cycles_default(purl, scene):
    ob = make_hair(scene)
    ob.scale = (1.0, 1.0, 1.0)
    ob.data.attributes.remove(ob.data.attributes["radius"])
    (arrays,) = yarn_arrays(export(purl), ob.name)
    np.testing.assert_allclose(arrays["radii"], 0.005, rtol=1e-6)


# --- particle hair -------------------------------------------------------------------------

def make_particle_hair(scene, count=6, children=0, length=0.5):
    ob = add_plane(scene, "Emitter", size=1.0, location=(0.0, 0.0, -0.25))
    ob.modifiers.new("Hair", "PARTICLE_SYSTEM")
    settings = ob.particle_systems[0].settings
    settings.type = "HAIR"
    settings.count = count
    settings.hair_length = length
    settings.display_step = settings.render_step = 3
    settings.root_radius, settings.tip_radius, settings.radius_scale = 1.0, 0.5, 0.02
    settings.use_close_tip = False
    if children:
        settings.child_type = "SIMPLE"
        settings.rendered_child_count = children
        # The viewport child count is child_nbr on 3.x, child_percent on 4.x.
        setattr(settings, "child_nbr" if hasattr(settings, "child_nbr") else "child_percent", children)
    return ob


def test_particle_hair_strands_start_on_the_emitter_and_have_the_path_steps(purl, scene):
    ob = make_particle_hair(scene)
    exported = export(purl)
    (arrays,) = yarn_arrays(exported, ob.name + " / ")
    steps = (1 << 3) + 1
    curves = curves_of(arrays)
    assert len(curves) == 6
    for points, _ in curves:
        assert len(points) == steps + 2
        assert abs(points[1][2] - (-0.25)) < 1e-4          # root on the plane
        assert abs(points[-2][2] - (0.25)) < 1e-3           # straight hair of length 0.5 along +Z
        assert np.all(np.abs(points[:, :2]) <= 0.5 + 1e-4)  # inside the 1 m plane
    radii = arrays["radii"][: steps + 2]
    assert radii[1] == pytest.approx(0.01, rel=1e-4)        # root: 0.5 x radius_scale x root
    assert radii[-2] == pytest.approx(0.005, rel=1e-4)      # tip


def test_particle_hair_with_children_exports_only_the_children(purl, scene):
    ob = make_particle_hair(scene, count=4, children=3)
    (arrays,) = yarn_arrays(export(purl), ob.name + " / ")
    assert len(arrays["offsets"]) - 1 == 4 * 3


# --- curve objects -------------------------------------------------------------------------

def centre_polyline(scene, ob):
    """Blender's own evaluated centre line: a copy without bevel converted to a mesh."""
    copy = ob.copy()
    copy.data = ob.data.copy()
    copy.data.bevel_depth = 0.0
    scene.collection.objects.link(copy)
    graph = depsgraph()
    evaluated = copy.evaluated_get(graph)
    mesh = evaluated.to_mesh()
    points = np.array([evaluated.matrix_world @ v.co for v in mesh.vertices])
    evaluated.to_mesh_clear()
    bpy.data.objects.remove(copy)
    return points


PLACEMENT = Matrix.Translation((0.1, 0.2, -0.3)) @ Matrix.Rotation(0.4, 4, "Z") @ Matrix.Scale(1.5, 4)


@pytest.mark.parametrize("kind, options, basis", [
    ("POLY", {}, "polyline"),
    ("POLY", {"cyclic": True}, "polyline"),
    ("BEZIER", {}, "bezier"),
    ("BEZIER", {"cyclic": True}, "bezier"),
    ("NURBS", {}, "bspline"),
    ("NURBS", {"cyclic": True}, "bspline"),
    ("NURBS", {"endpoint": True}, "catmull_rom"),
    ("NURBS", {"order": 3}, "catmull_rom"),
    ("NURBS", {"weights": [1.0, 3.0, 0.5, 1.0, 2.0]}, "catmull_rom"),
])
def test_curve_object_follows_blenders_own_evaluation(purl, scene, kind, options, basis):
    knots = [(-1.0, 0.0, 0.0), (-0.5, 0.6, 0.2), (0.0, 0.0, 0.4), (0.5, -0.6, 0.2), (1.0, 0.1, 0.0)]
    radii = [1.0, 2.0, 1.5, 1.0, 0.5]
    ob = add_curve(scene, "Yarn", [(kind, knots, dict(options, radius=radii))], bevel_depth=0.02)
    ob.matrix_world = PLACEMENT
    (arrays,) = yarn_arrays(export(purl), "Yarn")
    assert arrays["basis"] == basis
    ((points, closed),) = curves_of(arrays)
    reference = centre_polyline(scene, ob)
    dense = sample_curve(basis, points, closed, samples=400)
    size = np.ptp(reference, axis=0).max()
    # Blender's sampled polyline lies on the exported curve, and the curve spans all of it.
    assert max_distance_to(reference, dense) < 2e-3 * size
    loop = np.concatenate([reference, reference[:1]]) if options.get("cyclic") else reference
    assert max_distance_to(dense[::10], sample_curve("polyline", loop, samples=50)) < 0.02 * size
    # Radius: bevel depth x point radius x object scale (smoothed where the curve is resampled).
    scale = 0.02 * 1.5
    if basis == "catmull_rom":
        assert scale * 0.49 <= arrays["radii"].min() and arrays["radii"].max() <= scale * 2.0
    else:
        assert arrays["radii"].max() == pytest.approx(scale * 2.0, rel=1e-5)


def test_poly_curve_points_and_radii_equal_the_source(purl, scene):
    knots = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.5)]
    ob = add_curve(scene, "Poly", [("POLY", knots, {"radius": [1.0, 0.5, 2.0]})], bevel_depth=0.1)
    ob.matrix_world = PLACEMENT
    (arrays,) = yarn_arrays(export(purl), "Poly")
    expected = np.array([PLACEMENT @ Vector(k) for k in knots])
    np.testing.assert_allclose(arrays["points"], expected, atol=1e-6)
    np.testing.assert_allclose(arrays["radii"], np.array([1.0, 0.5, 2.0]) * 0.1 * 1.5, rtol=1e-6)
    assert arrays["offsets"].tolist() == [0, 3]


def test_curve_far_from_the_origin_keeps_its_precision(purl, scene):
    """At 1e4 m float32 is 1 mm apart; the points go relative to the object and its translation
    into matrix_world (read in double), so 0.1 mm steps survive."""
    knots = [(0.0, 0.0, 0.0), (1e-4, 0.0, 0.0), (1e-4, 1e-4, 1e-4)]
    ob = add_curve(scene, "Far", [("POLY", knots, {})], bevel_depth=1e-5)
    ob.location = (1e4, -1e4, 1e4)
    (arrays,) = yarn_arrays(export(purl), "Far")
    expected = np.array(knots) + np.array([1e4, -1e4, 1e4])
    np.testing.assert_allclose(arrays["points"], expected, rtol=0, atol=1e-8)


def test_splines_of_different_types_become_separate_sets(purl, scene):
    line = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (2.0, 0.5, 0.0), (3.0, 0.0, 0.0)]
    add_curve(scene, "Mixed", [("POLY", line, {}), ("BEZIER", line, {}), ("POLY", line, {})])
    sets = yarn_arrays(export(purl), "Mixed")
    assert sorted((a["basis"], len(a["offsets"]) - 1) for a in sets) == [("bezier", 1), ("polyline", 2)]


# --- bad input -----------------------------------------------------------------------------

def test_curve_without_points_is_reported_not_fatal(purl, scene):
    data = bpy.data.curves.new("Empty", "CURVE")
    data.bevel_depth = 0.1
    scene.collection.objects.link(bpy.data.objects.new("Empty", data))
    add_curve(scene, "Good", [("POLY", [(0, 0, 0), (1, 0, 0)], {})])
    exported = export(purl)
    assert [y["name"] for y in exported.scene["yarns"]] == ["Good"]
    assert any("Empty" in m and "no points" in m for m in exported.problems.messages())


def test_nan_positions_are_reported_and_the_object_skipped(purl, scene):
    ob = add_curve(scene, "Broken", [("POLY", [(0, 0, 0), (1, 0, 0), (2, 0, 0)], {})])
    ob.data.splines[0].points[1].co = (math.nan, 0.0, 0.0, 1.0)
    add_curve(scene, "Good", [("POLY", [(0, 0, 0), (1, 0, 0)], {})])
    exported = export(purl)
    assert [y["name"] for y in exported.scene["yarns"]] == ["Good"]
    (message,) = exported.problems.messages("WARNING")
    assert "Broken" in message and "not finite" in message


def test_zero_radius_is_reported_and_the_object_skipped(purl, scene):
    add_curve(scene, "Flat", [("POLY", [(0, 0, 0), (1, 0, 0)], {"radius": [0.0, 0.0]})])
    add_curve(scene, "NoBevel", [("POLY", [(0, 0, 0), (1, 0, 0)], {})], bevel_depth=0.0)
    exported = export(purl)
    assert exported.scene["yarns"] == []
    messages = exported.problems.messages()
    assert any("Flat" in m and "radius is zero" in m for m in messages)
    assert any("NoBevel" in m and "bevel depth" in m for m in messages)
    assert any("nothing to render" in m for m in messages)


def test_tapered_tips_are_raised_to_a_small_positive_radius(purl, scene):
    add_curve(scene, "Taper", [("POLY", [(0, 0, 0), (1, 0, 0), (2, 0, 0)], {"radius": [1.0, 1.0, 0.0]})])
    (arrays,) = yarn_arrays(export(purl), "Taper")
    assert arrays["radii"].min() > 0.0


def test_an_object_whose_export_fails_is_skipped_with_a_warning(purl, scene, monkeypatch):
    yarns = import_module(purl.__name__ + ".export.yarns")

    def broken_reader(ob, matrix, problems):
        raise RuntimeError("unexpected data")

    monkeypatch.setattr(yarns, "curve_object", broken_reader)
    add_curve(scene, "Odd", [("POLY", [(0, 0, 0), (1, 0, 0)], {})])
    add_plane(scene)
    exported = export(purl)
    assert exported.scene["yarns"] == [] and len(exported.scene["meshes"]) == 1
    assert any("Odd" in m and "unexpected data" in m for m in exported.problems.messages("WARNING"))


def test_empty_hair_curves_object_is_skipped(purl, scene):
    scene.collection.objects.link(bpy.data.objects.new("NoHair", bpy.data.hair_curves.new("NoHair")))
    add_curve(scene, "Good", [("POLY", [(0, 0, 0), (1, 0, 0)], {})])
    exported = export(purl)
    assert [y["name"] for y in exported.scene["yarns"]] == ["Good"]


def test_hair_curves_with_nan_positions_or_zero_radius_are_reported(purl, scene):
    nan_hair, flat_hair = make_hair(scene), make_hair(scene)
    nan_hair.name, flat_hair.name = "NanHair", "FlatHair"
    positions = np.zeros(len(nan_hair.data.points) * 3, dtype=np.float32)
    nan_hair.data.attributes["position"].data.foreach_get("vector", positions)
    positions[4] = math.nan
    nan_hair.data.attributes["position"].data.foreach_set("vector", positions)
    flat_hair.data.attributes["radius"].data.foreach_set("value", np.zeros(len(flat_hair.data.points), np.float32))
    nan_hair.data.update_tag()
    flat_hair.data.update_tag()
    exported = export(purl)
    assert exported.scene["yarns"] == []
    messages = exported.problems.messages("WARNING")
    assert any("NanHair" in m and "not finite" in m for m in messages)
    assert any("FlatHair" in m and "radius is zero" in m for m in messages)


# --- per-curve colours ---------------------------------------------------------------------

def _colour_values(count, seed):
    return np.random.default_rng(seed).uniform(0.0, 1.0, (count, 4)).astype(np.float32)


def test_curve_domain_colour_attribute_is_exported_per_curve(purl, scene):
    ob = make_hair(scene)
    attribute = ob.data.attributes.new("purl_color", "FLOAT_COLOR", "CURVE")
    values = _colour_values(len(ob.data.curves), 1)
    attribute.data.foreach_set("color", values.ravel())
    (arrays,) = yarn_arrays(export(purl), ob.name)
    colours = arrays["curve_colors"]
    assert colours.dtype == np.float32 and colours.shape == (len(ob.data.curves), 3)
    np.testing.assert_allclose(colours, values[:, :3], rtol=1e-6)


def test_point_domain_colour_attribute_is_averaged_per_curve(purl, core, scene):
    ob = make_hair(scene)
    material = bpy.data.materials.new("Tinted")
    material.purl.color_attribute = "tint"  # the name is configurable on the yarn material
    ob.data.materials.append(material)
    attribute = ob.data.attributes.new("tint", "FLOAT_COLOR", "POINT")
    values = _colour_values(len(ob.data.points), 2)
    attribute.data.foreach_set("color", values.ravel())
    (arrays,) = yarn_arrays(export(purl), ob.name)
    for c in (0, len(ob.data.curves) - 1):
        curve = ob.data.curves[c]
        first, count = curve.first_point_index, curve.points_length
        np.testing.assert_allclose(arrays["curve_colors"][c], values[first:first + count, :3].mean(axis=0),
                                   rtol=1e-5)


def test_colours_outside_zero_to_one_are_clipped_with_a_warning(purl, scene):
    ob = make_hair(scene)
    attribute = ob.data.attributes.new("purl_color", "FLOAT_COLOR", "CURVE")
    values = _colour_values(len(ob.data.curves), 3) * 3.0 - 1.0
    attribute.data.foreach_set("color", values.ravel())
    exported = export(purl)
    (arrays,) = yarn_arrays(exported, ob.name)
    np.testing.assert_allclose(arrays["curve_colors"], np.clip(values[:, :3], 0.0, 1.0))
    assert any("clipped" in m for m in exported.problems.messages("WARNING"))


def test_without_a_colour_attribute_no_colours_are_exported(purl, scene):
    ob = make_hair(scene)
    (arrays,) = yarn_arrays(export(purl), ob.name)
    assert "curve_colors" not in arrays


def test_a_missing_named_colour_attribute_is_reported(purl, core, scene):
    ob = make_hair(scene)
    material = bpy.data.materials.new("Tinted")
    material.purl.color_attribute = "no_such_attribute"
    ob.data.materials.append(material)
    exported = export(purl)
    (arrays,) = yarn_arrays(exported, ob.name)
    assert "curve_colors" not in arrays
    assert any("no_such_attribute" in m for m in exported.problems.messages("WARNING"))


def test_curve_colours_reach_the_renderer(purl, core, scene):
    """Black and white per-curve colours give different images once purlcore reads curve_colors;
    until then (the key is ignored) the two images are the same and the test skips."""
    ob = make_hair(scene)
    ob.scale = (1.0, 1.0, 1.0)
    # Even radii: random hair's tapered tips make the native Catmull-Rom conversion reject them.
    ob.data.attributes["radius"].data.foreach_set("value", np.full(len(ob.data.points), 0.02, np.float32))
    attribute = ob.data.attributes.new("purl_color", "FLOAT_COLOR", "CURVE")
    scene.world.color = (0.5, 0.5, 0.5)
    means = []
    for value in (0.0, 1.0):
        attribute.data.foreach_set("color", np.full(len(ob.data.curves) * 4, value, np.float32))
        ob.data.update_tag()
        exported = export(purl)
        (arrays,) = yarn_arrays(exported, ob.name)
        assert np.all(arrays["curve_colors"] == value)
        passes = core.render(exported.scene, exported.arrays, spp=4, seed=1)
        hit = passes["YarnID"][..., 0] > 0
        assert hit.any()
        means.append(float(passes["Combined"][..., :3][hit].mean()))
    if means[0] == means[1]:
        pytest.skip("purlcore does not read curve_colors yet (the images are identical)")
    assert means[0] < means[1]
