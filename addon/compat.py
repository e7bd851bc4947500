"""The few places where Blender 3.4, 4.5 and 5.0 differ in the API this add-on uses."""
import bpy
import numpy as np

NODES_ALWAYS_ON = bpy.app.version >= (5, 0, 0)  # 5.0 deprecates use_nodes: node trees are always used
# RenderPass.rect takes a flat float array through foreach_set from 4.x on; 3.4 wants a sequence.
PASS_PIXELS_BY_FOREACH = bpy.app.version >= (4, 0, 0)


def uses_nodes(datablock):
    """True when a material or world is shaded by its node tree."""
    if getattr(datablock, "node_tree", None) is None:
        return False
    return NODES_ALWAYS_ON or bool(getattr(datablock, "use_nodes", True))


def enable_nodes(datablock):
    """Makes a material or world use (and have) a node tree."""
    if not NODES_ALWAYS_ON or datablock.node_tree is None:
        datablock.use_nodes = True


def _has_media_type(image_settings):
    return "media_type" in image_settings.bl_rna.properties


def set_multilayer_exr(image_settings):
    """Multilayer OpenEXR output (from 5.0 it is a media type of its own)."""
    if _has_media_type(image_settings):
        image_settings.media_type = "MULTI_LAYER_IMAGE"
    image_settings.file_format = "OPEN_EXR_MULTILAYER"


def set_image_format(image_settings, file_format):
    """A single-image format such as PNG, JPEG or TIFF."""
    if _has_media_type(image_settings):
        image_settings.media_type = "IMAGE"
    image_settings.file_format = file_format


def set_pass_pixels(render_pass, pixels):
    """Fills a RenderPass from a float32 (H, W, C) array whose rows run bottom to top, as Blender's do.
    4.x takes the flat array through foreach_set; 3.4 only takes a (pixels, channels) sequence."""
    try:
        render_pass.rect.foreach_set(np.ascontiguousarray(pixels, dtype=np.float32).ravel())
    except (TypeError, ValueError, RuntimeError, AttributeError):
        render_pass.rect = pixels.reshape(-1, pixels.shape[-1])
