"""Composite back into Cycles: Cycles renders the scene without the yarns, Purl renders the yarns
with every mesh as a holdout, and the two are laid one over the other into one render result.

Why this order of work: a holdout mesh in front of a yarn cuts the yarn out of Purl's image per
sample, so the mesh's edges over the yarn are antialiased and "Purl over Cycles" (premultiplied
alpha) already has the right depth order; the Depth pass takes the nearer of the two.
Cycles runs in a child process (a fresh Blender, or Python with the bpy module) on a copy of the
scene, so it neither re-enters Blender's render pipeline nor touches the user's data.
"""
import json
import os
import subprocess
import sys

import bpy
import numpy as np

from .exr import read_exr

WORKER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "composite_worker.py")
OUTPUT_TAIL_CHARS = 1500  # how much of a failed child's output goes into the error report


class CompositeError(RuntimeError):
    pass


def prepare_purl_scene(exported):
    """Purl's half: meshes only occlude (holdouts) and the background is left to Cycles."""
    for mesh in exported.scene.get("meshes", []):
        mesh["holdout"] = True
    exported.scene["film"]["transparent"] = True


def _child_command(job_path):
    binary = bpy.app.binary_path
    if binary and os.path.basename(binary).startswith("blender"):
        return [binary, "-b", "--factory-startup", "--python-exit-code", "1", "--python", WORKER, "--", job_path]
    return [sys.executable, WORKER, job_path]  # the bpy module: its Python imports bpy itself


def _path_hair_settings(scene):
    """Particle settings Purl renders as yarn. Cycles cannot hide hair from the camera alone (the
    emitter would go too), so the worker turns these hairs off: they cast no shadow in Cycles."""
    names = set()
    for ob in scene.objects:
        for psys in getattr(ob, "particle_systems", ()):
            if psys.settings.type == "HAIR" and psys.settings.render_type == "PATH":
                names.add(psys.settings.name)
    return names


class CyclesHalf:
    """The Cycles render of one frame, running in a child process."""

    def __init__(self, scene, layer_name, hidden_objects, temp_dir):
        self.output = os.path.join(temp_dir, "cycles.exr")
        blend = os.path.join(temp_dir, "cycles_scene.blend")
        # Writes the scene and everything it references; absolute paths keep textures found.
        bpy.data.libraries.write(blend, {scene}, path_remap="ABSOLUTE")
        job = {"blend": blend, "scene": scene.name, "layer": layer_name, "frame": scene.frame_current,
               "samples": int(scene.purl.cycles_samples), "seed": int(scene.purl.seed),
               "hide": sorted(hidden_objects), "hide_hair": sorted(_path_hair_settings(scene)),
               "output": self.output}
        job_path = os.path.join(temp_dir, "cycles_job.json")
        with open(job_path, "w", encoding="utf-8") as f:
            json.dump(job, f)
        self._log = open(os.path.join(temp_dir, "cycles.log"), "w+", encoding="utf-8", errors="replace")
        self.process = subprocess.Popen(_child_command(job_path), stdout=self._log, stderr=subprocess.STDOUT)

    def done(self):
        return self.process.poll() is not None

    def cancel(self):
        if self.process.poll() is None:
            self.process.kill()  # our own child, by its id
            self.process.wait()
        self._log.close()

    def read(self, layer_name):
        """(rgba (H, W, 4), depth (H, W)), rows top to bottom; CompositeError when Cycles failed."""
        self.process.wait()
        self._log.seek(0)
        output = self._log.read()
        self._log.close()
        if self.process.returncode != 0 or not os.path.isfile(self.output):
            raise CompositeError("the Cycles render failed (exit status {}): {}".format(
                self.process.returncode, output[-OUTPUT_TAIL_CHARS:].strip()))
        planes = read_exr(self.output)
        prefix = layer_name + "."
        try:
            rgba = np.stack([planes[prefix + "Combined." + c] for c in "RGBA"], axis=-1)
        except KeyError as missing:
            raise CompositeError("the Cycles image has no channel {} (has {})".format(
                missing, ", ".join(sorted(planes)))) from None
        depth = planes.get(prefix + "Depth.Z", np.full(rgba.shape[:2], np.inf, dtype=np.float32))
        return rgba, depth


def composite(purl_passes, cycles_rgba, cycles_depth):
    """The passes of the composite, rows top to bottom: Combined is Purl (premultiplied, meshes
    cut out) over Cycles; Depth the nearer of both; Normal and YarnID are Purl's."""
    purl_rgba = purl_passes["Combined"]
    if purl_rgba.shape != cycles_rgba.shape:
        raise CompositeError("Purl's image is {} but Cycles' is {}".format(purl_rgba.shape, cycles_rgba.shape))
    uncovered = 1.0 - purl_rgba[..., 3:4]
    result = dict(purl_passes)
    result["Combined"] = (purl_rgba + uncovered * cycles_rgba).astype(np.float32)
    purl_depth = purl_passes["Depth"][..., 0]
    result["Depth"] = np.minimum(purl_depth, cycles_depth)[..., None].astype(np.float32)
    return result
