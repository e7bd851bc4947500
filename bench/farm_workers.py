#!/usr/bin/env python3
"""Three frames through the Purl Render Flamenco job type (docs/farm.md): one worker process
against two side by side, on this machine with Debian's Blender. Wall time and the CPU time of
all Blender processes, medians of runs alternated between the layouts (the machine is shared).

    python3 bench/farm_workers.py [--size 320x240] [--samples 8] [--yarns 12] [--repeats 3]

The add-on comes from dist/purl-<v>-legacy.zip (scripts/build_addon.sh). Layouts:
  1 worker,  chunk 3           one task renders frames 1..3
  2 workers, chunk 2           tasks 1,2 and 3 side by side
  2 workers, chunk 1           tasks 1, 2, 3 on two workers (1 and 2 at once, then 3)
  2 workers, chunk 2, 1 thread as chunk 2, each worker rendering on one thread
"""
import argparse
import glob
import os
import pathlib
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import zipfile

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "farm" / "flamenco"))
import run_local  # noqa: E402

LAYOUTS = [("1 worker, chunk 3", 1, 3, 0), ("2 workers, chunk 2", 2, 2, 0),
           ("2 workers, chunk 1", 2, 1, 0), ("2 workers, chunk 2, 1 thread each", 2, 2, 1)]


def children_cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", default="320x240")
    parser.add_argument("--samples", type=int, default=8)
    parser.add_argument("--yarns", type=int, default=12)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    blender = shutil.which("blender")
    zips = sorted(glob.glob(str(ROOT / "dist" / "purl-*-legacy.zip")))
    if not blender or not zips:
        sys.exit("needs Debian's blender and dist/purl-<v>-legacy.zip (scripts/build_addon.sh)")

    with tempfile.TemporaryDirectory(prefix="purl_farm_bench_") as folder:
        root = pathlib.Path(folder)
        zipfile.ZipFile(zips[-1]).extractall(root / "scripts" / "addons")
        env = dict(os.environ, BLENDER_USER_SCRIPTS=str(root / "scripts"), BLENDER_USER_CONFIG=str(root / "config"))
        blend = root / "knit.blend"
        subprocess.run([blender, "-b", "--factory-startup", "--addons", "purl", "--python",
                        str(ROOT / "tests" / "farm" / "make_scene.py"), "--", str(blend), "--size", args.size,
                        "--samples", str(args.samples), "--yarns", str(args.yarns)],
                       check=True, capture_output=True, env=run_local.worker_env(blender, env))
        submitted = run_local.submit(str(blend), "knit", {"render_output_root": str(root / "frames")},
                                     blender, "purl", env)
        variables = {"blender": blender, "blenderArgs": "-b -y"}
        walls = {layout[0]: [] for layout in LAYOUTS}
        cpus = {layout[0]: [] for layout in LAYOUTS}
        for repeat in range(args.repeats):
            for name, workers, chunk, threads in LAYOUTS:
                job = dict(submitted, settings=dict(submitted["settings"], chunk_size=chunk, threads=threads))
                tasks = run_local.compile_job(job)["tasks"]
                cpu_before = children_cpu_seconds()
                results, wall = run_local.run_tasks(tasks, workers, variables, env)
                failed = [r for r in results if r["returncode"] != 0]
                if failed:
                    sys.exit("{} failed:\n{}".format(failed[0]["name"], failed[0]["log"][-3000:]))
                walls[name].append(wall)
                cpus[name].append(children_cpu_seconds() - cpu_before)
                print("run {} {:<36} wall {:6.2f} s  cpu {:6.2f} s  load {}".format(
                    repeat + 1, name, wall, cpus[name][-1], " ".join("%.1f" % v for v in os.getloadavg())),
                      flush=True)

    base = statistics.median(walls[LAYOUTS[0][0]])
    print("\nthree frames, {} px, {} spp, {} yarns; medians of {} alternated runs".format(
        args.size, args.samples, args.yarns, args.repeats))
    print("| layout | wall (s) | vs one worker | CPU, all processes (s) |")
    print("|---|---|---|---|")
    for name, *_ in LAYOUTS:
        wall = statistics.median(walls[name])
        print("| {} | {:.1f} | {:.2f}x | {:.1f} |".format(name, wall, base / wall, statistics.median(cpus[name])))


if __name__ == "__main__":
    main()
