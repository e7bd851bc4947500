"""What a benchmark worker renders, and how it keeps the results: shared by bench/purl_worker.py and
bench/cycles_worker.py (which runs in the bpy venv, so this module is plain Python).

A request is a dict {"kind": "series" | "reference", "spp": n, "seed": s, "keep": bool,
"name": image name}. A one-shot worker makes its requests from --series/--repeats/--reference-spp
(series_requests); a serving worker (--serve, the production tier) reads one JSON request a line
on stdin and answers each with one line on stdout that starts with REPLY_PREFIX (Blender prints
its own lines there too), so bench/production.py can interleave the methods of a scene render by
render while each keeps its own process (and its own peak memory).
"""
import json
import sys

REPLY_PREFIX = "@purl-bench "
SERIES_SEEDS = (101, 17)  # repeat r renders with seed 101 + 17 r
REFERENCE_SEEDS = (9001, 9002)  # the converged image's two halves


def series_seed(repeat):
    return SERIES_SEEDS[0] + SERIES_SEEDS[1] * repeat


def series_request(spp, repeat):
    return {"kind": "series", "spp": spp, "seed": series_seed(repeat), "keep": repeat == 0, "name": "spp%d" % spp}


def reference_requests(reference_spp):
    """The converged image as two halves with their own seeds (none for reference_spp 0)."""
    if reference_spp <= 0:
        return []
    half = max(1, reference_spp // 2)
    return [{"kind": "reference", "spp": half, "seed": seed, "keep": True, "name": name}
            for seed, name in zip(REFERENCE_SEEDS, ("reference_a", "reference_b"))]


def series_requests(series, repeats, reference_spp):
    """A one-shot worker's renders: every sample count `repeats` times, then the converged image."""
    return [series_request(spp, r) for spp in series for r in range(repeats)] + reference_requests(reference_spp)


def parse_series(text):
    return [int(s) for s in text.split(",") if s.strip()]


class Record:
    """The images a worker keeps and the per-render figures, in the layout bench/report.py reads:
    series = [{"spp": n, "runs": [stats, ...]}, ...] in first-seen order, reference = {"spp": total,
    "runs": [stats of each half]} or None."""

    def __init__(self):
        self.images = {}
        self.series = []
        self.reference = None

    def add(self, request, image, stats):
        if request.get("keep"):
            self.images[request["name"]] = image
        if request["kind"] == "reference":
            if self.reference is None:
                self.reference = {"spp": 0, "runs": []}
            self.reference["spp"] += request["spp"]
            self.reference["runs"].append(stats)
            return
        entry = next((e for e in self.series if e["spp"] == request["spp"]), None)
        if entry is None:
            entry = {"spp": request["spp"], "runs": []}
            self.series.append(entry)
        entry["runs"].append(stats)

    def first_stats(self):
        for entry in self.series:
            return entry["runs"][0]
        return self.reference["runs"][0] if self.reference else None


def serve(run, announce):
    """Answers requests from stdin until it closes; run(request) renders one and returns its stats."""
    reply(dict(announce, ready=True))
    for line in sys.stdin:
        if line.strip():
            request = json.loads(line)
            reply({"name": request["name"], "stats": run(request)})


def run_all(args, run, announce):
    """Every request of this worker: from stdin with --serve, else from its command line."""
    if args.serve:
        serve(run, announce)
    else:
        for request in series_requests(parse_series(args.series), args.repeats, args.reference_spp):
            run(request)


def reply(message):
    sys.stdout.write(REPLY_PREFIX + json.dumps(message) + "\n")
    sys.stdout.flush()


def add_arguments(parser):
    parser.add_argument("--series", default="", help="comma-separated sample counts (one-shot)")
    parser.add_argument("--reference-spp", type=int, default=0, help="0: no converged image (one-shot)")
    parser.add_argument("--repeats", type=int, default=1, help="renders per sample count (one-shot)")
    parser.add_argument("--serve", action="store_true",
                        help="render requests read from stdin, one JSON a line, until it closes")
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--out", required=True, help="output path without extension")
