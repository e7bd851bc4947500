"""The production tier of the benchmark (`bench/run.py --production`, not in CI): images of 320 x 240
where yarns are 5-100 px wide (a 3-ply yarn macro, the glove, a knit and a woven swatch close up)
and one garment-scale scene with yarns of 1-3 px, every method side by side.

Interleaved: all methods of a scene start at once, each in its own serving worker process
(bench/worker_requests.py; peak memory stays per method), and the scene's renders go round the
methods one render at a time (schedule), in alternating order, so load changes on a shared
machine hit every method alike. Times are medians over the rounds. Results go through the same
analysis and charts as the standard suite (bench/report.py).
"""
import json
import queue
import subprocess
import threading
import time

import worker_requests

SERIES = [1, 2, 4]
ROUNDS = 3  # renders per sample count and method: times are their medians
REFERENCE_SPP = 32  # each method's converged image (two halves of 16)
CLOSE_UPS = ["yarn_macro", "glove_close", "knit_close", "woven_close"]
BYSDF_MODES = ["bysdf-near", "bysdf-multi", "bysdf-far", "bysdf-auto"]
METHODS = BYSDF_MODES + ["ply", "placeholder", "trace", "cycles-ply", "cycles-yarn"]
WITH_FIBER = METHODS[:5] + ["fiber"] + METHODS[5:]


def production_suite(root):
    """(name, scene file, film size, series, reference spp, methods), like run.full_suite().
    The glove's fiber model is left out: 26 M fiber segments take about 130 s and 3.5 GB to build
    (docs/explicit-references.md) for each of its workers, more than the hour allows."""
    bench = root / "bench"
    scenes = bench / "scenes" / "production"
    return [
        ("yarn_macro", scenes / "yarn_macro.json", (320, 240), SERIES, REFERENCE_SPP, WITH_FIBER),
        ("glove_close", bench / "scenes" / "glove_close.json", (320, 240), SERIES, REFERENCE_SPP, METHODS),
        ("knit_close", root / "scenes" / "demo_knit.json", (320, 240), SERIES, REFERENCE_SPP, WITH_FIBER),
        ("woven_close", scenes / "woven_close.json", (320, 240), SERIES, REFERENCE_SPP, WITH_FIBER),
        ("knit_tube", bench / "scenes" / "knit_tube.json", (240, 320), SERIES, REFERENCE_SPP, WITH_FIBER),
    ]


def schedule(methods, series, rounds, reference_spp):
    """(method, request) in the order they render: round by round, each sample count of the series
    rendered by every method before the next, the methods' order reversed every other round; then
    each method's converged image (trace-only methods have none)."""
    steps = []
    for r in range(rounds):
        order = list(methods) if r % 2 == 0 else list(reversed(methods))
        for spp in series:
            steps += [(m, worker_requests.series_request(spp, r)) for m in order]
    for m in methods:
        if not m.startswith("trace"):
            steps += [(m, request) for request in worker_requests.reference_requests(reference_spp)]
    return steps


class Worker:
    """One serving worker process: waits for it to be ready, sends requests, reads the replies."""

    def __init__(self, cmd, env, log, timeout):
        self.timeout = timeout
        self.problem = None
        self.process = subprocess.Popen(cmd, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=log,
                                        text=True, bufsize=1)
        self.replies = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()
        self.ready = self._next_reply()

    def _read(self):
        for line in self.process.stdout:
            if line.startswith(worker_requests.REPLY_PREFIX):
                self.replies.put(json.loads(line[len(worker_requests.REPLY_PREFIX):]))
        self.replies.put(None)  # the process closed its output: it ended

    def _next_reply(self):
        if self.problem:
            return None
        try:
            message = self.replies.get(timeout=self.timeout)
        except queue.Empty:
            message, self.problem = None, "failed: no answer in %d s" % self.timeout
            self.process.kill()
        if message is None and not self.problem:
            self.problem = "failed: worker ended (exit %s; see run.log)" % self.process.wait()
        return message

    def render(self, request):
        if self.problem:
            return None
        self.process.stdin.write(json.dumps(request) + "\n")
        self.process.stdin.flush()
        return self._next_reply()

    def finish(self):
        """Closes its input (it writes its files and exits); returns None or why it failed."""
        if self.process.poll() is None:
            self.process.stdin.close()
            try:
                code = self.process.wait(timeout=self.timeout)
            except subprocess.TimeoutExpired:
                self.process.kill()
                code = "killed"
            if code != 0 and not self.problem:
                self.problem = "failed: exit %s while writing results (see run.log)" % code
        return self.problem


def run_scene(scene_file, methods, series, reference_spp, rounds, command_for, log, timeout):
    """Renders the scene's schedule; returns {method: None or why it did not run}."""
    outcomes, workers = {}, {}
    for method in methods:  # one at a time: each one's setup (geometry, BVH) alone on the machine
        command = command_for(method)
        if isinstance(command, str):
            outcomes[method] = command
            continue
        t0 = time.perf_counter()
        workers[method] = Worker(command[0] + ["--serve"], command[1], log, timeout)
        log.write("%s: %s ready in %.1f s\n" % (scene_file, method, time.perf_counter() - t0))
        log.flush()
    started = time.perf_counter()
    for method, request in schedule(list(workers), series, rounds, reference_spp):
        workers[method].render(request)
    for method, worker in workers.items():
        outcomes[method] = worker.finish()
    log.write("%s: renders took %.1f s\n" % (scene_file, time.perf_counter() - started))
    return outcomes
