"""The Cycles half of a composite render, run in a separate Blender (or bpy) process:

    blender -b --factory-startup --python composite_worker.py -- job.json
    python composite_worker.py job.json            (the bpy module)

job.json names a .blend holding a copy of the scene, the scene and view layer, the yarn objects
to hide from the camera, the frame, samples, seed and the EXR to write. The yarns stay visible to
every other ray, so they still cast shadows and show in reflections of the Cycles render.
Nothing of the Purl add-on is imported here: this file only needs bpy.
"""
import json
import sys

import bpy


def _job_path():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    if not argv:
        raise SystemExit("composite_worker.py: no job file given")
    return argv[-1]


def _set_multilayer_exr(settings):
    if "media_type" in settings.bl_rna.properties:  # Blender 5.0
        settings.media_type = "MULTI_LAYER_IMAGE"
    settings.file_format = "OPEN_EXR_MULTILAYER"
    settings.exr_codec = "NONE"  # the add-on's reader reads uncompressed files only
    settings.color_depth = "32"


def main():
    with open(_job_path(), encoding="utf-8") as f:
        job = json.load(f)
    bpy.ops.wm.open_mainfile(filepath=job["blend"], load_ui=False)
    scene = bpy.data.scenes[job["scene"]]
    scene.frame_set(job["frame"])
    render = scene.render
    render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = job["samples"]
    scene.cycles.seed = job["seed"]
    if hasattr(scene.cycles, "use_denoising"):
        scene.cycles.use_denoising = False  # Purl's half is not denoised either
    render.use_compositing = False   # the layer passes, not the user's composite
    render.use_sequencer = False
    for name in job["hide"]:
        ob = bpy.data.objects.get(name)
        if ob is not None:
            ob.visible_camera = False  # still casts shadows and shows in reflections
    for name in job["hide_hair"]:
        settings = bpy.data.particles.get(name)
        if settings is not None:
            settings.render_type = "NONE"  # no camera-only switch for particle hair
    layer = scene.view_layers[job["layer"]]
    layer.use_pass_combined = True
    layer.use_pass_z = True
    _set_multilayer_exr(render.image_settings)
    render.filepath = job["output"]
    render.use_file_extension = False
    bpy.ops.render.render(write_still=True, scene=scene.name, layer=layer.name)


if __name__ == "__main__":
    main()
