"""The Purl render engine: export the depsgraph, run a purlcore.RenderJob, read back its EXR.

Nothing here may raise into Blender: every failure becomes a report on the engine, and a render
that was cancelled or failed simply leaves the result empty.
"""
import os
import shutil
import tempfile
import time
import traceback

import bpy

from . import composite, native
from .compat import set_pass_pixels
from .export import export_scene

POLL_SECONDS = 0.05          # progress / cancel polling period
CANCEL_GRACE_SECONDS = 5.0   # how long to wait for a cancelled job before giving up on it

# Passes Purl writes: (name, channels, channel ids, type). Combined is always there.
PASSES = [
    ("Depth", 1, "Z", "VALUE"),
    ("Normal", 3, "XYZ", "VECTOR"),
    ("YarnID", 1, "X", "VALUE"),
    ("PlyIndex", 1, "X", "VALUE"),
    ("PlyUV", 2, "UV", "VECTOR"),
]


class PurlRenderEngine(bpy.types.RenderEngine):
    bl_idname = "PURL"
    bl_label = "Purl"
    bl_use_preview = False            # material previews have no yarns to show yet
    bl_use_postprocess = True
    bl_use_shading_nodes_custom = False  # keep Blender's shader nodes for mesh materials
    bl_use_eevee_viewport = True      # material preview in the viewport uses EEVEE

    last_export = None          # the Export of the last render, for scripts and tests
    keep_last_arrays = False    # keep its (possibly large) arrays too; tests turn this on

    def render(self, depsgraph):
        try:
            self._render(depsgraph)
        except Exception as error:  # never let an exception escape into Blender's render loop
            traceback.print_exc()
            self.report({"ERROR"}, "Purl: {}".format(error))

    def _render(self, depsgraph):
        core = native.purlcore()
        if core is None:
            self.report({"ERROR"}, "Purl: " + native.load_error())
            return
        scene = depsgraph.scene
        layer_name = depsgraph.view_layer.name
        width, height = self._result_size(scene)
        temp_dir = tempfile.mkdtemp(prefix="purl_")
        try:
            self.update_stats("", "Purl | exporting")
            exported = export_scene(depsgraph, size=(width, height), temp_dir=temp_dir)
            type(self).last_export = exported
            for level, message in exported.problems.items:
                self.report({level}, "Purl: " + message)
            if not exported.renderable:
                return
            cycles = None
            if scene.purl.use_cycles_composite:
                composite.prepare_purl_scene(exported)
                self.update_stats("", "Purl | starting Cycles for the rest of the scene")
                cycles = composite.CyclesHalf(scene, layer_name, exported.yarn_objects, temp_dir)
            try:
                self._render_purl(core, exported, scene, layer_name, (width, height), temp_dir, cycles)
            finally:
                if cycles is not None:
                    cycles.cancel()  # no-op once it has finished
        finally:
            shutil.rmtree(temp_dir, ignore_errors=True)
            if type(self).last_export is not None and not self.keep_last_arrays:
                type(self).last_export.arrays = {}  # don't hold the yarn arrays between renders

    def _render_purl(self, core, exported, scene, layer_name, size, temp_dir, cycles):
        """Renders Purl's half and loads the result; with `cycles`, composites over its image."""
        width, height = size
        base_dir = bpy.path.abspath("//") if bpy.data.filepath else ""
        try:
            job = core.RenderJob(exported.scene, exported.arrays, base_dir)
        except core.Error as error:
            self.report({"ERROR"}, "Purl: {}".format(error))
            return
        if not self._run(job, exported.stats, scene.purl.samples):
            return
        if cycles is not None:
            if not self._wait_for_cycles(cycles):
                return
            try:
                rgba, depth = cycles.read(layer_name)
                passes = composite.composite(job.passes(), rgba, depth)
            except (composite.CompositeError, ValueError, OSError) as error:
                self.report({"ERROR"}, "Purl composite: {}".format(error))
                return
            self._load_passes(passes, width, height, layer_name)
            return
        exr_path = os.path.join(temp_dir, "purl.exr")
        job.write(exr_path, None, layer_name)
        result = self.begin_result(0, 0, width, height, layer=layer_name)
        try:
            result.load_from_file(exr_path)
        finally:
            self.end_result(result)

    def _load_passes(self, passes, width, height, layer_name):
        """Writes numpy passes (rows top to bottom) into the render result."""
        result = self.begin_result(0, 0, width, height, layer=layer_name)
        try:
            layer = result.layers[0]
            for render_pass in layer.passes:
                pixels = passes.get(render_pass.name)
                if pixels is not None and pixels.shape[-1] == render_pass.channels:
                    set_pass_pixels(render_pass, pixels[::-1])  # Blender's rows run bottom to top
        finally:
            self.end_result(result)

    def _wait_for_cycles(self, cycles):
        """Polls the Cycles child until it ends; False when the user cancelled."""
        start = time.monotonic()
        while not cycles.done():
            self.update_stats("", "Purl | waiting for Cycles | {:.1f} s".format(time.monotonic() - start))
            if self._user_cancelled():
                cycles.cancel()
                return False
            time.sleep(POLL_SECONDS)
        return True

    def _result_size(self, scene):
        render = scene.render
        return (render.resolution_x * render.resolution_percentage // 100,
                render.resolution_y * render.resolution_percentage // 100)

    def _run(self, job, stats, samples):
        """Starts the job and polls it; True when it finished with an image to read back."""
        summary = "{} yarns, {} points, {} triangles".format(stats["curves"], stats["points"], stats["triangles"])
        start = time.monotonic()
        job.start()
        while not job.wait(POLL_SECONDS):
            progress = float(job.progress)
            self.update_progress(progress)
            self.update_stats("", "Purl | {} | {:.0f}% of {} spp | {:.1f} s".format(
                summary, 100.0 * progress, samples, time.monotonic() - start))
            if self._user_cancelled():
                job.cancel()
                job.wait(CANCEL_GRACE_SECONDS)
                return False
        self.update_progress(1.0)
        if job.cancelled:
            return False
        if job.error:
            self.report({"ERROR"}, "Purl: {}".format(job.error))
            return False
        return True

    def _user_cancelled(self):
        # A Python method of our own, so tests can stand in for Esc (RNA's test_break cannot be overridden).
        return self.test_break()

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        for name, channels, ids, kind in PASSES:
            self.register_pass(scene, renderlayer, name, channels, ids, kind)


def register():
    bpy.utils.register_class(PurlRenderEngine)


def unregister():
    bpy.utils.unregister_class(PurlRenderEngine)
