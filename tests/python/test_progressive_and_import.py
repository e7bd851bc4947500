"""What the Blender look-dev loop needs from purlcore: progressive sample passes that add up to one
render, view changes without a rebuild, BCC files as stored and the yarn radius their spacing implies."""
import os
import subprocess
import sys

import numpy as np
import pytest

import purlcore
from test_purlcore import scene, yarn_arrays

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "blender"))
from bcc_files import write_bcc  # noqa: E402

DATA = os.environ.get("PURL_SHARED_DATA_DIR",
                      os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))
REPO = os.path.join(os.path.dirname(__file__), "..", "..")


def test_sample_passes_average_to_the_one_shot_render():
    arrays = {"knit": yarn_arrays()}
    job = purlcore.RenderJob(scene(spp=7), arrays)
    job.start(seed=5)
    job.wait()
    whole = job.passes()["Combined"]
    total, first = np.zeros_like(whole), 0
    for count in (1, 2, 4):  # 1 + 2 + 4 = 7 samples
        job.start(spp=count, seed=5, first_sample=first)
        job.wait()
        total += job.passes()["Combined"] * count
        first += count
    assert np.allclose(total / 7, whole, rtol=1e-5, atol=1e-6)
    job.start(spp=2, seed=5, first_sample=3)
    job.wait()
    assert not np.allclose(job.passes()["Combined"], whole, atol=1e-3), "other samples, other image"
    with pytest.raises(ValueError):
        job.start(first_sample=-1)


def test_set_view_renders_the_new_view_without_a_rebuild():
    arrays = {"knit": yarn_arrays()}
    moved = scene(width=12, height=8)
    moved["camera"] = {"position": [0.3, -1.5, 1.1], "look_at": [0, 0, 0], "lens": 50}
    expected = purlcore.render(moved, arrays, seed=1)["Combined"]
    job = purlcore.RenderJob(scene(), arrays)
    job.set_view(moved)
    job.start(seed=1)
    job.wait()
    # The new camera is placed in double from its own origin, the full scene's through the cloth's
    # frame: one float rounding apart (measured 1e-5 of a pixel value of 0.73).
    assert np.allclose(job.passes()["Combined"], expected, rtol=1e-4, atol=1e-5)
    with pytest.raises(purlcore.Error, match="film"):
        job.set_view(dict(moved, film={"width": 0, "height": 8}))


def test_far_field_progress_is_idle_between_renders():
    assert purlcore.far_field_progress() == (0, 0)


def test_read_bcc_gives_the_file_as_stored_turned_z_up(tmp_path):
    loop = [(np.cos(a), 2.0, np.sin(a)) for a in np.linspace(0, 2 * np.pi, 6, endpoint=False)]
    line = [(x, 0.0, 0.5) for x in range(5)]
    write_bcc(tmp_path / "a.bcc", "C0", [(loop, True), (line, False)], up=1)
    d = purlcore.read_bcc(str(tmp_path / "a.bcc"))
    assert d["type"] == "C0" and d["up_axis"] == "Y"
    assert list(d["offsets"]) == [0, 6, 11] and list(d["closed"]) == [True, False]
    # (x, y, z) -> (x, -z, y)
    assert np.allclose(d["points"][6:], [(x, -0.5, 0.0) for x in range(5)])
    assert np.allclose(d["points"][:6, 2], 2.0)


def test_read_bcc_reports_a_bad_file(tmp_path):
    path = tmp_path / "short.bcc"
    write_bcc(path, "BS", [([(0, 0, 0)] * 4, False)])
    path.write_bytes(path.read_bytes()[:-5])
    with pytest.raises(purlcore.Error, match="short.bcc"):
        purlcore.read_bcc(str(path))


@pytest.mark.parametrize("kind", ["knit", "plain"])
def test_radius_estimate_of_generated_swatches(tmp_path, kind):
    # Swatches keep distinct yarns at least 2.2 R (knit) or 2.1 R (weaves) apart.
    purl = os.path.join(os.environ.get("PURL_BUILD_DIR", os.path.join(REPO, "build")), "purl")
    if not os.path.exists(purl):
        pytest.skip("the purl CLI is not built")
    radius = 0.002
    path = str(tmp_path / (kind + ".bcc"))
    subprocess.run([purl, "generate", kind, "--radius", str(radius), "-o", path], check=True, capture_output=True)
    estimate = purlcore.read_bcc(path)["radius_estimate"]
    assert 1.0 * radius < estimate < 1.3 * radius


def test_radius_estimate_of_the_glove():
    path = os.path.join(DATA, "glove.bcc")
    if not os.path.exists(path):
        pytest.skip("no shared glove.bcc")
    d = purlcore.read_bcc(path)
    assert d["type"] == "C0" and len(d["points"]) == 58537 and d["closed"].all()
    # The project's glove scenes use 0.12; neighbouring yarns lie about 0.2 apart.
    assert 0.08 < d["radius_estimate"] < 0.13
