"""The Purl render engine: F12 exports the depsgraph and runs a purlcore.RenderJob in progressive
sample passes, each shown in the render result as it finishes.

Nothing here may raise into Blender: every failure becomes a report on the engine, and a render
that was cancelled or failed simply leaves the result empty.
"""
import os
import shutil
import tempfile
import time
import traceback

import bpy

from . import compat, composite, denoise, native, preview, progressive, viewport
from .compat import set_pass_pixels
from .export import export_scene

POLL_SECONDS = progressive.POLL_SECONDS  # progress / cancel polling period
CANCEL_GRACE_SECONDS = 5.0   # how long to wait for a cancelled job before giving up on it

# Passes Purl writes: (name, channels, channel ids, type). Combined is always there.
PASSES = [
    ("Depth", 1, "Z", "VALUE"),
    ("Normal", 3, "XYZ", "VECTOR"),
    ("YarnID", 1, "X", "VALUE"),
    ("PlyIndex", 1, "X", "VALUE"),
    ("PlyUV", 2, "UV", "VECTOR"),
    ("Denoising Albedo", 3, "RGB", "COLOR"),   # the Denoise node's guides, as Cycles names them
    ("Denoising Normal", 3, "XYZ", "VECTOR"),
]
NOISY_PASS = ("Noisy Image", 4, "RGBA", "COLOR")  # the input, when Purl denoised


