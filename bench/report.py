"""Turns a benchmark run (plan.json + runs/<scene>/<method>.json/.npz, from bench/run.py) into
results.json, results.md and the charts, all in the run's output folder."""
import csv
import json
import pathlib
import statistics

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

import metrics  # noqa: E402

REFERENCE_METHOD = "ply"  # accuracy is measured against the converged explicit-ply image
BASE_METHOD = "bysdf-auto"  # equal-quality ratios are method time / this method's time
NEAR_LOOK_FLIP = 0.01  # a multi-scale mode "meets quality" when its converged image is this close to near's
STYLE = {  # colour, marker
    "bysdf-auto": ("tab:blue", "o"), "bysdf-near": ("tab:cyan", "v"), "bysdf-multi": ("tab:purple", "^"),
    "bysdf-far": ("tab:pink", "<"), "ply": ("tab:orange", "s"), "fiber": ("tab:green", "D"),
    "cycles-ply": ("tab:brown", "P"), "cycles-fiber": ("tab:olive", "X"), "cycles-yarn": ("tab:red", "*"),
    "placeholder": ("k", "d"),
    "trace": ("0.4", "."), "trace-ply": ("0.6", "."), "trace-fiber": ("0.8", "."),
}


def median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def analyse_method(work, method):
    summary = json.loads((work / (method + ".json")).read_text(encoding="utf-8"))
    images = np.load(work / (method + ".npz"))
    has_reference = "reference_a" in images
    points = []
    for entry in summary["series"]:
        runs = entry["runs"]
        point = {"spp": entry["spp"],
                 "seconds": median(r["render_seconds"] for r in runs),
                 "samples": runs[0]["samples"],
                 "samples_per_second": median(r["samples_per_second"] for r in runs),
                 "rays_per_sample": median(r["rays"] / r["samples"] if r.get("rays") else None for r in runs),
                 "path_length": median(r.get("mean_path_length") for r in runs)}
        if has_reference:
            point["rel_mse"], point["reference_noise"] = metrics.relative_mse(
                images["spp%d" % entry["spp"]], images["reference_a"], images["reference_b"])
        points.append(point)
    # Cost per sample without fixed per-render overheads: slope of time against samples.
    samples = np.array([p["samples"] for p in points], float)
    seconds = np.array([p["seconds"] for p in points], float)
    us_per_sample = float(np.polyfit(samples, seconds, 1)[0] * 1e6) if len(points) > 1 else \
        float(seconds[0] / samples[0] * 1e6)
    all_runs = [r for e in summary["series"] for r in e["runs"]] + \
               (summary["reference"]["runs"] if summary.get("reference") else [])
    invalid = [r.get("invalid_samples") for r in all_runs]
    geometry = None
    if summary.get("acceleration_bytes") is not None:
        # Control points as float4 (position, radius) + Embree's structure + frames and fiber maps.
        geometry = summary["control_points"] * 16 + summary["acceleration_bytes"] + summary["shading_bytes"]
    result = {
        "method": method, "points": points, "us_per_sample": us_per_sample,
        "setup_seconds": summary["setup_seconds"], "peak_resident_bytes": summary["peak_resident_bytes"],
        "cycles_peak_bytes": summary.get("cycles_peak_bytes"), "geometry_bytes": geometry,
        "acceleration_bytes": summary.get("acceleration_bytes"), "control_points": summary["control_points"],
        "curves": summary["curves"],
        "invalid_samples": None if any(v is None for v in invalid) else int(sum(invalid)),
        "samples_total": int(sum(r["samples"] for r in all_runs)),
    }
    converged = 0.5 * (images["reference_a"] + images["reference_b"]) if has_reference else None
    return result, converged


