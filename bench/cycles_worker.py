"""Cycles as a peer: renders the explicit ply or fiber curves Purl exported (`purl export-explicit`)
with the Principled Hair BSDF, through the scene's camera and lights at the scene's resolution.

Runs in a Python that has the PyPI `bpy` module (scripts/test_blender.sh makes /opt/purl-bpy):
  /opt/purl-bpy/bin/python bench/cycles_worker.py scene.json --curves plies.bcc --radii plies.radii \
      --series 1,4,16 --reference-spp 256 --out /tmp/x

What matches Purl: camera (position / look_at, Z up, lens, 36 mm sensor, AUTO fit), film size,
area lights (power in W, size, shape, colour: Purl follows Cycles' radiometry), world colour,
path depth, box pixel filter of one pixel (Purl jitters uniformly inside the pixel), no
denoising, no adaptive sampling. What does not: the scattering. Cycles has no BYSDF and no
Khungurn fiber BCSDF; Principled Hair (Chiang 2016) with the fiber's colours is the closest
stock model. So Cycles' *noise* against time is comparable with Purl's, its *accuracy* against
the ply reference measures mostly the model difference.

Curves: the export holds uniform cubic B-spline control points; Cycles interpolates keys as
Catmull-Rom. We hand Cycles the B-spline evaluated at every knot and half-way between knots
(the curve is dense already: the export's knot step bounds the spline error to 0.005 ply
radii), closing loops by repeating their first point.
"""
import argparse
import json
import math
import os
import resource
import struct
import sys
import tempfile
import time

import numpy as np

import bpy

import worker_requests  # bench/, beside this file