class PurlRenderEngine(bpy.types.RenderEngine):
    bl_idname = "PURL"
    bl_label = "Purl"
    bl_use_preview = True             # material previews render a knitted swatch (preview.py)
    bl_use_postprocess = True
    bl_use_shading_nodes_custom = False  # keep Blender's shader nodes for mesh materials
    bl_use_eevee_viewport = True      # Material Preview shading uses EEVEE; Rendered uses Purl

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
        temp_dir = tempfile.mkdtemp(prefix="purl_")
        try:
            if self.is_preview:  # the material tab's preview and the browser's icons
                width, height = self.resolution_x, self.resolution_y
                exported = preview.preview_export(depsgraph, width, height)
            else:
                width, height = self._result_size(scene)
                self.update_stats("", "Purl | exporting")
                exported = export_scene(depsgraph, size=(width, height), temp_dir=temp_dir)
                type(self).last_export = exported
            for level, message in exported.problems.items:
                self.report({level}, "Purl: " + message)
            if not exported.renderable:
                return
            cycles = None
            if scene.purl.use_cycles_composite and not self.is_preview:
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
        """Renders Purl's half in sample passes, showing each in the result as it finishes (Esc
        keeps what was rendered); with `cycles`, composites the finished image over Cycles'."""
        width, height = size
        base_dir = bpy.path.abspath("//") if bpy.data.filepath else ""
        # Denoised after the last pass in a child process (addon/denoise.py), never in Blender's.
        denoise_after = exported.scene["render"].pop("denoise", False)
        try:
            job = core.RenderJob(exported.scene, exported.arrays, base_dir)
        except core.Error as error:
            self.report({"ERROR"}, "Purl: {}".format(error))
            return
        samples = int(exported.scene["render"]["spp"])
        result = None
        if cycles is None:
            result = self.begin_result(0, 0, width, height, layer=layer_name)
        shown = {"at": time.monotonic(), "cost": 0.0}
        try:
            def show(accumulated, final):
                # Passes in between are for eyes only: none in background renders, and none that
                # would cost more than a quarter of the time since the last one (large 3.4 EXRs).
                now = time.monotonic()
                if result is None or (not final and (not self.shows_passes() or
                                                     shown["cost"] > 0.25 * (now - shown["at"]))):
                    return
                passes = self._denoised(core, accumulated.passes) if final and denoise_after else accumulated.passes
                self._write_result(result, job, passes, temp_dir, layer_name, final)
                if not final:
                    self.update_result(result)
                shown["at"], shown["cost"] = time.monotonic(), time.monotonic() - now
            accumulated = self._run_passes(core, job, exported.stats, samples, show)
            if cycles is None or accumulated is None or accumulated.samples < samples:
                return
            passes = self._denoised(core, accumulated.passes) if denoise_after else accumulated.passes
            if not self._wait_for_cycles(cycles):
                return
            try:
                rgba, depth = cycles.read(layer_name)
                passes = composite.composite(passes, rgba, depth)
            except (composite.CompositeError, ValueError, OSError) as error:
                self.report({"ERROR"}, "Purl composite: {}".format(error))
                return
            result = self.begin_result(0, 0, width, height, layer=layer_name)
            self._write_result(result, job, passes, temp_dir, layer_name, final=True)
        finally:
            if result is not None:
                self.end_result(result)  # also after Esc: the passes rendered so far stay

    def _denoised(self, core, passes):
        """The passes denoised (Combined, with the input as Noisy Image), or as they are with a warning."""
        self.update_stats("", "Purl | denoising")
        denoised, problem = denoise.denoise_passes(core, passes, self._user_cancelled)
        if problem:  # the noisy image is still shown
            self.report({"WARNING"}, "Purl: not denoised: " + problem)
        return denoised or passes

    def _write_result(self, result, job, passes, temp_dir, layer_name, final):
        """Puts numpy passes (those the result has; `final` marks the render's last) into the
        result: directly on Blender 4.x, through a multilayer EXR on 3.4, whose RenderPass.rect
        takes Python sequences only (0.4 s for 512 x 512) and whose EXR loader wants every pass
        of the result in the file."""
        names = {render_pass.name for render_pass in result.layers[0].passes}  # previews: Combined only
        passes = {name: pixels for name, pixels in passes.items() if name in names}
        direct = passes
        if not compat.PASS_PIXELS_BY_FOREACH:
            exr_path = os.path.join(temp_dir, "purl_pass.exr")
            job.write(exr_path, None, layer_name, passes)  # the job's own passes; Noisy Image is not one
            result.load_from_file(exr_path)
            direct = {name: pixels for name, pixels in passes.items() if name == NOISY_PASS[0]}
        for render_pass in result.layers[0].passes:
            pixels = direct.get(render_pass.name)
            if pixels is not None and pixels.shape[-1] == render_pass.channels:
                set_pass_pixels(render_pass, pixels[::-1])  # Blender's rows run bottom to top

    def _run_passes(self, core, job, stats, samples, show):
        """Renders `samples` in passes of 1, 1, 2, 4, ... (progressive.sample_passes) and calls
        show(accumulated, final) after each. Returns the Accumulator, None when nothing was
        rendered; after Esc it holds the passes finished so far (or the first pass's tiles)."""
        summary = "{} yarns, {} points, {} triangles".format(stats["curves"], stats["points"], stats["triangles"])
        status = progressive.StatusLine(self, bpy.app.background)
        accumulated = progressive.Accumulator()
        start = time.monotonic()
        for first, count in progressive.sample_passes(samples):
            job.start(spp=count, first_sample=first)
            while not job.wait(POLL_SECONDS):
                done = first + count * float(job.progress)
                waiting = progressive.far_field_status(core)
                status.show("Purl | {} | {}{:.0f} of {} spp | {:.1f} s".format(
                    summary, waiting + " | " if waiting else "", done, samples, time.monotonic() - start),
                    done / samples)
                if self._user_cancelled():
                    job.cancel()
                    job.wait(CANCEL_GRACE_SECONDS)
                    break
            if job.error:
                self.report({"ERROR"}, "Purl: {}".format(job.error))
                return None
            if job.cancelled or not job.done:
                if accumulated.passes is None and job.done:  # keep the first pass's finished tiles
                    accumulated.add(job.passes(), count)
                    show(accumulated, True)
                status.show("Purl | cancelled after {} of {} spp".format(accumulated.samples, samples), force=True)
                return accumulated if accumulated.passes is not None else None
            accumulated.add(job.passes(), count)
            final = accumulated.samples >= samples
            show(accumulated, final)
            status.show("Purl | {} | {} of {} spp | {:.1f} s".format(
                summary, accumulated.samples, samples, time.monotonic() - start),
                accumulated.samples / samples, force=final)
        return accumulated

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

    # --- rendered viewport (viewport.py) --------------------------------------------------

    def view_update(self, context, depsgraph):
        try:
            if getattr(self, "_viewport", None) is None:
                core = native.purlcore()
                if core is None:
                    self.update_stats("", "Purl: " + native.load_error())
                    return
                self._viewport = viewport.Viewport(self, core)
            self._viewport.update(context, depsgraph)
        except Exception:  # never raise into Blender's draw loop
            traceback.print_exc()

    def view_draw(self, context, depsgraph):
        try:
            if getattr(self, "_viewport", None) is not None:
                self._viewport.draw(context, depsgraph)
        except Exception:
            traceback.print_exc()

    def shows_passes(self):
        """Whether passes show as they finish: not in background renders, where nobody sees them
        (tests stand in for a window by overriding this)."""
        return not bpy.app.background

    def _user_cancelled(self):
        # A Python method of our own, so tests can stand in for Esc (RNA's test_break cannot be overridden).
        return self.test_break()

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        for name, channels, ids, kind in PASSES:
            self.register_pass(scene, renderlayer, name, channels, ids, kind)
        if scene is not None and scene.purl.use_denoise:
            self.register_pass(scene, renderlayer, *NOISY_PASS)


def register():
    bpy.utils.register_class(PurlRenderEngine)


def unregister():
    viewport.stop_all()
    bpy.utils.unregister_class(PurlRenderEngine)
