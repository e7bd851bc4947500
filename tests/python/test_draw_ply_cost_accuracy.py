"""tools/draw_ply_cost_accuracy.py on a small benchmark JSON and dump in the layouts bench_cloth_plies and
dump_ply_queries write."""
import json
import pathlib
import subprocess
import sys

import numpy as np

TOOL = pathlib.Path(__file__).resolve().parents[2] / "tools" / "draw_ply_cost_accuracy.py"
FIELDS = ["hit", "ply", "plies_crossed", "tangent_x", "tangent_y", "tangent_z", "converged"]
METHODS = ["elliptical", "local", "circular", "explicit"]


def write_dump(prefix, rays=400):
    """Scene glove_close: the exact method always right, the local one with the wrong N_i on a
    quarter of the rays, the circular one with a tilted tangent on every ray, and one ray the
    explicit answer could not settle (left out)."""
    prefix.with_suffix(".json").write_text(json.dumps({"scenes": ["glove_close"], "methods": METHODS,
                                                       "fields": FIELDS}))
    d = np.zeros((rays, len(METHODS), len(FIELDS)))
    d[..., 0] = 1
    d[..., 1] = np.arange(rays)[:, None] % 3
    d[..., 2] = 2
    d[..., 3] = 1
    d[..., 6] = 1
    d[: rays // 4, METHODS.index("local"), 2] = 3
    d[:, METHODS.index("circular"), 4] = np.tan(np.radians(10.0))
    d[-1, METHODS.index("explicit"), 6] = 0
    d[-1, METHODS.index("elliptical"), 1] = 2 - d[-1, METHODS.index("explicit"), 1]  # wrong, but not comparable
    d.astype(np.float32).tofile(f"{prefix}.glove_close.bin")


def aggregate(name, ns):
    return {"name": f"{name}_median", "run_name": name, "run_type": "aggregate", "aggregate_name": "median",
            "cpu_time": ns, "time_unit": "ns"}


def write_bench(path, families=("BM_ClothQuery", "BM_ClothLocal", "BM_ClothCircular", "BM_ClothExplicit",
                                "BM_ClothShared")):
    ns = {"BM_ClothQuery": 3000.0, "BM_ClothLocal": 1500.0, "BM_ClothCircular": 700.0, "BM_ClothExplicit": 1000.0,
          "BM_ClothShared": 250.0}
    runs = [aggregate(f"{f}/0", ns[f]) for f in families]
    # Repetitions and other aggregates are in such files too; only the median is read.
    runs.append({"name": "BM_ClothQuery/0_mean", "run_name": "BM_ClothQuery/0", "run_type": "aggregate",
                 "aggregate_name": "mean", "cpu_time": 9999.0, "time_unit": "ns"})
    path.write_text(json.dumps({"context": {}, "benchmarks": runs}))


def run(*args):
    return subprocess.run([sys.executable, str(TOOL), *map(str, args)], capture_output=True, text=True)


def test_prints_each_methods_cost_ratio_and_error_and_draws_them(tmp_path):
    write_dump(tmp_path / "dump")
    write_bench(tmp_path / "bench.json")
    out = tmp_path / "chart.png"
    result = run(tmp_path / "bench.json", tmp_path / "dump", "--out", out)
    assert result.returncode == 0, result.stderr
    rows = {line.split("|")[2].strip(): [c.strip() for c in line.split("|")[3:-1]]
            for line in result.stdout.splitlines() if line.startswith("| glove_close")}
    assert rows["exact"] == ["3000", "1000", "3.00", "0.00%", "0.00"]
    assert rows["local"][2:4] == ["1.50", "25.06%"]  # 100 of the 399 comparable rays
    assert rows["circular"][2:] == ["0.70", "0.00%", "10.00"]
    assert "Shared work (projection, fiber maps, shading frame) / plies: 0.25-0.25" in result.stdout
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_run_without_the_explicit_trace_is_refused(tmp_path):
    write_dump(tmp_path / "dump")
    write_bench(tmp_path / "bench.json", families=("BM_ClothQuery", "BM_ClothLocal"))
    result = run(tmp_path / "bench.json", tmp_path / "dump", "--out", tmp_path / "chart.png")
    assert result.returncode != 0
    assert "no BM_ClothExplicit run for glove_close" in result.stderr
    assert not (tmp_path / "chart.png").exists()


def test_unreadable_inputs_are_clear_errors(tmp_path):
    write_dump(tmp_path / "dump")
    (tmp_path / "bench.json").write_text("{not json")
    result = run(tmp_path / "bench.json", tmp_path / "dump")
    assert result.returncode == 1
    assert "cannot read the benchmark JSON" in result.stderr
    write_bench(tmp_path / "bench.json")
    result = run(tmp_path / "bench.json", tmp_path / "nothing")
    assert result.returncode == 1
    assert "cannot read the dump" in result.stderr
