#!/usr/bin/env python3
"""Speed against accuracy: renders every benchmark scene with every method at a series of sample
counts, then writes charts and a results table (bench/report.py). See docs/benchmarks.md.

  python3 bench/run.py                 full suite into bench/results/ (about 30-45 min, 2 cores)
  python3 bench/run.py --quick         whole pipeline on one tiny scene (CI; under 2 min)
  python3 bench/run.py --production    production tier into bench/results-production/ (under an hour;
                                       320 x 240 close-ups, methods interleaved: bench/production.py)
  python3 bench/run.py --report-only   redraw charts and table from the last run's files

Options: --build-dir (where purl and purlcore are; default build), --out, --threads,
--scenes/--methods (comma-separated filters), --no-cycles, --no-stability.
Each (scene, method) runs in its own process (bench/purl_worker.py, or bench/cycles_worker.py
in the bpy venv for Cycles), so peak memory is per method.
"""
import argparse
import datetime
import json
import os
import pathlib
import platform
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
BENCH = ROOT / "bench"
BPY_PYTHON = pathlib.Path(os.environ.get("PURL_BPY_VENV", "/opt/purl-bpy")) / "bin" / "python"

TIMEOUT_SECONDS = 1200  # per worker process: a hung or runaway method is reported, the suite goes on
FIG7 = ["yarn_%dply_%s" % (n, light) for n in (1, 3, 6) for light in ("front", "back", "both")]
ALL_MODES = ["bysdf-near", "bysdf-multi", "bysdf-far", "bysdf-auto"]
SINGLE_YARN_METHODS = ["bysdf-auto", "ply", "fiber", "trace", "cycles-ply", "cycles-fiber"]


def full_suite():
    """(name, scene file, film size, series, reference spp, methods)."""
    suite = []
    for name in FIG7:
        methods = list(SINGLE_YARN_METHODS)
        if name == "yarn_3ply_both":  # all modes and traversal baselines on one single-yarn scene
            methods = ALL_MODES[:3] + methods + ["trace-ply", "trace-fiber"]
        suite.append((name, ROOT / "scenes/fig7" / (name + ".json"), (64, 32), [1, 4, 16], 256, methods))
    large = ALL_MODES + ["ply", "trace", "trace-ply", "cycles-ply"]
    # The glove's fiber model is left out: 26 M fiber segments take about 130 s and 3.5 GB to build
    # (docs/explicit-references.md), more than this suite's time budget allows.
    suite.append(("glove_close", BENCH / "scenes/glove_close.json", (64, 48), [1, 4, 16], 64, large))
    suite.append(("glove_far", BENCH / "scenes/glove_far.json", (48, 64), [1, 4, 16], 64, large))
    suite.append(("knit_tube", BENCH / "scenes/knit_tube.json", (48, 64), [1, 4, 16], 64,
                  large + ["fiber", "trace-fiber", "cycles-fiber"]))
    return suite


def quick_suite():
    return [("yarn_3ply_both", ROOT / "scenes/fig7/yarn_3ply_both.json", (48, 24), [1, 4], 16,
             ["bysdf-auto", "ply", "fiber", "trace", "cycles-ply"])]


def shared_model(path):
    """Scenes find the shared cloth models (shared/data) beside the repository; a git worktree sits
    deeper, so the same file is looked for beside each folder above the repository too."""
    parts = pathlib.PurePath(path).parts
    if os.path.exists(path) or "shared" not in parts:
        return path
    inside = pathlib.PurePath(*parts[len(parts) - 1 - parts[::-1].index("shared"):])
    for folder in ROOT.parents:
        if (folder / inside).exists():
            return str(folder / inside)
    return path


def prepared_scene(path, size, work):
    """The scene with the benchmark's film size and absolute file paths, in `work`."""
    with open(path, encoding="utf-8") as f:
        scene = json.load(f)
    scene.setdefault("film", {}).update({"width": size[0], "height": size[1]})
    base = os.path.dirname(os.path.abspath(path))
    for yarn in scene.get("yarns", []):
        if "bcc" in yarn and not os.path.isabs(yarn["bcc"]):
            yarn["bcc"] = shared_model(os.path.normpath(os.path.join(base, yarn["bcc"])))
    out = work / "scene.json"
    out.write_text(json.dumps(scene, indent=1), encoding="utf-8")
    return out


def run_logged(cmd, env=None, log=None):
    start = time.perf_counter()
    try:
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=TIMEOUT_SECONDS)
    except subprocess.TimeoutExpired as e:
        p = subprocess.CompletedProcess(cmd, 124, e.stdout or "", "timed out after %d s" % TIMEOUT_SECONDS)
    seconds = time.perf_counter() - start
    if log is not None:
        log.write("$ %s\n%s%s(exit %d, %.1f s)\n" % (" ".join(map(str, cmd)), p.stdout[-4000:], p.stderr[-4000:],
                                                   p.returncode, seconds))
        log.flush()
    return p, seconds