def analyse_scene(out, entry):
    work = out / "runs" / entry["scene"]
    results, converged = {}, {}
    for method, problem in entry["methods"].items():
        if problem is None and (work / (method + ".json")).exists():
            results[method], converged[method] = analyse_method(work, method)
    reference = converged.get(REFERENCE_METHOD)
    near = converged.get("bysdf-near")
    for method, image in converged.items():
        if image is not None and reference is not None:
            results[method]["rmse_vs_ply"] = metrics.rmse(image, reference)
            results[method]["flip_vs_ply"] = metrics.flip(image, reference)
        if image is not None and near is not None and method.startswith("bysdf-"):
            results[method]["flip_vs_near"] = metrics.flip(image, near)  # does a mode keep near's look?
    # Equal quality: the relMSE bysdf-auto reaches at its second-highest sample count.
    target = None
    base = results.get(BASE_METHOD) or next((r for r in results.values() if r["points"] and "rel_mse" in r["points"][0]), None)
    if base is not None:
        pts = base["points"]
        target = pts[-2 if len(pts) > 1 else -1]["rel_mse"]
    for r in results.values():
        if target is not None and r["points"] and "rel_mse" in r["points"][0]:
            t, extrapolated = metrics.time_to_quality([(p["seconds"], p["rel_mse"]) for p in r["points"]], target)
            r["time_to_target"], r["extrapolated"] = t, extrapolated
    base_time = results.get(BASE_METHOD, {}).get("time_to_target")
    for r in results.values():
        if base_time and r.get("time_to_target"):
            r["time_vs_auto"] = r["time_to_target"] / base_time
    return {"scene": entry["scene"], "film": entry["film"], "series": entry["series"],
            "reference_spp": entry["reference_spp"], "target_rel_mse": target, "results": results,
            "problems": {m: p for m, p in entry["methods"].items() if p is not None}}, converged


def fmt(value, spec="%.3g", none="–"):
    return none if value is None else spec % value


def mib(value):
    return fmt(None if value is None else value / 2**20, "%.3g")


def write_table(out, machine, scenes, stability, close_ups=None):
    mode = machine.get("mode")
    lines = ["# Benchmark results", "",
             "Regenerated by `python3 bench/run.py%s` (docs/benchmarks.md explains every column)." %
             (" --%s" % mode if mode in ("quick", "production") else ""), "",
             "Machine: %s, %d cores, %.0f GiB; %d render threads; load average %.1f before, %.1f after%s; commit %s; "
             "%s; run took %.1f min%s." % (
                 machine["cpu"], machine["cores"], machine["memory_gib"] or 0, machine["threads"], machine["load_before"],
                 machine["load_after"], load_during(machine), machine["commit"], machine["date"],
                 machine["wall_minutes"], worker_cpu(machine)), ""]
    if close_ups is not None:
        lines += production_goal_lines(scenes, close_ups) + [""] + compact_table_lines(scenes) + [""]
    else:
        lines += summary_lines(scenes) + [""]
    header = ("| method | µs/sample | samples/s | time to target (s) | × auto | relMSE at max spp | RMSE vs ply | "
              "FLIP vs ply | geometry MiB | peak RSS MiB | rays/sample | path length | NaN/Inf | setup s |")
    for s in scenes:
        lines += ["## %s" % s["scene"], "",
                  "%d x %d, spp %s (times: median of repeats), converged images %d spp; target relMSE %s." % (
                      s["film"][0], s["film"][1], "/".join(map(str, s["series"])), s["reference_spp"],
                      fmt(s["target_rel_mse"], "%.3g")), "", header, "|" + "---|" * 14]
        for method, r in s["results"].items():
            last = r["points"][-1]
            lines.append("| %s | %s | %s | %s%s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                method, fmt(r["us_per_sample"], "%.3g"), fmt(last["samples_per_second"], "%.3g"),
                fmt(r.get("time_to_target"), "%.3g"), " (extrap.)" if r.get("extrapolated") else "",
                fmt(r.get("time_vs_auto"), "%.2f"), fmt(last.get("rel_mse"), "%.2e"),
                fmt(r.get("rmse_vs_ply"), "%.3g"), fmt(r.get("flip_vs_ply"), "%.3f"), mib(r["geometry_bytes"]),
                mib(r["peak_resident_bytes"]), fmt(last["rays_per_sample"], "%.2f"), fmt(last["path_length"], "%.2f"),
                fmt(r["invalid_samples"], "%d", "n/a"), fmt(r["setup_seconds"], "%.1f")))
        for method, problem in s["problems"].items():
            lines.append("| %s | %s |%s" % (method, problem.replace("|", "/"), " |" * 12))
        lines.append("")
    if stability:
        lines += ["## Implicit-ply stability (tools/yarn_maps sweep, elliptical cross-section)", "",
                  "| plies | rays | agreement (min / mean) | unconverged | non-finite | tangent error mean / worst p95 (°) |"
                  " evaluations mean / max |", "|---|---|---|---|---|---|---|"]
        for plies, rows in sorted(stability.items()):
            agreement = [float(r["agreement"]) for r in rows]
            lines.append("| %d | %d | %.3f / %.3f | %d | %d | %.2f / %.2f | %.1f / %d |" % (
                plies, sum(int(r["rays"]) for r in rows), min(agreement), sum(agreement) / len(agreement),
                sum(int(r["unconverged"]) for r in rows), sum(int(r["non_finite"]) for r in rows),
                statistics.mean(float(r["tangent_mean"]) for r in rows), max(float(r["tangent_p95"]) for r in rows),
                statistics.mean(float(r["evals_mean"]) for r in rows), max(int(r["evals_max"]) for r in rows)))
        lines.append("")
    (out / "results.md").write_text("\n".join(lines), encoding="utf-8")