def read_bcc(path):
    """Control points (list of (n, 3) arrays) and closed flags of a Z-up 'BS' BCC file."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:3] != b"BCC" or data[4:6] != b"BS" or data[7] != 2:
        raise SystemExit("%s: expected a Z-up uniform B-spline BCC file from purl export-explicit" % path)
    curves, points = struct.unpack_from("<QQ", data, 8)
    offset, out, closed = 64, [], []
    for _ in range(curves):
        (n,) = struct.unpack_from("<i", data, offset)
        offset += 4
        out.append(np.frombuffer(data, "<f4", 3 * abs(n), offset).reshape(-1, 3).astype(np.float64))
        closed.append(n < 0)
        offset += 12 * abs(n)
    if sum(len(c) for c in out) != points:
        raise SystemExit("%s: header says %d points, curves hold %d" % (path, points, sum(len(c) for c in out)))
    return out, closed


def bspline_samples(p, closed):
    """Points on the uniform cubic B-spline at every knot and half-way between knots."""
    if closed:
        q = np.concatenate([p[-1:], p, p[:2]])  # wrap: segment i uses p[i-1 .. i+2]
    else:
        q = p
    a, b, c, d = q[:-3], q[1:-2], q[2:-1], q[3:]
    knot = (a + 4 * b + c) / 6.0
    half = (a + 23 * b + 23 * c + d) / 48.0
    end = (b + 4 * c + d) / 6.0
    out = np.empty((2 * len(a) + 1,) + p.shape[1:])
    out[0:-1:2], out[1:-1:2], out[-1] = knot, half, end[-1]
    return out


def look_at_matrix(position, target):
    """Blender object matrix for an object at `position` whose local -Z looks at `target` (Z up)."""
    from mathutils import Matrix, Vector
    forward = (Vector(target) - Vector(position)).normalized()
    right = forward.cross(Vector((0, 0, 1)))
    if right.length < 1e-6:
        right = Vector((1, 0, 0))
    right.normalize()
    up = right.cross(forward)
    m = Matrix.Identity(4)
    for i in range(3):
        m[i][0], m[i][1], m[i][2], m[i][3] = right[i], up[i], -forward[i], position[i]
    return m


def curve_keys(curves_path, radii_path):
    """Cycles' keys (points, radii) per curve: the B-spline of a BCC file from export-explicit
    sampled at knots and half-way, or keys given as they are in an .npz (bench/yarn_keys.py:
    "points" (N, 3), "radii" (N,), "counts" keys per curve)."""
    if curves_path.endswith(".npz"):
        data = np.load(curves_path)
        ends = np.cumsum(data["counts"])[:-1]
        return np.split(data["points"].astype(np.float64), ends), np.split(data["radii"].astype(np.float64), ends)
    curves, closed = read_bcc(curves_path)
    radii = np.fromfile(radii_path, "<f4").astype(np.float64)
    if len(radii) != sum(len(c) for c in curves):
        raise SystemExit("%s: %d radii for %d control points" % (radii_path, len(radii), sum(len(c) for c in curves)))
    samples = [bspline_samples(p, c) for p, c in zip(curves, closed)]
    radius_samples, start = [], 0
    for p, c in zip(curves, closed):
        radius_samples.append(bspline_samples(radii[start:start + len(p)], c))
        start += len(p)
    return samples, radius_samples


def build_scene(scene, samples, radius_samples, threads):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    s = bpy.context.scene
    s.render.engine = "CYCLES"
    s.cycles.device = "CPU"
    s.cycles.use_adaptive_sampling = False
    s.cycles.use_denoising = False
    s.cycles.pixel_filter_type = "BOX"
    s.cycles.filter_width = 1.0
    depth = int(scene.get("render", {}).get("max_depth", 8))
    s.cycles.max_bounces = depth
    for name in ("diffuse_bounces", "glossy_bounces", "transmission_bounces", "transparent_max_bounces"):
        setattr(s.cycles, name, depth)
    s.render.use_persistent_data = True  # later renders reuse the synced scene and its BVH
    s.render.threads_mode = "FIXED" if threads > 0 else "AUTO"
    if threads > 0:
        s.render.threads = threads
    film = scene.get("film", {})
    s.render.resolution_x, s.render.resolution_y = int(film["width"]), int(film["height"])
    s.render.resolution_percentage = 100
    s.render.image_settings.file_format = "OPEN_EXR"
    s.render.image_settings.color_depth = "32"
    s.view_settings.view_transform = "Standard"

    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = list(scene.get("world", {}).get("color", [0, 0, 0])) + [1]
    background.inputs["Strength"].default_value = float(scene.get("world", {}).get("strength", 1.0))
    s.world = world

    cam_desc = scene["camera"]
    cam = bpy.data.cameras.new("Camera")
    cam.lens = float(cam_desc.get("lens", 50))
    cam.sensor_width = float(cam_desc.get("sensor_width", 36))
    cam.sensor_fit = cam_desc.get("sensor_fit", "AUTO")
    cam.clip_start = float(cam_desc.get("clip_start", 0.1))
    cam.clip_end = float(cam_desc.get("clip_end", 1000))
    cam_ob = bpy.data.objects.new("Camera", cam)
    cam_ob.matrix_world = look_at_matrix(cam_desc["position"], cam_desc["look_at"])
    s.collection.objects.link(cam_ob)
    s.camera = cam_ob

    for i, l in enumerate(scene.get("lights", [])):
        if l.get("type") != "area" or "position" not in l:
            raise SystemExit("cycles_worker: only area lights placed by position/look_at are supported")
        light = bpy.data.lights.new("Light%d" % i, "AREA")
        light.shape = l.get("shape", "SQUARE").upper()
        light.size = float(l.get("size", 1.0))
        if light.shape in {"RECTANGLE", "ELLIPSE"}:
            light.size_y = float(l.get("size_y", light.size))
        light.energy = float(l.get("power", 1000))
        light.color = l.get("color", [1, 1, 1])
        ob = bpy.data.objects.new("Light%d" % i, light)
        ob.matrix_world = look_at_matrix(l["position"], l.get("look_at", [0, 0, 0]))
        s.collection.objects.link(ob)

    hair = bpy.data.hair_curves.new("Yarns")
    hair.add_curves([len(p) for p in samples])
    hair.attributes["position"].data.foreach_set("vector", np.concatenate(samples).astype(np.float32).ravel())
    if "radius" not in hair.attributes:
        hair.attributes.new("radius", "FLOAT", "POINT")
    hair.attributes["radius"].data.foreach_set("value", np.concatenate(radius_samples).astype(np.float32))
    hair.materials.append(hair_material(scene))
    ob = bpy.data.objects.new("Yarns", hair)
    s.collection.objects.link(ob)
    return s, sum(len(p) for p in samples)


def hair_material(scene):
    """Principled Hair (Chiang) coloured with the BYSDF's body reflection albedo: the fiber
    BCSDF's transmission colour (brighter) made Cycles' yarn about 8x brighter than Purl's."""
    desc = scene["yarns"][0].get("material", {})
    colour = desc.get("body_reflection_albedo") or desc.get("fiber", {}).get("transmission_color") or [0.5] * 3
    mat = bpy.data.materials.new("Yarn")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    hair = nodes.new("ShaderNodeBsdfHairPrincipled")
    if hasattr(hair, "model"):
        hair.model = "CHIANG"
    hair.parametrization = "COLOR"
    hair.inputs["Color"].default_value = list(colour) + [1]
    # Longitudinal roughness 0.2 gives a lobe of about 7-10 degrees (the fleece fiber's widths);
    # radial roughness 0.5 spreads TT azimuthally about as the fiber BCSDF's 26 degrees.
    hair.inputs["Roughness"].default_value = 0.2
    hair.inputs["Radial Roughness"].default_value = 0.5
    hair.inputs["Coat"].default_value = 0.0
    hair.inputs["IOR"].default_value = 1.55
    mat.node_tree.links.new(hair.outputs[0], out.inputs["Surface"])
    return mat


