"""Robustness of render jobs (docs/robustness.md): cancelling twice, two renders of one scene at
once, a job started again while it runs, and bit-identical images for 1 and 2 threads; Ctrl-C
during purlcore.render, unknown array keys, errors as purlcore.Error, bad output paths."""
import math
import os
import signal
import threading

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


@pytest.fixture
def sigint_raises():
    """Python's own Ctrl+C handler for the test: a shell that starts the suite in the background
    (`cmd &`) starts it with SIGINT ignored, and Python then installs no handler, so the signal
    the tests send would be dropped and the render of minutes would run to its end."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


@pytest.mark.usefixtures("sigint_raises")
def test_ctrl_c_interrupts_render():
    # A render of minutes; SIGINT from another thread once it runs. purlcore.render checks
    # Python's signals between waits of 0.1 s, cancels the render and raises KeyboardInterrupt.
    started = threading.Event()

    def progress(fraction):
        started.set()

    def interrupt():
        started.wait(60)
        os.kill(os.getpid(), signal.SIGINT)

    sender = threading.Thread(target=interrupt)
    sender.start()
    with pytest.raises(KeyboardInterrupt):
        purlcore.render(scene(200, 200, 1 << 16), {"knit": yarn_arrays()}, progress=progress)
    sender.join()


@pytest.mark.usefixtures("sigint_raises")
def test_ctrl_c_interrupts_wait_of_a_job():
    job = purlcore.RenderJob(scene(200, 200, 1 << 16), {"knit": yarn_arrays()})
    job.start()
    threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    with pytest.raises(KeyboardInterrupt):
        job.wait()
    assert not job.done  # the wait was interrupted, not the render
    job.cancel()
    assert job.wait(timeout=60.0) and job.cancelled


def test_unknown_array_key_is_an_error():
    arrays = yarn_arrays()
    arrays["curve_colours"] = np.ones((3, 3), dtype=np.float32)  # British spelling: a typo here
    with pytest.raises(purlcore.Error, match=r"knit\.curve_colours: unknown key \(known: points, radii"):
        purlcore.RenderJob(scene(), {"knit": arrays})


def test_job_errors_are_purlcore_errors(tmp_path):
    job = purlcore.RenderJob(scene(), {"knit": yarn_arrays()})
    with pytest.raises(purlcore.Error, match="has not been started"):
        job.wait()
    job.start()
    assert job.wait(timeout=60.0)
    with pytest.raises(purlcore.Error, match="folder .* does not exist"):
        job.write(str(tmp_path / "missing" / "out.exr"))
    with pytest.raises(purlcore.Error, match="NUL"):
        job.write(str(tmp_path / "a\0b.exr"))
    with pytest.raises(purlcore.Error, match="must end in .png"):
        job.write(str(tmp_path / "out.exr"), str(tmp_path / "out.jpg"))
    assert list(tmp_path.iterdir()) == []
    job.write(str(tmp_path / "out.exr"), str(tmp_path / "out.png"))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.exr", "out.png"]


def _purl():
    import subprocess
    path = os.path.join(os.path.dirname(purlcore.__file__), "purl")
    if not os.path.exists(path):
        pytest.skip("no purl binary beside the module at " + path)
    return lambda *args: subprocess.run([path, *args], capture_output=True, text=True)


def test_cli_input_errors_exit_2_before_rendering(tmp_path):
    purl = _purl()
    scene_path = tmp_path / "scene.json"
    scene_path.write_text('{"camera": {"position": [0, -1, 0.5], "look_at": [0, 0, 0]}, "meshes": '
                          '[{"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "triangles": [[0, 1, 2]]}]}')
    scene = str(scene_path)
    cases = [
        (["render", scene, "-o", str(tmp_path / "out.exr"), "--spp", "abc"], "--spp"),  # CLI11: was 105
        (["render", scene], "--output is required"),                                    # was 106
        (["render", scene, "-o", str(tmp_path / "missing" / "out.exr")], "does not exist"),
        (["render", scene, "-o", str(tmp_path)], "is a folder"),
        (["render", scene, "-o", str(tmp_path / "out.jpg")], "must end in .exr or .png"),
        (["render", scene, "-o", str(tmp_path / "out.png"), "--png", str(tmp_path / "out.png")], "is the -o output"),
        (["render", scene, "-o", str(tmp_path / "out.exr"), "--png", str(tmp_path / "out.jpg")], "must end in .png"),
    ]
    for args, message in cases:
        result = purl(*args)
        assert result.returncode == 2, (args, result.stderr)
        assert message in result.stderr, (args, result.stderr)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.json"]  # nothing rendered, nothing left