def worker_cpu(machine):
    minutes = machine.get("worker_cpu_minutes")
    return ", its workers %.1f CPU min" % minutes if minutes is not None else ""


def load_during(machine):
    loads = machine.get("load_during")
    return " (%s at the scenes' starts)" % ", ".join("%.1f" % v for v in loads) if loads else ""


def summary_lines(scenes):
    """The issue's goals, measured: medians over the single-yarn scenes."""
    single = [s for s in scenes if s["scene"].startswith("yarn_")]
    if not single:
        return []

    def med(method, key):
        return median(s["results"].get(method, {}).get(key) for s in single)

    def ratio_geometry(method):
        values = []
        for s in single:
            a, b = s["results"].get(BASE_METHOD), s["results"].get(method)
            if a and b and a["geometry_bytes"] and b["geometry_bytes"]:
                values.append(a["geometry_bytes"] / b["geometry_bytes"])
        return median(values)

    flips = [s["results"].get(BASE_METHOD, {}).get("flip_vs_ply") for s in single]
    flips = [f for f in flips if f is not None]
    return ["## Goals (medians over the %d single-yarn scenes)" % len(single), "",
            "| goal | measured | met |", "|---|---|---|",
            "| equal-quality time ply / bysdf-auto >= 3 | %s | %s |" % (
                fmt(med("ply", "time_vs_auto"), "%.2f"), yes(med("ply", "time_vs_auto"), 3)),
            "| equal-quality time fiber / bysdf-auto >= 10 | %s | %s |" % (
                fmt(med("fiber", "time_vs_auto"), "%.2f"), yes(med("fiber", "time_vs_auto"), 10)),
            "| equal-quality time Cycles fiber / bysdf-auto >= 10 | %s | %s |" % (
                fmt(med("cycles-fiber", "time_vs_auto"), "%.2f"), yes(med("cycles-fiber", "time_vs_auto"), 10)),
            "| geometry memory bysdf-auto / ply <= 0.10 | %s | %s |" % (
                fmt(ratio_geometry("ply"), "%.2f"),
                "–" if ratio_geometry("ply") is None else ("yes" if ratio_geometry("ply") <= 0.10 else "no")),
            "| FLIP bysdf-auto vs ply <= 0.05 (worst scene) | %s | %s |" % (
                fmt(max(flips) if flips else None, "%.3f"),
                "–" if not flips else ("yes" if max(flips) <= 0.05 else "no"))]


