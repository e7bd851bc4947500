"""Side-by-side cost of the three yarn models (bysdf, ply, fiber) on one scene.

Runs `purl render --stats` for every model in turn (one process each, so peak memory is per
model), `--runs` times, interleaving the models so machine load hits them alike, and prints the
medians: curves, control points, Embree bytes, shading bytes, peak resident memory, build time
and render time per camera sample, as wall time and as CPU time. The CPU time per sample is
(CPU of a run at --spp minus CPU of the same run at 1 spp) / (difference in samples): it leaves
out the build and is less sensitive to other processes on a shared machine than wall time.
Numbers for docs/explicit-references.md came from:

  python3 tests/data/explicit/measure_models.py tests/data/explicit/single_yarn_3ply.json \
      --width 384 --height 256 --spp 64 --runs 3
  python3 tests/data/explicit/measure_models.py tests/data/explicit/glove_bysdf.json \
      --width 240 --height 320 --spp 8 --runs 3
"""
import argparse
import json
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile

STATS = {
    "build_s": r"build ([\d.]+) s",
    "render_s": r"render ([\d.]+) s",
    "samples": r"samples (\d+)",
    "mean_path": r"mean path length ([\d.]+)",
    "invalid": r"invalid samples (\d+)",
    "curves": r"curves (\d+)",
    "control_points": r"control points (\d+)",
    "accel_mb": r"acceleration structure ([\d.]+) MB",
    "shading_mb": r"frames and maps ([\d.]+) MB",
    "peak_mb": r"peak resident memory ([\d.]+) MB",
}


def absolute_scene(path, width, height):
    """The scene with its film resized and its files made absolute, in a temporary file."""
    with open(path, encoding="utf-8") as f:
        scene = json.load(f)
    base = os.path.dirname(os.path.abspath(path))
    if width and height:
        scene.setdefault("film", {}).update({"width": width, "height": height})
    for yarn in scene.get("yarns", []):
        if "bcc" in yarn and not os.path.isabs(yarn["bcc"]):
            yarn["bcc"] = os.path.normpath(os.path.join(base, yarn["bcc"]))
    out = tempfile.NamedTemporaryFile("w", suffix=".json", delete=False)
    json.dump(scene, out)
    out.close()
    return out.name


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(purl, scene, model, spp, threads):
    """--stats figures of one render, plus the CPU seconds the process used."""
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [purl, "render", scene, "--model", model, "--spp", str(spp), "--threads", str(threads),
               "--stats", "-o", os.path.join(tmp, "out.exr")]
        before = children_cpu()
        done = subprocess.run(cmd, capture_output=True, text=True)
        cpu = children_cpu() - before
    if done.returncode != 0:
        sys.exit(f"{model}: purl failed ({done.returncode}): {done.stderr.strip()}")
    values = {"cpu_s": cpu}
    for key, pattern in STATS.items():
        m = re.search(pattern, done.stderr)
        if not m:
            sys.exit(f"{model}: no '{key}' in the --stats output:\n{done.stderr}")
        values[key] = float(m.group(1))
    values["us_per_sample"] = 1e6 * values["render_s"] / values["samples"]
    return values


def measure(purl, scene, model, spp, threads):
    full = run(purl, scene, model, spp, threads)
    one = run(purl, scene, model, 1, threads)
    full["cpu_us_per_sample"] = 1e6 * (full["cpu_s"] - one["cpu_s"]) / (full["samples"] - one["samples"])
    return full


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--models", nargs="+", default=["bysdf", "ply", "fiber"])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--width", type=int, default=0)
    parser.add_argument("--height", type=int, default=0)
    parser.add_argument("--purl", default=os.environ.get("PURL", "purl"))
    args = parser.parse_args()

    scene = absolute_scene(args.scene, args.width, args.height)
    results = {m: [] for m in args.models}
    try:
        for r in range(args.runs):
            for model in args.models:
                results[model].append(measure(args.purl, scene, model, args.spp, args.threads))
                last = results[model][-1]
                print(f"run {r + 1}/{args.runs} {model}: {last['us_per_sample']:.2f} us/sample wall, "
                      f"{last['cpu_us_per_sample']:.2f} CPU", file=sys.stderr)
    finally:
        os.unlink(scene)

    med = {m: {k: statistics.median(v[k] for v in results[m]) for k in results[m][0]} for m in args.models}
    base = med.get("bysdf")
    print(f"\n{args.scene}: medians of {args.runs} runs, {args.spp} spp, {args.threads} threads")
    print("| model | curves | control points | Embree MB | frames+maps MB | peak RSS MB | build s "
          "| wall us/sample | CPU us/sample | path length | CPU time / bysdf |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for m in args.models:
        v = med[m]
        ratio = f"{v['cpu_us_per_sample'] / base['cpu_us_per_sample']:.2f}" if base else "-"
        print(f"| {m} | {v['curves']:.0f} | {v['control_points']:.0f} | {v['accel_mb']:.2f} | {v['shading_mb']:.3f} "
              f"| {v['peak_mb']:.0f} | {v['build_s']:.2f} | {v['us_per_sample']:.2f} | {v['cpu_us_per_sample']:.2f} "
              f"| {v['mean_path']:.2f} | {ratio} |")
    for m in args.models:
        print(f"{m} runs, CPU us/sample: " + " / ".join(f"{x['cpu_us_per_sample']:.2f}" for x in results[m]) +
              "; wall: " + " / ".join(f"{x['us_per_sample']:.2f}" for x in results[m]))


if __name__ == "__main__":
    main()
