#!/usr/bin/env python3
"""Runs the Purl Render job type on this machine the way Flamenco would, without a Manager:
the add-on's submission (settings evaluated in Blender), the Manager's compilation (Node.js,
farm/flamenco/local_manager.js) and Workers running the tasks' blender-render commands, several
at once.

    python3 farm/flamenco/run_local.py scene.blend --output-root /tmp/frames --workers 2 \\
        [--frames 1-3] [--chunk-size 2] [--threads 1] [--addon-module purl] [--blender blender]

Prints each task's command and time and the wall time of the whole job; exits 1 when a task
failed (its log is printed). A Worker runs {exe} {exeArgs} {argsBefore} {blendfile} {args} with
{blender} and {blenderArgs} replaced by the Manager's variables (here --blender and
--blender-args, "-b -y" as in Flamenco's default configuration).
"""
import argparse
import concurrent.futures
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
JOB_TYPE_SCRIPT = os.path.join(HERE, "purl_render.js")
SAVED = re.compile(r"Saved: '(.*)'")


def worker_env(blender="blender", env=None):
    """The environment for Blender children, with the Blender binary's folder first on PATH:
    Debian's Blender runs the system Python and takes its home from the python3.11 found first
    on PATH, so one started from a pyenv or venv Python would miss its own modules (numpy)."""
    env = dict(os.environ if env is None else env)
    binary = shutil.which(blender, path=env.get("PATH")) or blender
    env["PATH"] = os.path.dirname(os.path.abspath(binary)) + os.pathsep + env.get("PATH", "")
    return env


def _node(*args):
    result = subprocess.run(["node", os.path.join(HERE, "local_manager.js"), JOB_TYPE_SCRIPT, *args],
                            capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(result.stderr.strip() or "local_manager.js failed")
    return json.loads(result.stdout)


def submit(blendfile, name, given, blender="blender", addon_module="purl", env=None):
    """The job the Flamenco add-on would submit from `blendfile`, with the artist's `given` settings."""
    with tempfile.TemporaryDirectory(prefix="purl_flamenco_") as folder:
        job_type_path = os.path.join(folder, "job_type.json")
        job_path = os.path.join(folder, "job.json")
        out_path = os.path.join(folder, "submitted.json")
        with open(job_type_path, "w") as f:
            json.dump(_node("job-type"), f)
        with open(job_path, "w") as f:
            json.dump({"name": name, "settings": given}, f)
        result = subprocess.run([blender, "-b", blendfile, "--addons", addon_module, "--python-exit-code", "1",
                                 "--python", os.path.join(HERE, "submit_settings.py"), "--",
                                 job_type_path, job_path, out_path],
                                capture_output=True, text=True, env=worker_env(blender, env))
        if result.returncode != 0:
            raise RuntimeError("evaluating the job settings in Blender failed:\n" + result.stdout[-3000:]
                               + result.stderr[-3000:])
        with open(out_path) as f:
            return json.load(f)


def compile_job(job):
    """The Manager's compilation: {"name", "type", "settings", "tasks": [...]}."""
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(job, f)
    try:
        return _node("compile", f.name)
    finally:
        os.unlink(f.name)


def _expand(value, variables):
    if isinstance(value, str):
        for name, replacement in variables.items():
            value = value.replace("{" + name + "}", replacement)
        return value
    if isinstance(value, list):
        return [_expand(item, variables) for item in value]
    return value


def worker_argv(command, variables):
    """The process a Flamenco Worker starts for a blender-render command."""
    if command["name"] != "blender-render":
        raise ValueError("only blender-render commands run here, not " + command["name"])
    p = {key: _expand(value, variables) for key, value in command["parameters"].items()}
    return ([p["exe"]] + shlex.split(p.get("exeArgs", "")) + list(p.get("argsBefore", []))
            + [p["blendfile"]] + list(p.get("args", [])))


def run_task(task, variables, env=None):
    """Runs one task's commands in order; {"name", "seconds", "saved", "returncode", "log"}."""
    start = time.monotonic()
    saved, log, returncode = [], [], 0
    for command in task["commands"]:
        argv = worker_argv(command, variables)
        result = subprocess.run(argv, capture_output=True, text=True, env=worker_env(argv[0], env))
        log.append(result.stdout + result.stderr)
        saved += SAVED.findall(result.stdout)
        returncode = result.returncode
        if returncode != 0:
            break  # a Worker stops a task at its first failing command
    return {"name": task["name"], "seconds": time.monotonic() - start, "saved": saved, "returncode": returncode,
            "log": "".join(log)}


def run_tasks(tasks, workers, variables, env=None):
    """Runs the tasks on `workers` worker processes at once; (results in task order, wall seconds)."""
    start = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        results = list(pool.map(lambda task: run_task(task, variables, env), tasks))
    return results, time.monotonic() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("blendfile")
    parser.add_argument("--output-root", required=True, help="render_output_root: frames go to <root>/<job>/")
    parser.add_argument("--name", default="", help="job name (default: the file's name)")
    parser.add_argument("--frames", help="frames to render (default: the scene's range)")
    parser.add_argument("--chunk-size", type=int, help="frames per task (default: the job type's)")
    parser.add_argument("--threads", type=int, default=0, help="render threads per task (0: all cores)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes at once")
    parser.add_argument("--addon-module", default="purl")
    parser.add_argument("--blender", default="blender")
    parser.add_argument("--blender-args", default="-b -y")
    args = parser.parse_args()

    name = args.name or os.path.splitext(os.path.basename(args.blendfile))[0]
    given = {"render_output_root": os.path.abspath(args.output_root), "threads": args.threads,
             "blendfile": os.path.abspath(args.blendfile)}
    if args.frames:
        given["frames"] = args.frames
    if args.chunk_size:
        given["chunk_size"] = args.chunk_size
    job = compile_job(submit(args.blendfile, name, given, args.blender, args.addon_module))
    variables = {"blender": args.blender, "blenderArgs": args.blender_args}
    for task in job["tasks"]:
        print("{}: {}".format(task["name"], shlex.join(worker_argv(task["commands"][0], variables))))
    results, wall = run_tasks(job["tasks"], args.workers, variables)
    failed = [r for r in results if r["returncode"] != 0]
    for result in results:
        print("{:<16} {:6.2f} s  {}".format(result["name"], result["seconds"], ", ".join(result["saved"])))
    for result in failed:
        print("\n{} failed (exit status {}):\n{}".format(result["name"], result["returncode"], result["log"][-3000:]))
    print("{} tasks on {} workers: {:.2f} s wall".format(len(results), args.workers, wall))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
