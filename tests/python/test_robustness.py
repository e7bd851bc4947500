"""Robustness of render jobs (docs/robustness.md): cancelling twice, two renders of one scene at
once, a job started again while it runs, and bit-identical images for 1 and 2 threads."""
import math

import numpy as np
import pytest

import purlcore


def yarn_arrays():
    pts, offsets = [], [0]
    for c in range(3):
        for i in range(10):
            pts.append((-0.5 + 0.1 * i, -0.2 + 0.2 * c, 0.05 * math.sin(i + c)))
        offsets.append(len(pts))
    pts = np.asarray(pts, dtype=np.float32)
    return {"points": pts, "radii": np.full(len(pts), 0.05, dtype=np.float32),
            "offsets": np.asarray(offsets, dtype=np.int64)}


def scene(width=32, height=24, spp=4):
    return {
        "camera": {"position": [0, -1.6, 1.0], "look_at": [0, 0, 0], "lens": 40},
        "film": {"width": width, "height": height},
        "render": {"spp": spp, "seed": 3},
        "world": {"color": [0.6, 0.7, 0.8]},
        "lights": [{"type": "area", "position": [1, -1, 2], "look_at": [0, 0, 0], "power": 50}],
        "yarns": [{"arrays": "knit", "material": {"model": "bysdf"}}],
    }


def test_cancelling_twice_and_after_the_end_is_safe():
    job = purlcore.RenderJob(scene(200, 200, 4096), {"knit": yarn_arrays()})
    job.start()
    job.cancel()
    job.cancel()
    assert job.wait(timeout=10.0)
    assert job.cancelled
    job.cancel()  # after the end: nothing to stop, nothing breaks
    assert job.done and job.error is None


def test_starting_a_running_job_again_is_an_error_not_a_second_render():
    job = purlcore.RenderJob(scene(200, 200, 4096), {"knit": yarn_arrays()})
    job.start()
    with pytest.raises(RuntimeError, match="still rendering"):
        job.start()
    job.cancel()
    assert job.wait(timeout=10.0)


def test_two_renders_of_one_scene_at_once_give_the_same_image():
    jobs = [purlcore.RenderJob(scene(), {"knit": yarn_arrays()}) for _ in range(2)]
    for job in jobs:
        job.start(threads=1)
    for job in jobs:
        assert job.wait(timeout=60.0)
    first, second = (job.passes() for job in jobs)
    assert first["Combined"].sum() > 0
    for name in first:
        assert np.array_equal(first[name], second[name]), name


def test_one_and_two_threads_give_bit_identical_images():
    job = purlcore.RenderJob(scene(), {"knit": yarn_arrays()})
    images = []
    for threads in (1, 2, 1):
        job.start(threads=threads)
        assert job.wait(timeout=60.0)
        images.append(job.passes()["Combined"].copy())
    assert images[0].tobytes() == images[1].tobytes() == images[2].tobytes()
