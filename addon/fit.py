"""Operator "Fit to Image": fits the active yarn material's BYSDF parameters so that Purl's
render of the current scene matches a target image (docs/fitting.md).

The scene is exported as for a render, the target must have the scene's render size, and
every yarn with a BYSDF material takes the fitted parameters during the fit; the result is
written to the active material (and, when a preset path is given, saved as a preset file).
From the panel the fit runs on a worker thread (the native fit releases the GIL) while a modal
operator shows its progress; Esc stops it early and keeps the best parameters so far. Without a
window (`blender --background`, scripts) it runs to the end before the operator returns."""
import json
import os
import threading

import bpy
from bpy.props import IntProperty, StringProperty

from . import native, presets
from .export import export_scene


def _apply_fitted(material, preset):
    """Sets the fitted appearance parameters; the yarn geometry and fiber settings stay the
    user's (the preset's "yarn" and "fiber" objects describe the fit's scene, not this material)."""
    values = {k: v for k, v in preset["material"].items() if k not in ("yarn", "fiber")}
    return presets.apply_preset(material, {"material": values})


class PURL_OT_fit_to_image(bpy.types.Operator):
    bl_idname = "purl.fit_to_image"
    bl_label = "Fit to Image"
    bl_description = ("Fit the active material's BYSDF parameters so that Purl's render of this scene "
                      "matches a target image of the render size")
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(name="Target", subtype="FILE_PATH",
                             description="Target image (EXR or PNG) with the scene's render size")
    mask_path: StringProperty(name="Mask", subtype="FILE_PATH",
                              description="Optional mask image: pixels where it is 0 do not count")
    params: StringProperty(name="Parameters", default="kxB,kyB,sigma_t",
                           description="Comma-separated parameters to fit (names or symbols, docs/fitting.md)")
    iterations: IntProperty(name="Iterations", default=10, min=1, max=200)
    samples: IntProperty(name="Samples", default=16, min=1, max=4096,
                         description="Samples per pixel of every render inside the fit")
    preset_path: StringProperty(name="Save Preset", subtype="FILE_PATH",
                                description="Optional: also write the fitted preset (JSON) here")

    @classmethod
    def poll(cls, context):
        material = getattr(context, "material", None)
        return material is not None and material.purl.model == "bysdf"

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self)

    def execute(self, context):
        core = native.purlcore()
        if core is None:
            self.report({"ERROR"}, "Purl's native module is missing: {}".format(native.load_error()))
            return {"CANCELLED"}
        target = bpy.path.abspath(self.filepath)
        if not target or not os.path.isfile(target):
            self.report({"ERROR"}, "{}: no such target image".format(target or "(none)"))
            return {"CANCELLED"}
        exported = export_scene(context.evaluated_depsgraph_get())
        errors = exported.problems.messages("ERROR")
        if errors:
            self.report({"ERROR"}, "; ".join(errors))
            return {"CANCELLED"}
        entry = {"scene": exported.scene, "image": target}
        if self.mask_path:
            entry["mask"] = bpy.path.abspath(self.mask_path)
        self._material_name = context.material.name  # by name: the user may edit or undo meanwhile
        self._job = FitJob(core, entry, exported.arrays, self.params, self.iterations, self.samples,
                           context.material.name)
        wm = context.window_manager
        if bpy.app.background or context.window is None:  # no event loop to return to: finish here
            self._job.run()
            return self._finish()
        self._job.start()
        wm.progress_begin(0, self.iterations)
        self._timer = wm.event_timer_add(0.25, window=context.window)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC":
            self._job.stop()  # the fit ends after its current step, keeping the best so far
            return {"RUNNING_MODAL"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}  # the rest of Blender stays usable while the fit runs
        wm = context.window_manager
        state = self._job.state
        if state:
            wm.progress_update(min(state["iteration"], self.iterations))
            context.area and context.area.header_text_set(
                "Purl fit: iteration {} of {}, mse {:.4g}, at most ~{:.0f} s left (Esc stops)".format(
                    state["iteration"], self.iterations, state["mse"], state.get("seconds_left", 0)))
        if not self._job.finished:
            return {"PASS_THROUGH"}  # other timers are not ours to swallow
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.area and context.area.header_text_set(None)
        return self._finish()

    def _finish(self):
        job = self._job
        if job.error is not None:
            self.report({"ERROR"}, job.error)
            return {"CANCELLED"}
        preset = job.result
        material = bpy.data.materials.get(self._material_name)
        if material is None:
            self.report({"WARNING"}, "material '{}' was removed during the fit; the result is not applied{}".format(
                self._material_name, " (it is in the preset file)" if self.preset_path else ""))
        else:
            for warning in _apply_fitted(material, preset):
                self.report({"WARNING"}, warning)
        if self.preset_path:
            path = bpy.path.abspath(self.preset_path)
            try:
                with open(path, "w", encoding="utf-8") as f:
                    json.dump(preset, f, indent=2)
                    f.write("\n")
            except OSError as error:
                self.report({"ERROR"}, "{}: cannot write the preset ({})".format(path, error.strerror))
        fit = preset["provenance"]
        self.report({"INFO"}, "fitted {}: mse {:.4g} -> {:.4g} in {} iterations ({:.1f} s){}".format(
            self.params, fit["initial_mse"], fit["final_mse"], fit["iterations"], fit["seconds"],
            "; stopped early, best so far applied (Ctrl+Z undoes it)" if job.stopped else ""))
        return {"FINISHED"}


_running = set()  # FitJobs on worker threads


def _stop_running_fits():
    for job in list(_running):
        job.stop()


# Runs when the interpreter shuts down (Blender quits), before it joins non-daemon threads.
threading._register_atexit(_stop_running_fits)


class FitJob:
    """One native fit, run here (run) or on a worker thread (start). The worker touches no bpy
    data: it only calls the native module and records its progress for the modal operator."""

    def __init__(self, core, entry, arrays, params, iterations, samples, name):
        self._call = lambda progress: core.fit([entry], arrays=arrays, params=params, iterations=iterations,
                                               spp=samples, progress=progress, name=name)
        self._thread = None
        self._stop = threading.Event()
        self.state = None       # the latest progress dict
        self.result = None      # the fitted preset dict
        self.error = None       # the native error's message
        self.stopped = False    # Esc ended the fit early

    def _progress(self, state):
        self.state = dict(state)
        if state["event"] != "jacobian":  # one line per step; the header shows every derivative
            print("Purl fit: iteration {iteration} {event}: mse {mse:.6g} ({renders} renders, "
                  "{seconds:.1f} s, at most ~{seconds_left:.0f} s left)".format(**state))
        if self._stop.is_set():
            self.stopped = True
            return False
        return True

    def run(self):
        try:
            self.result = self._call(self._progress)
        except (RuntimeError, ValueError) as error:
            self.error = str(error)
        finally:
            _running.discard(self)

    def start(self):
        # Not a daemon: at exit Python joins it after _stop_running_fits asked it to stop, so the
        # native fit is never torn down mid-render (that aborts the process).
        self._thread = threading.Thread(target=self.run, name="purl-fit")
        _running.add(self)
        self._thread.start()

    def stop(self):
        self._stop.set()

    @property
    def finished(self):
        return self._thread is None or not self._thread.is_alive()


def register():
    bpy.utils.register_class(PURL_OT_fit_to_image)


def unregister():
    _stop_running_fits()
    bpy.utils.unregister_class(PURL_OT_fit_to_image)
