"""The benchmark's measures (bench/metrics.py) and the native pieces it relies on: the trace-only
baseline integrator and RenderJob rendering again on the scene it built."""
import json
import pathlib
import sys

import numpy as np
import pytest

import purlcore

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "bench"))
import metrics  # noqa: E402

from test_purlcore import scene, yarn_arrays  # noqa: E402


def test_relative_mse_removes_the_references_own_noise():
    rng = np.random.default_rng(3)
    truth = rng.uniform(0.2, 2.0, (64, 64, 3))
    sigma_image, sigma_half = 0.05, 0.02
    image = truth + rng.normal(0, sigma_image, truth.shape)
    a = truth + rng.normal(0, sigma_half, truth.shape)
    b = truth + rng.normal(0, sigma_half, truth.shape)
    expected = np.mean(sigma_image**2 / (truth**2 + metrics.EPSILON))
    measured, noise = metrics.relative_mse(image, a, b)
    assert measured == pytest.approx(expected, rel=0.05)
    assert noise == pytest.approx(np.mean(sigma_half**2 / 2 / (truth**2 + metrics.EPSILON)), rel=0.1)
    # Without the correction the error would be too high by the reference's noise.
    raw = np.mean((image - 0.5 * (a + b)) ** 2 / ((0.5 * (a + b)) ** 2 + metrics.EPSILON))
    assert raw > measured * 1.05


def test_time_to_quality_interpolates_and_extrapolates():
    points = [(1.0, 1.0), (4.0, 0.25), (16.0, 1 / 16)]  # relMSE = 1 / time
    t, extrapolated = metrics.time_to_quality(points, 0.5)
    assert t == pytest.approx(2.0) and not extrapolated
    t, extrapolated = metrics.time_to_quality(points, 1 / 64)
    assert t == pytest.approx(64.0) and extrapolated
    assert metrics.time_to_quality([], 0.1) == (None, False)


def test_flip_is_zero_for_equal_images_and_grows_with_difference():
    pytest.importorskip("flip_evaluator")
    image = np.random.default_rng(1).uniform(0, 1, (32, 32, 3)).astype(np.float32)
    assert metrics.flip(image, image) == pytest.approx(0.0, abs=1e-6)
    assert metrics.flip(image * 0.5, image) > metrics.flip(image * 0.9, image) > 0


def test_trace_integrator_shades_first_hits_a_constant_and_traces_camera_rays_only():
    s = scene(spp=2)
    s["world"] = {"color": [0, 0, 0]}
    s["render"]["integrator"] = "trace"
    job = purlcore.RenderJob(s, {"knit": yarn_arrays()})
    job.start()
    job.wait()
    stats = job.stats()
    assert stats["rays"] == stats["samples"]  # no shadow or bounce rays
    colour = job.passes()["Combined"][..., :3]
    assert colour.max() == pytest.approx(0.5, abs=1e-6)
    assert 0 < np.count_nonzero(colour[..., 0] > 0.49) < colour.shape[0] * colour.shape[1]
    with pytest.raises(purlcore.Error, match="integrator"):
        s["render"]["integrator"] = "photon"
        purlcore.RenderJob(s, {"knit": yarn_arrays()})


def test_render_job_renders_again_with_other_settings():
    job = purlcore.RenderJob(scene(spp=2), {"knit": yarn_arrays()})
    job.start(spp=1, seed=1)
    job.wait()
    first = job.passes()["Combined"].copy()
    job.start(spp=3, seed=2)
    job.wait()
    assert job.stats()["samples"] == 24 * 16 * 3
    again = job.passes()["Combined"]
    assert not np.array_equal(first, again)
    job.start(spp=1, seed=1)
    job.wait()
    np.testing.assert_array_equal(job.passes()["Combined"], first)  # same (scene, seed, spp), same image
    json.dumps(job.stats())
