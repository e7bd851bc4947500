"""The purlcore module: scenes from dicts and numpy arrays, renders, jobs, errors."""
import math
import os
import shutil
import subprocess
import time

import numpy as np
import pytest

import purlcore


def yarn_arrays(curves=3, points=10, radius=0.05):
    pts, offsets = [], [0]
    for c in range(curves):
        for i in range(points):
            pts.append((-0.5 + 0.1 * i, -0.2 + 0.2 * c, 0.05 * math.sin(i + c)))
        offsets.append(len(pts))
    pts = np.asarray(pts, dtype=np.float32)
    return {
        "points": pts,
        "radii": np.full(len(pts), radius, dtype=np.float32),
        "offsets": np.asarray(offsets, dtype=np.int64),
    }


def scene(width=24, height=16, spp=4, **extra):
    s = {
        "camera": {"position": [0, -1.6, 1.0], "look_at": [0, 0, 0], "lens": 40},
        "film": {"width": width, "height": height},
        "render": {"spp": spp},
        "world": {"color": [0.6, 0.7, 0.8]},
        "lights": [{"type": "area", "position": [1, -1, 2], "look_at": [0, 0, 0], "power": 50}],
        "yarns": [{"arrays": "knit", "material": {"model": "placeholder", "color": [0.8, 0.2, 0.1]}}],
    }
    s.update(extra)
    return s


def test_render_returns_all_passes_with_yarn_pixels():
    passes = purlcore.render(scene(), {"knit": yarn_arrays()})
    assert set(passes) == {"Combined", "Depth", "Normal", "YarnID", "PlyIndex", "PlyUV", "Denoising Albedo",
                           "Denoising Normal"}
    assert passes["Combined"].shape == (16, 24, 4)
    assert passes["Depth"].shape == (16, 24, 1)
    assert passes["PlyUV"].shape == (16, 24, 2)
    ids = passes["YarnID"][..., 0]
    assert (ids > 0).sum() > 20, "the yarns should cover part of the image"
    assert set(np.unique(ids)) <= {0.0, 1.0, 2.0, 3.0}
    assert np.all(passes["PlyIndex"][ids == 0] == -1), "no ply where no yarn"
    yarn = passes["Combined"][ids > 0]
    assert np.all(np.isfinite(yarn)) and yarn[:, 0].mean() > yarn[:, 2].mean(), "red yarn"


def test_same_seed_same_image_other_seed_other_image():
    arrays = {"knit": yarn_arrays()}
    a = purlcore.render(scene(), arrays, seed=3)["Combined"]
    b = purlcore.render(scene(), arrays, seed=3, threads=1)["Combined"]
    c = purlcore.render(scene(), arrays, seed=4)["Combined"]
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)


def test_unknown_key_is_an_error_naming_it():
    s = scene()
    s["yarns"][0]["materail"] = {}
    with pytest.raises(purlcore.Error, match=r"yarns\[0\]\.materail: unknown key"):
        purlcore.RenderJob(s, {"knit": yarn_arrays()})


def test_bad_arrays_are_errors():
    arrays = yarn_arrays()
    arrays["points"][5, 1] = np.nan
    with pytest.raises(purlcore.Error, match="not finite"):
        purlcore.RenderJob(scene(), {"knit": arrays})
    arrays = yarn_arrays()
    arrays["radii"][:] = 0
    with pytest.raises(purlcore.Error, match="radius"):
        purlcore.RenderJob(scene(), {"knit": arrays})
    with pytest.raises(purlcore.Error, match="no array set"):
        purlcore.RenderJob(scene(), {})
    arrays = yarn_arrays()
    arrays["points"] = arrays["points"][:, :2]
    with pytest.raises(purlcore.Error, match=r"shape \(N, 3\)"):
        purlcore.RenderJob(scene(), {"knit": arrays})


def test_job_progress_cancel_and_nothing_written(tmp_path):
    job = purlcore.RenderJob(scene(width=200, height=200, spp=2048), {"knit": yarn_arrays()})
    job.start()
    time.sleep(0.2)
    assert 0.0 <= job.progress < 1.0
    before = job.progress
    job.cancel()
    assert job.wait(timeout=60.0)
    # Counted, not timed: each thread finishes at most the pixel it was in (200 pixels = 0.005).
    assert job.progress - before <= 0.005
    assert job.cancelled and job.done
    out = tmp_path / "never.exr"
    with pytest.raises(RuntimeError, match="cancelled"):
        job.write(str(out))
    assert not out.exists()


def test_progress_callback_can_cancel():
    calls = []

    def progress(fraction):
        calls.append(fraction)
        return len(calls) < 2

    with pytest.raises(purlcore.Error, match="cancelled"):
        purlcore.render(scene(width=200, height=200, spp=2048), {"knit": yarn_arrays()}, progress=progress)
    assert calls


def test_write_multilayer_exr_with_blender_channel_names(tmp_path):
    job = purlcore.RenderJob(scene(), {"knit": yarn_arrays()})
    job.start()
    job.wait()
    exr, png = tmp_path / "r.exr", tmp_path / "r.png"
    job.write(str(exr), str(png))
    assert exr.stat().st_size > 0 and png.stat().st_size > 0
    stats = job.stats()
    assert stats["samples"] == 24 * 16 * 4 and stats["rays"] > stats["samples"]
    if shutil.which("oiiotool"):
        info = subprocess.run(["oiiotool", "--info", "-v", str(exr)], capture_output=True, text=True).stdout
        for channel in ("ViewLayer.Combined.R", "ViewLayer.Combined.A", "ViewLayer.Depth.Z",
                        "ViewLayer.Normal.X", "ViewLayer.YarnID.X", "ViewLayer.PlyIndex.X",
                        "ViewLayer.PlyUV.U", "ViewLayer.PlyUV.V"):
            assert channel in info