def production_goals(scenes, close_ups):
    """Issue 25's speed goals from a production-tier run: (goal, measured text, met or None) rows.
    Ratios are per scene; the equal-quality ones are medians over the close-up scenes."""
    close = [s for s in scenes if s["scene"] in close_ups]

    def value(s, method, key):
        return s["results"].get(method, {}).get(key)

    def ratio(s, a, b, key):
        x, y = value(s, a, key), value(s, b, key)
        return x / y if x and y else None

    def per_scene(values, spec="%.2f"):
        return ", ".join("%s %s" % (name, fmt(v, spec)) for name, v in values)

    rows = []
    near_ply = [(s["scene"], ratio(s, "bysdf-near", "ply", "us_per_sample")) for s in close]
    known = [v for _, v in near_ply if v is not None]
    rows.append(("BYSDF near µs/sample <= explicit ply's on every close-up (near / ply)", per_scene(near_ply),
                 all(v <= 1 for v in known) if known else None))
    for method, threshold in (("ply", 3), ("fiber", 10), ("cycles-ply", 5)):
        values = [(s["scene"], value(s, method, "time_vs_auto")) for s in close]
        m = median(v for _, v in values)
        rows.append(("equal-quality time %s / bysdf-auto >= %d (median of close-ups)" % (method, threshold),
                     "%s (%s)" % (fmt(m, "%.2f"), per_scene(values)), None if m is None else m >= threshold))
    placeholder = [(s["scene"], ratio(s, "bysdf-auto", "placeholder", "us_per_sample")) for s in scenes]
    known = [v for _, v in placeholder if v is not None]
    rows.append(("µs/sample bysdf-auto / placeholder on the same tubes <= 2", per_scene(placeholder),
                 all(v <= 2 for v in known) if known else None))
    for gate, label in ((None, ""), (NEAR_LOOK_FLIP, ", of those within FLIP %g of near's converged image" %
                                      NEAR_LOOK_FLIP)):
        auto_vs_best = []
        for s in scenes:
            modes = [value(s, m, "time_to_target") for m in ("bysdf-near", "bysdf-multi", "bysdf-far")
                     if gate is None or (value(s, m, "flip_vs_near") or 0) <= gate]
            modes = [t for t in modes if t]
            auto = value(s, "bysdf-auto", "time_to_target")
            auto_vs_best.append((s["scene"], auto / min(modes) if auto and modes else None))
        known = [v for _, v in auto_vs_best if v is not None]
        rows.append(("equal-quality time bysdf-auto / fastest of near, multi, far%s <= 1.1 on every scene" % label,
                     per_scene(auto_vs_best), all(v <= 1.1 for v in known) if known else None))
    return rows


def production_goal_lines(scenes, close_ups):
    rows = production_goals(scenes, close_ups)
    verdict = {None: "–", True: "yes", False: "**no**"}
    return ["## Goals of issue 25 (close-ups: %s)" % ", ".join(close_ups), "", "| goal | measured | met |",
            "|---|---|---|"] + ["| %s | %s | %s |" % (goal, measured, verdict[met]) for goal, measured, met in rows]


def compact_table_lines(scenes):
    """One table, every scene and method: the columns docs/benchmarks.md quotes."""
    lines = ["## All scenes", "", "| scene | method | µs/sample | time to target (s) | × auto | FLIP vs ply | "
             "FLIP vs near | peak RSS MiB |", "|---|---|---|---|---|---|---|---|"]
    for s in scenes:
        for method, r in s["results"].items():
            lines.append("| %s | %s | %s | %s%s | %s | %s | %s | %s |" % (
                s["scene"], method, fmt(r["us_per_sample"], "%.3g"), fmt(r.get("time_to_target"), "%.3g"),
                " (extrap.)" if r.get("extrapolated") else "", fmt(r.get("time_vs_auto"), "%.2f"),
                fmt(r.get("flip_vs_ply"), "%.3f"), fmt(r.get("flip_vs_near"), "%.3f"), mib(r["peak_resident_bytes"])))
        for method, problem in s["problems"].items():
            lines.append("| %s | %s | %s | | | | | |" % (s["scene"], method, problem.replace("|", "/")))
    return lines


def yes(value, threshold):
    return "–" if value is None else ("yes" if value >= threshold else "no")


