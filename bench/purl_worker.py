"""One Purl method on one scene, in a process of its own (so peak memory is per method).

Builds the scene once (purlcore.RenderJob) and renders it once at 1 spp to warm up; then renders
it at every sample count of the series, `--repeats` times each with different seeds, and finally
the converged image as two halves with their own seeds (the analysis uses their difference to
remove the reference's own noise from the error; bench/metrics.py). With --serve it renders what
bench/production.py asks instead (bench/worker_requests.py). Writes <out>.npz (images) and
<out>.json (figures).

Run by bench/run.py; by hand:
  PYTHONPATH=build python3 bench/purl_worker.py scene.json --method bysdf-auto \
      --series 1,4,16 --reference-spp 256 --out /tmp/x
"""
import argparse
import json
import os
import resource
import sys
import time

import numpy as np

import worker_requests

# Method name -> (yarn model, multi-scale mode or None, integrator).
METHODS = {
    "bysdf": ("bysdf", None, "path"),  # the scene's own multi-scale settings
    "bysdf-near": ("bysdf", "near", "path"),
    "bysdf-multi": ("bysdf", "multi", "path"),
    "bysdf-far": ("bysdf", "far", "path"),
    "bysdf-auto": ("bysdf", "auto", "path"),
    "ply": ("ply", None, "path"),
    "fiber": ("fiber", None, "path"),
    "trace": ("bysdf", None, "trace"),
    "trace-ply": ("ply", None, "trace"),
    "trace-fiber": ("fiber", None, "trace"),
    "placeholder": ("bysdf", None, "path"),  # the placeholder material on the BYSDF's tubes
}


def scene_for(path, method):
    with open(path, encoding="utf-8") as f:
        scene = json.load(f)
    model, mode, integrator = METHODS[method]
    if method == "placeholder":
        placeholder_materials(scene)
    render = scene.setdefault("render", {})
    if mode is not None:
        render.setdefault("multiscale", {})["mode"] = mode
    if integrator != "path":
        render["integrator"] = integrator
    return scene, model


def placeholder_materials(scene):
    """Every yarn's material as the placeholder (Lambert + GGX tube) in the BYSDF yarn's body
    transmission colour: the same tubes, lights and camera without the implicit plies."""
    for yarn in scene.get("yarns", []):
        colour = yarn.get("material", {}).get("body_transmission_albedo", [0.8, 0.8, 0.8])
        yarn["material"] = {"model": "placeholder", "color": colour}
    return scene


def render_once(job, spp, seed, threads):
    job.start(spp=spp, seed=seed, threads=threads)
    job.wait()
    if job.error:
        raise RuntimeError(job.error)
    image = np.ascontiguousarray(job.passes()["Combined"][..., :3], dtype=np.float32)
    return image, job.stats()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("--method", required=True, choices=sorted(METHODS))
    worker_requests.add_arguments(parser)
    args = parser.parse_args()

    import purlcore  # noqa: E402  (PYTHONPATH is set by the caller)

    scene, model = scene_for(args.scene, args.method)
    start = time.perf_counter()
    job = purlcore.RenderJob(json.dumps(scene), None, os.path.dirname(os.path.abspath(args.scene)), model)
    setup_seconds = time.perf_counter() - start  # explicit geometry + Embree + maps
    render_once(job, 1, 1, args.threads)  # warm-up: pages in code and data, starts the threads

    record = worker_requests.Record()

    def run(request):
        image, stats = render_once(job, request["spp"], request["seed"], args.threads)
        record.add(request, image, stats)
        return stats

    worker_requests.run_all(args, run, {"setup_seconds": setup_seconds})
    np.savez_compressed(args.out + ".npz", **record.images)
    first = record.first_stats()
    if first is None:
        raise SystemExit("purl_worker: no render was asked for (give --series or --serve requests)")
    summary = {
        "method": args.method,
        "model": model,
        "setup_seconds": setup_seconds,
        "series": record.series,
        "reference": record.reference,
        "peak_resident_bytes": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
        "acceleration_bytes": first["acceleration_bytes"],
        "shading_bytes": first["shading_bytes"],
        "control_points": first["control_points"],
        "curves": first["curves"],
        "build_seconds": first["build_seconds"],
    }
    with open(args.out + ".json", "w", encoding="utf-8") as f:
        json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