def last_error_line(p):
    lines = [line for line in (p.stderr or p.stdout).strip().splitlines() if line.strip()]
    return lines[-1][:300] if lines else "exit code %d" % p.returncode


def worker_command(scene_file, method, args, work, log):
    """(command, environment) of the worker process that renders `method`, or a one-line reason it
    cannot run. Cycles methods first write the curves Cycles traces (ply/fiber: purl
    export-explicit; yarn: the scene's own centre-lines, bench/yarn_keys.py)."""
    out = ["--threads", str(args.threads), "--out", str(work / method)]
    if not method.startswith("cycles-"):
        env = dict(os.environ, PYTHONPATH=str(args.build_dir))
        return [sys.executable, str(BENCH / "purl_worker.py"), str(scene_file), "--method", method] + out, env
    if args.no_cycles:
        return "skipped (--no-cycles)"
    if not BPY_PYTHON.exists():
        return "skipped: no bpy venv at %s (scripts/test_blender.sh bpy makes it)" % BPY_PYTHON.parent.parent
    model = method.split("-", 1)[1]
    if model == "yarn":
        curves, radii = work / "yarn_keys.npz", None
        try:
            import yarn_keys
            yarn_keys.write_yarn_keys(scene_file, curves, args.build_dir / "purl", work)
        except (SystemExit, subprocess.CalledProcessError, OSError) as e:
            return "failed: yarn keys: %s" % e
    else:
        curves = work / (model + ".bcc")
        radii = curves.with_suffix(".radii")
        p, _ = run_logged([str(args.build_dir / "purl"), "export-explicit", str(scene_file), "--model", model,
                           "-o", str(curves)], log=log)
        if p.returncode != 0:
            return "failed: export-explicit: " + last_error_line(p)
    cmd = [str(BPY_PYTHON), str(BENCH / "cycles_worker.py"), str(scene_file), "--curves", str(curves),
           "--material", model] + (["--radii", str(radii)] if radii else []) + out
    return cmd, None


def run_method(scene_file, method, series, reference_spp, args, work, log):
    """Runs one method in one process; returns None on success or a one-line reason it did not run."""
    command = worker_command(scene_file, method, args, work, log)
    if isinstance(command, str):
        return command
    cmd, env = command
    trace_only = method.startswith("trace")  # the baseline needs times only, no converged image
    cmd += ["--series", ",".join(map(str, series)), "--reference-spp", str(0 if trace_only else reference_spp),
            "--repeats", str(args.repeats)]
    p, _ = run_logged(cmd, env=env, log=log)
    if p.returncode != 0:
        return "failed: " + last_error_line(p)
    return None


