"""tools/compare_ply_queries.py, the ray-by-ray comparison of ply query dumps, on small dumps
written here in the layout bench/native/dump_ply_queries.cpp writes."""
import json
import pathlib
import subprocess
import sys

import numpy as np

TOOL = pathlib.Path(__file__).resolve().parents[2] / "tools" / "compare_ply_queries.py"
FIELDS = ["hit", "ply", "plies_crossed", "point_x", "point_y", "point_z", "tangent_x", "tangent_y", "tangent_z",
          "converged", "radius"]
METHODS = ["elliptical", "local"]


def write_dump(prefix, rays, scenes=("a",), methods=METHODS):
    prefix.with_suffix(".json").write_text(json.dumps({"scenes": list(scenes), "methods": methods, "fields": FIELDS}))
    for scene in scenes:
        rays.astype(np.float32).tofile(f"{prefix}.{scene}.bin")


def sample_rays():
    rays = np.zeros((4, len(METHODS), len(FIELDS)))
    rays[..., 0] = 1  # every ray hits
    rays[..., 1] = [[0, 0], [1, 1], [2, 2], [0, 0]]
    rays[..., 2] = 2
    rays[..., 6] = 1  # tangent along x
    rays[..., 9] = 1  # converged
    rays[..., 10] = 0.5  # yarn radius
    return rays


def compare(*args):
    return subprocess.run([sys.executable, str(TOOL), *map(str, args)], capture_output=True, text=True)


def test_identical_dumps_differ_nowhere(tmp_path):
    write_dump(tmp_path / "old", sample_rays())
    write_dump(tmp_path / "new", sample_rays())
    result = compare(tmp_path / "old", tmp_path / "new")
    assert result.returncode == 0, result.stderr
    assert result.stdout.count("4 rays: 0 differ in some bit") == len(METHODS)


def test_changes_are_counted_by_kind(tmp_path):
    old, new = sample_rays(), sample_rays()
    new[1, 1, 1] = 2  # local: another ply
    new[2, 1, 3] += 0.01  # local: the same ply, moved by 0.02 R
    new[3, 1, 0] = 0  # local: a pass-through instead of a hit
    new[2, 1, 6:9] = [np.cos(np.radians(10)), np.sin(np.radians(10)), 0]  # and its tangent turned by 10 deg
    write_dump(tmp_path / "old", old)
    write_dump(tmp_path / "new", new)
    lines = compare(tmp_path / "old", tmp_path / "new").stdout.splitlines()
    elliptical, local = (next(line for line in lines if f"a, {m}:" in line) for m in METHODS)
    assert "0 differ in some bit" in elliptical
    assert "3 differ in some bit; hit state 1, ply 1, N_i 0 changed" in local
    assert "moved > 1e-4 R: 1, most 0.02 R" in local
    # Same ply on rays 0 and 2: tangents turned by 0 and 10 degrees.
    assert "tangent turned (same ply) mean 5, p99 9.9 deg" in local


def test_methods_of_one_dump_are_compared(tmp_path):
    rays = sample_rays()
    rays[0, 1, 2] = 3  # local crosses one ply more on the first ray
    write_dump(tmp_path / "dump", rays)
    result = compare(tmp_path / "dump", "--methods", "elliptical", "local")
    assert result.returncode == 0, result.stderr
    assert "hit state 0, ply 0, N_i 1 changed" in result.stdout
    assert compare(tmp_path / "dump", "--methods", "elliptical", "exact").returncode != 0


def test_rays_without_an_explicit_answer_are_left_out(tmp_path):
    rays = sample_rays()
    rays[0, 1, 2] = 3  # the method crosses one ply more than the explicit plies on the first ray
    rays[3, 1, 1] = 1  # and finds another ply on the last
    rays[3, 0, 9] = 0  # where the explicit answer met another passage of the yarn
    write_dump(tmp_path / "dump", rays, methods=["explicit", "local"])
    result = compare(tmp_path / "dump", "--methods", "explicit", "local")
    assert result.returncode == 0, result.stderr
    assert "(1 rays without an explicit answer left out)" in result.stdout
    assert "3 rays:" in result.stdout and "ply 0, N_i 1 changed" in result.stdout


def test_dumps_of_another_layout_are_refused(tmp_path):
    write_dump(tmp_path / "old", sample_rays())
    write_dump(tmp_path / "new", sample_rays()[:3])
    result = compare(tmp_path / "old", tmp_path / "new")
    assert result.returncode == 1
    assert "differ in layout or ray count" in result.stderr


def test_a_missing_dump_is_a_clear_error(tmp_path):
    write_dump(tmp_path / "old", sample_rays())
    result = compare(tmp_path / "old", tmp_path / "missing")
    assert result.returncode == 1
    assert f"cannot read the dump {tmp_path / 'missing'}" in result.stderr
