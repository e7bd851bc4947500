#!/usr/bin/env python3
"""Chart what each implicit ply method costs against how often it is wrong, in the benchmark garments.

Cost comes from a Google Benchmark JSON of bench/native/bench_cloth_plies: each method's query
(plies + fiber maps, at the tube hit) over Embree's trace of the explicit plies, both from the
same run. Accuracy comes from a dump of bench/native/dump_ply_queries, against its `explicit`
method: the share of rays whose hit state, ply or N_i is wrong, and the 99th percentile of the
tangent error where the ply is right. The chart marks the issue's goal (query <= 0.5x the
explicit trace) and the work every method shares (BM_ClothShared: projection, fiber maps,
shading frame), below which no implicit query can go.

    build/bench_cloth_plies --benchmark_filter='BM_Cloth(Query|Local|Circular|Explicit|Shared)/' \\
        --benchmark_repetitions=5 --benchmark_report_aggregates_only=true --benchmark_out=/tmp/bench.json
    build/dump_ply_queries /tmp/dump
    python3 tools/draw_ply_cost_accuracy.py /tmp/bench.json /tmp/dump --out docs/images/ply-cost-accuracy.png

It also prints the chart's numbers as a Markdown table.
"""
import argparse
import json
import pathlib
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from compare_ply_queries import load_or_exit, mismatch, same_ply, tangent_turn  # noqa: E402

# Benchmark family -> the dump's method name and the chart's label.
METHODS = {"BM_ClothQuery": ("elliptical", "exact"), "BM_ClothLocal": ("local", "local"),
           "BM_ClothCircular": ("circular", "circular")}
REFERENCE, SHARED = "BM_ClothExplicit", "BM_ClothShared"
SCENES = ["glove_close", "glove_far", "knit_tube"]  # bench_cloth_plies' argument order
GOAL = 0.5


def cpu_times(path):
    """{(family, scene): CPU ns}: the median aggregate when the run has one, else the median of
    the repetitions."""
    with open(path) as f:
        runs = json.load(f)["benchmarks"]
    samples, medians = {}, {}
    for run in runs:
        family, _, arg = run["run_name"].partition("/")
        key = (family, SCENES[int(arg)] if arg.isdigit() and int(arg) < len(SCENES) else arg)
        scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[run.get("time_unit", "ns")]
        if run.get("run_type") == "aggregate":
            if run.get("aggregate_name") == "median":
                medians[key] = run["cpu_time"] * scale
        else:
            samples.setdefault(key, []).append(run["cpu_time"] * scale)
    times = {key: statistics.median(values) for key, values in samples.items()}
    times.update(medians)
    return times


def measure(times, meta, data):
    """Rows of the chart: one per scene and method found in both inputs."""
    col = {name: i for i, name in enumerate(meta["fields"])}
    if "explicit" not in meta["methods"]:
        raise SystemExit(f"the dump has no `explicit` method; it has {', '.join(meta['methods'])}")
    ref = meta["methods"].index("explicit")
    rows = []
    for scene, d in data.items():
        explicit_ns = times.get((REFERENCE, scene))
        if explicit_ns is None:
            raise SystemExit(f"the benchmark JSON has no {REFERENCE} run for {scene}")
        e = d[:, ref]
        comparable = e[:, col["converged"]] == 1
        for family, (method, label) in METHODS.items():
            if (family, scene) not in times or method not in meta["methods"]:
                continue
            m = d[:, meta["methods"].index(method)]
            same = same_ply(m, e, col, comparable)
            ns = times[(family, scene)]
            rows.append({"scene": scene, "method": label, "ns": ns, "explicit_ns": explicit_ns,
                         "ratio": ns / explicit_ns, "shared_ns": times.get((SHARED, scene)),
                         "wrong": mismatch(m, e, col, comparable).sum() / max(comparable.sum(), 1),
                         "tangent_p99": float(np.percentile(tangent_turn(m[same], e[same], col), 99))
                         if same.any() else float("nan")})
    if not rows:
        raise SystemExit("no method is in both the benchmark JSON and the dump")
    return rows


def shared_ratios(rows):
    """The shared work over the explicit trace, per row that has both."""
    return [r["shared_ns"] / r["explicit_ns"] for r in rows if r["shared_ns"]]


def table(rows):
    lines = ["| scene | method | query (ns) | Embree plies (ns) | query / plies | hit, ply or N_i wrong "
             "| tangent error p99 (deg) |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['scene']} | {r['method']} | {r['ns']:.0f} | {r['explicit_ns']:.0f} | "
                     f"{r['ratio']:.2f} | {r['wrong']:.2%} | {r['tangent_p99']:.2f} |")
    shared = shared_ratios(rows)
    if shared:
        lines.append(f"\nShared work (projection, fiber maps, shading frame) / plies: "
                     f"{min(shared):.2f}-{max(shared):.2f}")
    return "\n".join(lines)


def draw(rows, out):
    colours = {"exact": "tab:blue", "local": "tab:orange", "circular": "tab:red"}
    markers = dict(zip(SCENES, "os^"))
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2))
    panels = [("wrong", "hit, ply or N_i wrong against explicit plies (% of rays)", 100.0),
              ("tangent_p99", "tangent error where the ply is right, 99th percentile (deg)", 1.0)]
    shared = shared_ratios(rows)
    for ax, (key, ylabel, scale) in zip(axes, panels):
        for r in rows:
            ax.scatter(r["ratio"], max(r[key] * scale, 1e-3), color=colours.get(r["method"], "k"),
                       marker=markers.get(r["scene"], "D"), s=60, zorder=3)
        ax.axvspan(0, GOAL, color="tab:green", alpha=0.12, label=f"issue's goal: query <= {GOAL}x explicit trace")
        if shared:
            ax.axvspan(0, max(shared), color="0.5", alpha=0.35,
                       label=f"work every method shares ({min(shared):.2f}-{max(shared):.2f}x)")
        ax.axvline(1.0, color="0.3", lw=1, ls=":")
        ax.set_xlim(0, max(r["ratio"] for r in rows) * 1.15)
        ax.set_yscale("log")
        ax.set_xlabel("query cost / Embree's explicit ply trace (CPU time, same run)")
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
    # One legend for methods (colour) and scenes (marker), one for the shaded regions.
    handles = [plt.Line2D([], [], color=c, marker="o", ls="", label=m) for m, c in colours.items()
               if any(r["method"] == m for r in rows)]
    handles += [plt.Line2D([], [], color="k", marker=mk, ls="", label=s) for s, mk in markers.items()
                if any(r["scene"] == s for r in rows)]
    axes[0].legend(handles=handles, loc="upper right", fontsize=9)
    axes[1].legend(loc="upper right", fontsize=9)
    fig.suptitle("Implicit ply query in the benchmark garments: cost against accuracy, every method")
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    print(f"wrote {out}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("bench", help="bench_cloth_plies --benchmark_out JSON")
    parser.add_argument("dump", help="dump_ply_queries output prefix")
    parser.add_argument("--out", default="ply-cost-accuracy.png")
    args = parser.parse_args()
    try:
        times = cpu_times(args.bench)
    except (OSError, ValueError, KeyError) as e:
        print(f"draw_ply_cost_accuracy: cannot read the benchmark JSON {args.bench}: {e}", file=sys.stderr)
        return 1
    meta, data = load_or_exit(args.dump, "draw_ply_cost_accuracy")
    rows = measure(times, meta, data)
    print(table(rows))
    draw(rows, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