PEAK = {"bytes": 0}


def on_stats(text):
    """Cycles' status line carries 'Peak:123.45M'; keep the largest."""
    for part in str(text).replace("|", ",").split(","):
        part = part.strip()
        if part.startswith("Peak:"):
            value = part[5:].strip()
            scale = {"K": 1e3, "M": 1e6, "G": 1e9}.get(value[-1:], 1)
            try:
                PEAK["bytes"] = max(PEAK["bytes"], int(float(value.rstrip("KMG")) * scale))
            except ValueError:
                pass


def render(s, spp, seed, work):
    s.cycles.samples = spp
    s.cycles.seed = seed
    s.render.filepath = os.path.join(work, "render.exr")
    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - start
    img = bpy.data.images.load(s.render.filepath, check_existing=False)
    w, h = img.size
    pixels = np.empty(w * h * 4, np.float32)
    img.pixels.foreach_get(pixels)
    bpy.data.images.remove(img)
    image = pixels.reshape(h, w, 4)[::-1, :, :3].copy()  # Blender's rows run bottom to top
    return image, {"render_seconds": seconds, "samples": w * h * spp,
                   "samples_per_second": w * h * spp / seconds if seconds > 0 else 0.0,
                   "invalid_samples": None, "rays": None, "mean_path_length": None}


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("--curves", required=True, help="BCC file from purl export-explicit, or keys as .npz")
    parser.add_argument("--radii", default="", help="radius side file of a BCC file")
    parser.add_argument("--material", default="fiber", choices=["ply", "fiber", "yarn"],
                        help="which curves these are (names the method: cycles-<material>)")
    worker_requests.add_arguments(parser)
    args = parser.parse_args(argv)

    with open(args.scene, encoding="utf-8") as f:
        scene = json.load(f)
    samples, radius_samples = curve_keys(args.curves, args.radii)
    start = time.perf_counter()
    s, keys = build_scene(scene, samples, radius_samples, args.threads)
    bpy.app.handlers.render_stats.append(on_stats)
    work = tempfile.mkdtemp(prefix="purl-cycles-")
    render(s, 1, 0, work)  # warm-up: syncs the scene and builds the BVH once
    setup_seconds = time.perf_counter() - start

    record = worker_requests.Record()

    def run(request):
        image, stats = render(s, request["spp"], request["seed"], work)
        record.add(request, image, stats)
        return stats

    worker_requests.run_all(args, run, {"setup_seconds": setup_seconds})
    np.savez_compressed(args.out + ".npz", **record.images)
    summary = {
        "method": "cycles-" + args.material,
        "model": args.material,
        "setup_seconds": setup_seconds,
        "series": record.series,
        "reference": record.reference,
        "peak_resident_bytes": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
        "cycles_peak_bytes": PEAK["bytes"] or None,
        "acceleration_bytes": None,
        "shading_bytes": None,
        "control_points": keys,
        "curves": len(samples),
        "build_seconds": setup_seconds,
        "blender": bpy.app.version_string,
    }
    with open(args.out + ".json", "w", encoding="utf-8") as f:
        json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    status = main()
    sys.stdout.flush()
    sys.stderr.flush()
    # The bpy module can hang at interpreter exit after a render (seen with bpy 4.5); everything
    # is written by now, so leave without running its shutdown.
    os._exit(status)
