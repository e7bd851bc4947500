"""Camera and film, with Blender's own conventions (sensor fit, shift, pixel aspect)."""
from .transforms import split_scale


def film_size(render):
    """Image size in pixels as Blender computes it from resolution and percentage."""
    return (render.resolution_x * render.resolution_percentage // 100,
            render.resolution_y * render.resolution_percentage // 100)


def export_film(scene, size=None):
    render = scene.render
    width, height = size if size is not None else film_size(render)
    return {"width": int(width), "height": int(height),
            "pixel_aspect_x": float(render.pixel_aspect_x),
            "pixel_aspect_y": float(render.pixel_aspect_y),
            "transparent": bool(render.film_transparent)}


def export_camera(camera_object, problems):
    """The scene format's camera; None (with a report) when Purl cannot render through it."""
    if camera_object is None:
        problems.error("Scene", "there is no active camera")
        return None
    cam = camera_object.data
    if cam.type != "PERSP":
        problems.error(camera_object.name, "Purl renders perspective cameras only, not {}".format(
            cam.type.lower()))
        return None
    if getattr(cam.dof, "use_dof", False):
        problems.warning(camera_object.name, "depth of field is not rendered by Purl yet")
    # Blender ignores the camera object's scale when it projects.
    matrix, _ = split_scale(camera_object.matrix_world)
    return {"matrix_world": matrix,
            "lens": float(cam.lens),
            "sensor_width": float(cam.sensor_width),
            "sensor_height": float(cam.sensor_height),
            "sensor_fit": cam.sensor_fit,
            "shift_x": float(cam.shift_x),
            "shift_y": float(cam.shift_y),
            "clip_start": float(cam.clip_start),
            "clip_end": float(cam.clip_end)}