def test_meshes_from_arrays_and_holdout():
    plane = {
        "vertices": np.array([[-5, -5, -0.1], [5, -5, -0.1], [5, 5, -0.1], [-5, 5, -0.1]], np.float32),
        "triangles": np.array([[0, 1, 2], [0, 2, 3]]),
    }
    s = scene(meshes=[{"arrays": "floor", "holdout": True}])
    passes = purlcore.render(s, {"knit": yarn_arrays(), "floor": plane})
    alpha = passes["Combined"][..., 3]
    ids = passes["YarnID"][..., 0]
    # The floor fills the view: where it is seen, it is cut out; only yarn pixels stay opaque.
    assert (alpha == 0).mean() > 0.3
    assert np.all(ids[alpha == 1] > 0) and (alpha == 1).sum() > 20
    opaque = purlcore.render(scene(meshes=[{"arrays": "floor"}]), {"knit": yarn_arrays(), "floor": plane})
    assert np.all(opaque["Combined"][..., 3] == 1)


def test_material_parameters_carry_units_and_ranges():
    params = purlcore.material_parameters("placeholder")
    names = {p["name"] for p in params}
    assert {"color", "roughness", "specular"} <= names
    for p in params:
        assert p["min"] <= (p["default"][0] if p["components"] == 3 else p["default"]) <= p["max"]
        assert p["doc"]
    with pytest.raises(ValueError):
        purlcore.material_parameters("no-such-model")


def test_project_points_follows_the_camera():
    s = {"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "up": [0, 1, 0], "lens": 50},
         "film": {"width": 640, "height": 480}, "meshes": [{"arrays": "not-needed"}]}
    xy = purlcore.project_points(s, np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 9]], np.float32))
    # 50 mm over a 36 mm sensor: 1 m at 5 m is 640 * 50 / 36 / 5 px from the centre.
    offset = 640 * 50 / 36 / 5
    assert np.allclose(xy[0], [320, 240], atol=1e-3)
    assert np.allclose(xy[1], [320 + offset, 240], atol=1e-3)
    assert np.allclose(xy[2], [320, 240 - offset], atol=1e-3)
    assert np.all(np.isnan(xy[3])), "behind the camera"


def bysdf_scene(**render):
    s = scene()
    s["render"].update(render)
    s["yarns"][0]["material"] = {"model": "bysdf", "yarn": {"preset": "prototype", "fiber_count": 12}}
    return s


def test_explicit_curves_are_plies_and_fibers_inside_the_yarn():
    arrays = {"knit": yarn_arrays(curves=2, radius=0.05)}
    plies = purlcore.explicit_curves(bysdf_scene(), arrays, "", "ply")
    fibers = purlcore.explicit_curves(bysdf_scene(), arrays, "", "fiber")
    ply_count = next(p["default"] for p in purlcore.yarn_parameters() if p["name"] == "ply_count")
    ply_radius = next(p["default"] for p in purlcore.yarn_parameters() if p["name"] == "ply_radius")
    assert len(plies["offsets"]) - 1 == 2 * ply_count
    assert len(fibers["offsets"]) - 1 == 2 * ply_count * 12
    np.testing.assert_allclose(plies["radii"], ply_radius * 0.05, rtol=1e-5)
    assert np.all(fibers["radii"] < plies["radii"].min())
    # Every control point stays near its yarn: the yarns run along x at y = -0.2 and 0.
    # (B-spline control points may stand off the curve by a little, hence the 1.5 radii.)
    for curves in (plies, fibers):
        pts = curves["points"]
        nearest_yarn = np.minimum(np.abs(pts[:, 1] + 0.2), np.abs(pts[:, 1]))
        assert nearest_yarn.max() < 1.5 * 0.05
        assert np.all(np.isfinite(pts))
        assert curves["offsets"][0] == 0 and curves["offsets"][-1] == len(pts)
        assert np.all(np.diff(curves["offsets"]) >= 4)
        assert curves["segment_offsets"][-1] == len(curves["segments"])


def test_explicit_curves_refuse_beyond_the_memory_budget():
    arrays = {"knit": yarn_arrays(curves=2, radius=0.05)}
    with pytest.raises(purlcore.Error, match="memory|budget"):
        purlcore.explicit_curves(bysdf_scene(explicit={"memory_budget_gib": 0.0001}), arrays, "", "fiber")
    with pytest.raises(ValueError, match="ply' or 'fiber"):
        purlcore.explicit_curves(bysdf_scene(), arrays, "", "bysdf")


def test_load_bcc_returns_the_curve_tables():
    glove = os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data", "glove.bcc")
    if not os.path.exists(glove):
        pytest.skip("../shared/data/glove.bcc is not here")
    c = purlcore.load_bcc(glove, 0.1)
    offsets, segments, seg_offsets = c["offsets"], c["segments"], c["segment_offsets"]
    assert len(offsets) == len(c["closed"]) + 1 == 71  # 70 loops
    assert offsets[0] == 0 and offsets[-1] == len(c["points"]) == 234148
    assert np.all(np.diff(offsets) > 0) and seg_offsets[-1] == len(segments)
    assert np.all(segments[seg_offsets[1:] - 1] + 3 < offsets[1:])  # each curve's last segment is its own
    np.testing.assert_allclose(c["radii"], 0.1)
