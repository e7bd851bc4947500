"""File > Import > Yarn Curves (.bcc): every curve type, open and closed, Y-up and Z-up, comes back
out of the exporter as the curves purlcore renders from the file itself (BCC -> Blender object ->
export -> same control points, radii and closed flags); bad files leave the scene untouched."""
import os
from importlib import import_module

import bpy
import numpy as np
import pytest

from bcc_files import write_bcc
from builders import depsgraph

GLOVE = os.path.join(os.environ.get("PURL_SHARED_DATA_DIR", os.path.join(
    os.path.dirname(__file__), "..", "..", "..", "shared", "data")), "glove.bcc")
# Points per curve: (open, closed), whole segments for every type (Bezier: 3k + 1 open, 3k closed).
COUNTS = {"C0": (7, 6), "BS": (7, 6), "PL": (5, 5), "BZ": (7, 6)}


@pytest.fixture
def importer(purl):
    return import_module(purl.__name__ + ".bcc_import")


def wavy(count, offset, closed):
    """Points on a wavy loop (closed) or a wavy line, distinct per curve."""
    t = np.linspace(0.0, 2 * np.pi, count, endpoint=False) if closed else np.linspace(-1.0, 1.0, count)
    if closed:
        return np.stack([np.cos(t), np.sin(t) + offset, 0.2 * np.sin(3 * t)], axis=1)
    return np.stack([t, 0.3 * np.sin(4 * t) + offset, 0.1 * t * t], axis=1)


def exported_curves(purl, core):
    exported = import_module(purl.__name__ + ".export").export_scene(depsgraph())
    sets = [exported.arrays[y["arrays"]] for y in exported.scene["yarns"]]
    assert len(sets) == 1, [y["name"] for y in exported.scene["yarns"]]
    return core.convert_curves(sets[0])


@pytest.mark.parametrize("up", [1, 2], ids=["Y-up", "Z-up"])
@pytest.mark.parametrize("kind", sorted(COUNTS))
def test_round_trip_keeps_the_render_curves_and_closed_loops(purl, core, importer, scene, tmp_path, kind, up):
    open_count, closed_count = COUNTS[kind]
    curves = [(wavy(open_count, 0.0, False), False), (wavy(closed_count, 3.0, True), True),
              (wavy(open_count, -3.0, False), False)]
    path = write_bcc(tmp_path / "yarns.bcc", kind, curves, up)
    ob, _ = importer.import_bcc(bpy.context, path, radius=0.05)
    expected = core.load_bcc(path, 0.05)
    got = exported_curves(purl, core)
    assert list(got["closed"]) == [False, True, False] == list(expected["closed"])
    assert list(got["offsets"]) == list(expected["offsets"])
    assert list(got["segment_offsets"]) == list(expected["segment_offsets"])
    assert np.allclose(got["points"], expected["points"], atol=2e-5)
    assert np.allclose(got["radii"], 0.05, atol=1e-6)
    assert ob.active_material is not None and ob.active_material.purl.model == core.material_models()[0]


def test_the_radius_defaults_to_the_files_estimate_and_scale_applies(purl, core, importer, scene, tmp_path):
    curves = [(wavy(7, 0.3 * k, False), False) for k in range(6)]  # parallel wavy yarns 0.3 apart
    path = write_bcc(tmp_path / "rows.bcc", "BS", curves)
    estimate = core.read_bcc(path)["radius_estimate"]
    assert 0.1 < estimate < 0.16
    importer.import_bcc(bpy.context, path, scale=0.5)
    got = exported_curves(purl, core)
    assert np.allclose(got["radii"], 0.5 * estimate, rtol=1e-5)
    assert np.allclose(got["points"], 0.5 * core.load_bcc(path, 1.0)["points"], atol=1e-5)


@pytest.mark.skipif(not os.path.exists(GLOVE), reason="no shared glove.bcc")
def test_the_glove_imports_with_its_closed_loops(purl, core, importer, scene):
    ob, data = importer.import_bcc(bpy.context, GLOVE)
    assert bpy.context.view_layer.objects.active == ob and ob.select_get()
    got = exported_curves(purl, core)
    assert len(got["closed"]) == 70 and got["closed"].all()
    assert np.allclose(got["points"], core.load_bcc(GLOVE, data["radius"])["points"], atol=1e-3)


def test_a_bad_file_is_reported_and_the_scene_untouched(core, importer, scene, tmp_path):
    path = write_bcc(tmp_path / "broken.bcc", "BS", [(wavy(7, 0.0, False), False)])
    with open(path, "r+b") as f:
        f.truncate(os.path.getsize(path) - 6)
    before = (len(bpy.data.objects), len(bpy.data.curves), len(getattr(bpy.data, "hair_curves", [])),
              len(bpy.data.materials))
    with pytest.raises(RuntimeError, match="broken.bcc"):
        bpy.ops.purl.import_bcc(filepath=path)
    with pytest.raises(importer.BccImportError, match="broken.bcc: .*truncated"):
        importer.import_bcc(bpy.context, path)
    after = (len(bpy.data.objects), len(bpy.data.curves), len(getattr(bpy.data, "hair_curves", [])),
             len(bpy.data.materials))
    assert after == before


def test_closed_catmull_rom_loops_stay_loops_of_the_same_points(purl, core, importer, scene, tmp_path):
    curves = [(wavy(6, 3.0 * k, True), True) for k in range(3)]
    path = write_bcc(tmp_path / "loops.bcc", "C0", curves, up=1)
    ob, _ = importer.import_bcc(bpy.context, path, radius=0.05)
    if ob.type == "CURVES":  # Blender 4.x: Catmull-Rom curves (the default type), cyclic
        assert len(ob.data.points) == 18
        cyclic = np.zeros(3, dtype=bool)
        ob.data.attributes["cyclic"].data.foreach_get("value", cyclic)
        assert cyclic.all()
    else:
        assert all(spline.use_cyclic_u for spline in ob.data.splines)
    got, expected = exported_curves(purl, core), core.load_bcc(path, 0.05)
    assert got["closed"].all() and np.allclose(got["points"], expected["points"], atol=2e-5)
