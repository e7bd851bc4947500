"""Operator "Fit to Image": fits the active yarn material's BYSDF parameters so that Purl's
render of the current scene matches a target image (docs/fitting.md).

The scene is exported as for a render, the target must have the scene's render size, and
every yarn with a BYSDF material takes the fitted parameters during the fit; the result is
written to the active material (and, when a preset path is given, saved as a preset file).
The fit runs in the foreground with the progress shown in the window manager's progress bar."""
import json
import os

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
        wm = context.window_manager
        wm.progress_begin(0, self.iterations)

        def progress(state):
            wm.progress_update(min(state["iteration"], self.iterations))
            print("Purl fit: iteration {iteration} {event}: mse {mse:.6g} ({renders} renders, "
                  "{seconds:.1f} s)".format(**state))
            return True

        try:
            preset = core.fit([entry], arrays=exported.arrays, params=self.params, iterations=self.iterations,
                              spp=self.samples, progress=progress, name=context.material.name)
        except (RuntimeError, ValueError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        finally:
            wm.progress_end()
        for warning in _apply_fitted(context.material, preset):
            self.report({"WARNING"}, warning)
        if self.preset_path:
            path = bpy.path.abspath(self.preset_path)
            with open(path, "w", encoding="utf-8") as f:
                json.dump(preset, f, indent=2)
                f.write("\n")
        fit = preset["provenance"]
        self.report({"INFO"}, "fitted {}: mse {:.4g} -> {:.4g} in {} iterations ({:.1f} s)".format(
            self.params, fit["initial_mse"], fit["final_mse"], fit["iterations"], fit["seconds"]))
        return {"FINISHED"}


def register():
    bpy.utils.register_class(PURL_OT_fit_to_image)


def unregister():
    bpy.utils.unregister_class(PURL_OT_fit_to_image)