def describe_machine(args):
    cpu = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo", encoding="utf-8"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem_gib = None
    try:
        for line in open("/proc/meminfo", encoding="utf-8"):
            if line.startswith("MemTotal"):
                mem_gib = int(line.split()[1]) / 2**20
    except OSError:
        pass
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    # A tree with uncommitted source changes is not that commit (results/ itself does not count).
    dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--", ".", ":!bench/results"],
                           capture_output=True, text=True).stdout.strip()
    if commit and dirty:
        commit += " + uncommitted changes"
    return {"cpu": cpu, "cores": os.cpu_count(), "memory_gib": mem_gib, "threads": args.threads,
            "os": platform.platform(), "python": platform.python_version(), "commit": commit or "unknown",
            "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "load_before": os.getloadavg()[0]}


def stability_table(out, log):
    """The implicit-ply sweep of tools/yarn_maps (view angle x bend x ply count), as CSV."""
    sys.path.insert(0, str(ROOT / "tools/yarn_maps"))
    import draw_maps  # the tool that draws docs/images/implicit-plies-accuracy.png
    work = pathlib.Path(tempfile.mkdtemp(prefix="purl-yarn-maps-"))
    exe = draw_maps.build(work)
    csv = out / "stability.csv"
    p, seconds = run_logged([str(exe), "table", str(csv)], log=log)
    if p.returncode != 0:
        print("bench: stability sweep failed: " + last_error_line(p), file=sys.stderr)
    else:
        print("bench: stability sweep took %.0f s" % seconds, file=sys.stderr)


def merged_plan(out, plan):
    """This run's scenes and methods over those of the previous run in `out` (for --scenes/--methods)."""
    try:
        previous = json.loads((out / "plan.json").read_text(encoding="utf-8"))["scenes"]
    except (OSError, ValueError, KeyError):
        return plan
    merged = {s["scene"]: s for s in previous}
    for s in plan:
        if s["scene"] in merged and merged[s["scene"]]["series"] == s["series"]:
            merged[s["scene"]]["methods"].update(s["methods"])
        else:
            merged[s["scene"]] = s
    return list(merged.values())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--production", action="store_true",
                        help="the production tier: 320 x 240 close-ups, methods interleaved (bench/production.py)")
    parser.add_argument("--report-only", action="store_true")
    parser.add_argument("--build-dir", default=str(ROOT / "build"))
    parser.add_argument("--out", default=None,
                        help="default bench/results (quick: a temporary folder; production: bench/results-production)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=None,
                        help="renders per sample count (default 3; quick 1; production: production.ROUNDS)")
    parser.add_argument("--scenes", default="", help="comma-separated scene names to run")
    parser.add_argument("--methods", default="", help="comma-separated method names to run")
    parser.add_argument("--no-cycles", action="store_true")
    parser.add_argument("--no-stability", action="store_true", help="skip the implicit-ply sweep (a few minutes)")
    args = parser.parse_args()
    args.build_dir = pathlib.Path(args.build_dir).resolve()
    args.repeats = args.repeats or (1 if args.quick else 3)
    out = pathlib.Path(args.out) if args.out else (
        pathlib.Path(tempfile.mkdtemp(prefix="purl-bench-quick-")) if args.quick else
        BENCH / ("results-production" if args.production else "results"))
    out.mkdir(parents=True, exist_ok=True)
    runs = out / "runs"

    import production  # bench/production.py and bench/report.py, beside this file
    import report

    if args.report_only:
        report.write_report(out)
        return 0
    for needed in ("purl", "purlcore.cpython-%d%d-x86_64-linux-gnu.so" % sys.version_info[:2]):
        if not any(args.build_dir.glob(needed.split(".cpython")[0] + "*")):
            sys.exit("bench: %s not found in %s; build it first (scripts/build.sh)" % (needed, args.build_dir))

    sys.path.insert(0, str(args.build_dir))  # purlcore, for the Cycles yarn keys
    suite = quick_suite() if args.quick else production.production_suite(ROOT) if args.production else full_suite()
    only_scenes = set(filter(None, args.scenes.split(",")))
    only_methods = set(filter(None, args.methods.split(",")))
    machine = describe_machine(args)
    plan = []
    log = open(out / "run.log", "w", encoding="utf-8")
    started = time.perf_counter()
    for name, path, size, series, reference_spp, methods in suite:
        if only_scenes and name not in only_scenes:
            continue
        work = runs / name
        if work.exists() and not only_methods:
            shutil.rmtree(work)  # a method filter re-runs some methods and keeps the others
        work.mkdir(parents=True, exist_ok=True)
        scene_file = prepared_scene(path, size, work)
        machine.setdefault("load_during", []).append(round(os.getloadavg()[0], 1))  # at each scene's start
        outcomes = {}
        methods = [m for m in methods if not only_methods or m in only_methods]
        if args.production:
            t0 = time.perf_counter()
            outcomes = production.run_scene(
                scene_file, methods, series, reference_spp, production.ROUNDS,
                lambda method: worker_command(scene_file, method, args, work, log), log, TIMEOUT_SECONDS)
            print("bench: %-15s %6.1f s  %s" % (name, time.perf_counter() - t0, ", ".join(
                "%s %s" % (m, p or "ok") for m, p in outcomes.items())), file=sys.stderr, flush=True)
        else:
            for method in methods:
                t0 = time.perf_counter()
                problem = run_method(scene_file, method, series, reference_spp, args, work, log)
                outcomes[method] = problem
                print("bench: %-15s %-13s %6.1f s  %s" % (name, method, time.perf_counter() - t0, problem or "ok"),
                      file=sys.stderr, flush=True)
        plan.append({"scene": name, "source": str(path.relative_to(ROOT)), "film": list(size), "series": series,
                     "reference_spp": reference_spp, "methods": outcomes})
    if not args.quick and not args.production and not args.no_stability:
        stability_table(out, log)
    machine["load_after"] = os.getloadavg()[0]
    machine["wall_minutes"] = (time.perf_counter() - started) / 60
    # CPU time of the workers (all threads): on a loaded machine the wall time says little, while
    # this over the thread count is about what the run takes on an idle machine.
    children = os.times()
    machine["worker_cpu_minutes"] = (children.children_user + children.children_system) / 60
    machine["mode"] = "quick" if args.quick else "production" if args.production else "full"
    written = {"machine": machine, "scenes": merged_plan(out, plan)}
    if args.production:
        written["close_ups"] = production.CLOSE_UPS
    (out / "plan.json").write_text(json.dumps(written, indent=1), encoding="utf-8")
    report.write_report(out)
    print("bench: wrote %s (%.1f min)" % (out / "results.md", machine["wall_minutes"]), file=sys.stderr)
    failed = ["%s/%s: %s" % (s["scene"], m, p) for s in plan for m, p in s["methods"].items()
              if p and p.startswith("failed")]
    missing = [n for n in ("results.md", "error_vs_time.png", "accuracy_vs_speed.png", "memory.png")
               if not (out / n).exists()]
    if args.quick and (failed or missing):  # CI: the pipeline must run end to end
        sys.exit("bench --quick: failed methods %s, missing outputs %s (log: %s)" % (failed, missing, out / "run.log"))
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(BENCH))
    sys.exit(main())
