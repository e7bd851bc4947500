"""Rendering from scripts: one function and one operator, both independent of the add-on's
installed name, for `blender -b file.blend --python-expr ...` and render-farm jobs, and the check
a farm task runs before rendering (docs/farm.md).

    bpy.ops.purl.render_to_file(filepath="//yarn.png")      # from any script
"""
import os

import bpy
from bpy.props import IntProperty, StringProperty

from .compat import set_image_format, set_multilayer_exr
from .engine import PurlRenderEngine

_FORMATS = {".png": "PNG", ".exr": "MULTILAYER_EXR", ".jpg": "JPEG", ".jpeg": "JPEG",
            ".tif": "TIFF", ".tiff": "TIFF"}


def render_to_file(filepath, scene=None, frame=None):
    """Renders `scene` (the context's by default) with Purl to `filepath`, its format chosen by
    the extension (.png, .exr multilayer with all passes, .jpg, .tif). The scene's own settings
    are restored afterwards. Returns the absolute path; raises RuntimeError with Purl's messages
    when the render failed."""
    scene = scene or bpy.context.scene
    path = bpy.path.abspath(filepath)
    extension = os.path.splitext(path)[1].lower()
    if extension not in _FORMATS:
        raise ValueError("{}: unknown image extension (use one of {})".format(
            filepath, ", ".join(sorted(_FORMATS))))
    render = scene.render
    settings = render.image_settings
    saved = (render.engine, render.filepath, render.use_file_extension,
             getattr(settings, "media_type", None), settings.file_format, scene.frame_current)
    try:
        render.engine = PurlRenderEngine.bl_idname
        render.filepath = path
        render.use_file_extension = False
        if _FORMATS[extension] == "MULTILAYER_EXR":
            set_multilayer_exr(settings)
        else:
            set_image_format(settings, _FORMATS[extension])
        if frame is not None:
            scene.frame_set(frame)
        PurlRenderEngine.last_export = None
        bpy.ops.render.render(write_still=True, scene=scene.name)
    finally:
        render.engine, render.filepath, render.use_file_extension = saved[:3]
        if saved[3] is not None:
            settings.media_type = saved[3]
        settings.file_format = saved[4]
        if frame is not None:
            scene.frame_set(saved[5])
    exported = PurlRenderEngine.last_export
    errors = exported.problems.messages("ERROR") if exported is not None else ["the render did not run"]
    if errors:
        raise RuntimeError("; ".join(errors))
    return path


def missing_input_files(scene):
    """The files a Purl render of `scene` would read that are not on this machine. Purl reads
    nothing outside the .blend but the world's images (Environment Texture), so those that are
    neither packed nor found; the export would only warn about them and render a white world,
    which on a render farm must stop the task instead."""
    world = scene.world
    nodes = world.node_tree.nodes if world is not None and world.node_tree is not None else []
    missing = []
    for node in nodes:
        image = getattr(node, "image", None)
        if image is None or image.packed_file is not None or image.source != "FILE":
            continue
        path = bpy.path.abspath(image.filepath, library=image.library)
        if not os.path.isfile(path):
            missing.append(path)
    return missing


class PURL_OT_render_to_file(bpy.types.Operator):
    bl_idname = "purl.render_to_file"
    bl_label = "Render Yarns to File"
    bl_description = "Render the scene with Purl and save the image"

    filepath: StringProperty(subtype="FILE_PATH")
    frame: IntProperty(default=-1, description="Frame to render (-1: the current frame)")

    def execute(self, context):
        try:
            path = render_to_file(self.filepath, context.scene, None if self.frame < 0 else self.frame)
        except (RuntimeError, ValueError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, "saved " + path)
        return {"FINISHED"}


def register():
    bpy.utils.register_class(PURL_OT_render_to_file)


def unregister():
    bpy.utils.unregister_class(PURL_OT_render_to_file)
