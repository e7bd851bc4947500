"""What the rendered viewport renders: the view of a 3D viewport region as a Purl camera, and a
cache of per-object exports that depsgraph updates invalidate one object at a time.
"""
import json

import bpy

from .export import assemble, export_instance, instance_key

SENSOR_WIDTH = 36.0  # mm; any width works, the lens is derived from it


def view_from_region(region, region_data, film_transparent=False):
    """(camera, film) of the scene format for what a 3D viewport region shows, taken from its own
    projection (so the camera view, its zoom and offset come out exactly); None when the view is
    orthographic (Purl renders perspective cameras only)."""
    if region is None or region_data is None or not region_data.is_perspective:
        return None
    p = region_data.window_matrix
    width, height = int(region.width), int(region.height)
    if width < 1 or height < 1 or p[0][0] <= 0.0 or p[1][1] <= 0.0:
        return None
    # OpenGL projection: p00 = 2 lens / sensor, p11 = p00 * W / (H * y aspect), p02 and p12 the
    # off-centre shift, p22 and p23 the clipping planes.
    y_aspect = p[0][0] * width / (p[1][1] * height)
    camera = {
        "matrix_world": [float(v) for row in region_data.view_matrix.inverted() for v in row],
        "lens": float(p[0][0] * SENSOR_WIDTH / 2.0),
        "sensor_width": SENSOR_WIDTH,
        "sensor_height": SENSOR_WIDTH,
        "sensor_fit": "HORIZONTAL",
        "shift_x": float(p[0][2] / 2.0),
        "shift_y": float(p[1][2] * y_aspect * height / (2.0 * width)),
        "clip_start": float(p[2][3] / (p[2][2] - 1.0)),
        "clip_end": float(p[2][3] / (p[2][2] + 1.0)),
    }
    film = {"width": width, "height": height, "pixel_aspect_x": 1.0, "pixel_aspect_y": float(y_aspect),
            "transparent": bool(film_transparent)}
    return camera, film


def _has_geometry(part):
    return bool(part.yarns or part.meshes)


def _name(id_block):
    original = getattr(id_block, "original", None)
    return (original or id_block).name


class SceneCache:
    """Per-instance exports of the evaluated depsgraph. sync() re-exports only the instances whose
    object (or instancer) changed geometry or transform, or whose material changed; lights are
    cheap and read every time. `exports` counts yarn and mesh exports, for tests."""

    def __init__(self):
        self.parts = {}
        self.exports = 0

    def sync(self, depsgraph, problems):
        """Brings the cache up to date; True when any yarn or mesh was re-exported or removed."""
        objects, materials = set(), set()
        for update in depsgraph.updates:
            if isinstance(update.id, bpy.types.Object) and (update.is_updated_geometry or update.is_updated_transform):
                objects.add(_name(update.id))
            elif isinstance(update.id, bpy.types.Material):
                materials.add(_name(update.id))
        render_mode = getattr(depsgraph, "mode", "VIEWPORT") == "RENDER"
        changed, seen = False, set()
        for instance in depsgraph.object_instances:
            key = instance_key(instance)
            seen.add(key)
            old = self.parts.get(key)
            stale = (old is None or not objects.isdisjoint(key[:2]) or bool(old.material_names & materials)
                     or (bool(old.meshes) and bool(materials)))  # mesh colours come from their materials
            if stale or old.lights:
                new = self.parts[key] = export_instance(instance, problems, render_mode, depsgraph.view_layer)
                if stale:
                    self.exports += _has_geometry(new)
                    changed |= _has_geometry(new) or (old is not None and _has_geometry(old))
        for key in set(self.parts) - seen:
            changed |= _has_geometry(self.parts.pop(key))
        return changed

    def scene(self, depsgraph, problems, temp_dir):
        """The Export of the cached parts with the scene's world and settings."""
        return assemble(depsgraph, list(self.parts.values()), problems, temp_dir=temp_dir, with_camera=False)


def scene_key(scene_dict):
    """What must match for a render to go on: everything but the camera and film."""
    return json.dumps({k: v for k, v in scene_dict.items() if k not in ("camera", "film")}, sort_keys=True)

