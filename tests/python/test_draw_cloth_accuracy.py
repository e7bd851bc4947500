"""tools/draw_cloth_accuracy.py on small dumps in the layout bench/native/dump_ply_queries.cpp writes."""
import json
import pathlib
import subprocess
import sys

import numpy as np

TOOL = pathlib.Path(__file__).resolve().parents[2] / "tools" / "draw_cloth_accuracy.py"
FIELDS = ["hit", "ply", "plies_crossed", "tangent_x", "tangent_y", "tangent_z", "converged", "film_x", "film_y"]


def write_dump(prefix, methods, rays=200):
    prefix.with_suffix(".json").write_text(json.dumps({"scenes": ["a"], "methods": methods, "fields": FIELDS}))
    rng = np.random.default_rng(1)
    d = np.zeros((rays, len(methods), len(FIELDS)))
    d[..., 0] = 1
    d[..., 1] = rng.integers(0, 3, rays)[:, None]
    d[..., 2] = 2
    d[..., 3] = 1
    d[..., 6] = 1
    d[..., 7] = rng.uniform(0, 8, rays)[:, None]
    d[..., 8] = rng.uniform(0, 6, rays)[:, None]
    if "local" in methods:
        d[: rays // 4, methods.index("local"), 4] = 0.05  # a tilted tangent on a quarter of the rays
    d.astype(np.float32).tofile(f"{prefix}.a.bin")


def run(*args):
    return subprocess.run([sys.executable, str(TOOL), *map(str, args)], capture_output=True, text=True)


def test_draws_a_picture_of_a_dump(tmp_path):
    write_dump(tmp_path / "dump", ["elliptical", "local", "circular", "explicit"])
    out = tmp_path / "accuracy.png"
    result = run(tmp_path / "dump", "--out", out)
    assert result.returncode == 0, result.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_dump_without_explicit_answers_is_refused(tmp_path):
    write_dump(tmp_path / "dump", ["elliptical", "local"])
    result = run(tmp_path / "dump", "--out", tmp_path / "accuracy.png")
    assert result.returncode != 0
    assert "no `explicit` method" in result.stderr
    assert not (tmp_path / "accuracy.png").exists()


def test_a_missing_dump_is_a_clear_error(tmp_path):
    result = run(tmp_path / "nothing")
    assert result.returncode == 1
    assert "cannot read the dump" in result.stderr