def chart_error_vs_time(out, scenes):
    n = len(scenes)
    cols = min(4, n)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), squeeze=False)
    for ax, s in zip(axes.flat, scenes):
        for method, r in s["results"].items():
            pts = [(p["seconds"], p["rel_mse"]) for p in r["points"] if "rel_mse" in p]
            if not pts:
                continue
            colour, marker = STYLE.get(method, ("k", "x"))
            ax.loglog(*zip(*pts), marker=marker, color=colour, label=method)
        if s["target_rel_mse"]:
            ax.axhline(s["target_rel_mse"], color="0.7", lw=0.8, ls="--")
        ax.set_title(s["scene"], fontsize=9)
        ax.set_xlabel("render time (s)", fontsize=8)
        ax.set_ylabel("relMSE vs own converged", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())  # a decade's ticks would overlap
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    handles = {}
    for ax in axes.flat:
        for h, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, h)
    columns = min(8, len(handles))
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=columns, fontsize=8)
    legend_rows = -(-len(handles) // columns)
    fig.tight_layout(rect=(0, 0.25 * legend_rows / fig.get_size_inches()[1] + 0.02, 1, 1))
    fig.savefig(out / "error_vs_time.png", dpi=80)
    plt.close(fig)


def chart_accuracy_vs_speed(out, scenes):
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for group, marker_fill, pick in (("single yarn", "full", lambda n: n.startswith("yarn_")),
                                     ("glove / knit tube", "none", lambda n: not n.startswith("yarn_"))):
        chosen = [s for s in scenes if pick(s["scene"])]
        methods = sorted({m for s in chosen for m in s["results"]})
        for method in methods:
            x = median(s["results"].get(method, {}).get("time_vs_auto") for s in chosen)
            y = median(s["results"].get(method, {}).get("flip_vs_ply") for s in chosen)
            if x is None or y is None:
                continue
            colour, marker = STYLE.get(method, ("k", "x"))
            ax.scatter([x], [max(y, 1e-4)], color=colour, marker=marker, s=60,
                       facecolors=colour if marker_fill == "full" else "none", label="%s (%s)" % (method, group))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("equal-quality time / bysdf-auto's (median over scenes)")
    ax.set_ylabel("FLIP vs converged explicit ply (median)")
    ax.legend(fontsize=6, loc="best")
    ax.set_title("accuracy against speed (filled: single yarn, hollow: glove / knit tube)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "accuracy_vs_speed.png", dpi=80)
    plt.close(fig)


def chart_memory(out, scenes):
    wanted = [s for s in scenes if s["scene"] in ("yarn_3ply_both", "glove_close", "knit_tube")] or scenes[:1]
    fig, axes = plt.subplots(1, len(wanted), figsize=(4.8 * len(wanted), 3.8), squeeze=False)
    for ax, s in zip(axes.flat, wanted):
        methods = [m for m in s["results"] if not m.startswith("trace")]
        geometry = [(s["results"][m]["geometry_bytes"] or 0) / 2**20 for m in methods]
        peak = [s["results"][m]["peak_resident_bytes"] / 2**20 for m in methods]
        x = np.arange(len(methods))
        ax.bar(x - 0.2, geometry, 0.4, label="geometry (points + BVH + maps)", color="tab:blue")
        ax.bar(x + 0.2, peak, 0.4, label="peak RSS of the process", color="tab:gray")
        ax.set_yscale("log")
        ax.set_xticks(x)
        ax.set_xticklabels(methods, rotation=45, ha="right", fontsize=7)
        ax.set_ylabel("MiB")
        ax.set_title(s["scene"], fontsize=9)
    axes.flat[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "memory.png", dpi=80)
    plt.close(fig)


def chart_invalid(out, scenes):
    totals = {}
    for s in scenes:
        for method, r in s["results"].items():
            if r["invalid_samples"] is not None:
                count, samples = totals.get(method, (0, 0))
                totals[method] = (count + r["invalid_samples"], samples + r["samples_total"])
    if not totals:
        return
    fig, ax = plt.subplots(figsize=(6.5, 3.2))
    methods = list(totals)
    ax.bar(methods, [totals[m][0] for m in methods], color=[STYLE.get(m, ("k",))[0] for m in methods])
    for i, m in enumerate(methods):
        ax.text(i, totals[m][0], "%d / %.3g" % totals[m], ha="center", va="bottom", fontsize=6)
    ax.set_ylabel("NaN/Inf samples dropped")
    ax.set_title("NaN/Inf samples caught, all scenes (count / samples taken)", fontsize=9)
    ax.tick_params(axis="x", labelrotation=45, labelsize=7)
    fig.tight_layout()
    fig.savefig(out / "invalid_samples.png", dpi=80)
    plt.close(fig)


def chart_images(out, scenes, converged):
    methods = [m for m in STYLE if any(converged[s["scene"]].get(m) is not None for s in scenes)]
    if not methods:
        return
    fig, axes = plt.subplots(len(scenes), len(methods), figsize=(1.9 * len(methods), 1.3 * len(scenes) + 0.4),
                             squeeze=False)
    for i, s in enumerate(scenes):
        for j, m in enumerate(methods):
            ax = axes[i][j]
            ax.axis("off")
            image = converged[s["scene"]].get(m)
            if image is not None:
                ax.imshow(metrics.srgb(image))
            if i == 0:
                ax.set_title(m, fontsize=7)
            if j == 0:
                ax.text(-0.05, 0.5, s["scene"], transform=ax.transAxes, ha="right", va="center", fontsize=6)
    fig.tight_layout()
    fig.savefig(out / "images.png", dpi=80)
    plt.close(fig)


def read_stability(out):
    path = out / "stability.csv"
    if not path.exists():
        return {}
    by_plies = {}
    for row in csv.DictReader(open(path, encoding="utf-8")):
        if row["method"] == "elliptical":
            by_plies.setdefault(int(row["plies"]), []).append(row)
    return by_plies


def chart_stability(out, stability):
    """Per ply count, over view angle x bend: the 95th percentile of the ply tangent error
    against explicit helix tubes (colour) and the mean number of ply-search evaluations, with
    unconverged + non-finite searches after a slash when there are any (numbers)."""
    if not stability:
        return
    fig, axes = plt.subplots(1, len(stability), figsize=(3.8 * len(stability), 3.4), squeeze=False)
    top = max(float(r["tangent_p95"]) for rows in stability.values() for r in rows)
    for ax, (plies, rows) in zip(axes.flat, sorted(stability.items())):
        views = sorted({float(r["view"]) for r in rows})
        bends = sorted({float(r["bend"]) for r in rows}, key=lambda b: (b != 0, -b))
        grid = np.full((len(bends), len(views)), np.nan)
        for r in rows:
            i, j = bends.index(float(r["bend"])), views.index(float(r["view"]))
            grid[i, j] = float(r["tangent_p95"])
            failures = int(r["unconverged"]) + int(r["non_finite"])
            label = "%.0f" % float(r["evals_mean"]) + ("/%d" % failures if failures else "")
            ax.text(j, i, label, ha="center", va="center", fontsize=6,
                    color="w" if grid[i, j] < 0.5 * max(top, 1e-3) else "k")
        im = ax.imshow(grid, cmap="magma", vmin=0, vmax=max(top, 1e-3), aspect="auto")
        ax.set_xticks(range(len(views)))
        ax.set_xticklabels(["%g" % v for v in views], fontsize=7)
        ax.set_yticks(range(len(bends)))
        ax.set_yticklabels(["straight" if b == 0 else "bend %gR" % b for b in bends], fontsize=7)
        ax.set_xlabel("view angle from the yarn normal (°)", fontsize=7)
        ax.set_title("%d plies" % plies, fontsize=9)
        fig.colorbar(im, ax=ax, fraction=0.046).set_label("tangent error p95 (°)", fontsize=7)
    fig.suptitle("implicit plies vs explicit tubes: tangent error p95 (colour); mean ply-search evaluations"
                 " / unconverged + non-finite searches (numbers)", fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "stability_map.png", dpi=80)
    plt.close(fig)


def write_report(out):
    out = pathlib.Path(out)
    plan = json.loads((out / "plan.json").read_text(encoding="utf-8"))
    scenes, converged = [], {}
    for entry in plan["scenes"]:
        analysed, images = analyse_scene(out, entry)
        scenes.append(analysed)
        converged[entry["scene"]] = images
    stability = read_stability(out)
    (out / "results.json").write_text(json.dumps({"machine": plan["machine"], "scenes": scenes}, indent=1),
                                      encoding="utf-8")
    write_table(out, plan["machine"], scenes, stability, plan.get("close_ups"))
    if scenes:
        chart_error_vs_time(out, scenes)
        chart_accuracy_vs_speed(out, scenes)
        chart_memory(out, scenes)
        chart_invalid(out, scenes)
        chart_images(out, scenes, converged)
    chart_stability(out, stability)
