"""Blender depsgraph -> Purl scene (the JSON object of docs/scene-format.md) + in-memory arrays.

export_scene() is a pure function of the evaluated depsgraph: it reads, never writes, Blender data.
Problems (bad objects, unsupported settings) are collected and returned, never raised, so one bad
object costs a warning instead of the render.
"""
from dataclasses import dataclass, field

from . import camera, lights, meshes, world, yarns
from .materials import yarn_material
from .problems import Problems

# Text, surface and metaball objects reach the depsgraph as instanced meshes, so only meshes are read.
MESH_TYPES = {"MESH"}


@dataclass
class Export:
    scene: dict                     # the scene object, ready for purlcore.RenderJob
    arrays: dict                    # name -> yarn or mesh arrays referenced by the scene
    problems: Problems
    stats: dict = field(default_factory=dict)
    yarn_objects: set = field(default_factory=set)  # names of the objects rendered as yarn

    @property
    def renderable(self):
        return bool(self.scene.get("camera")) and bool(self.scene.get("yarns") or self.scene.get("meshes"))


def _is_render_mode(depsgraph):
    return getattr(depsgraph, "mode", "RENDER") == "RENDER"


def _is_holdout(ob, view_layer):
    if getattr(ob, "is_holdout", False):
        return True
    try:
        return bool(ob.holdout_get(view_layer=view_layer))
    except (AttributeError, TypeError, RuntimeError):
        return False


def render_settings(scene):
    settings = scene.purl
    seed = settings.seed + (scene.frame_current if settings.use_animated_seed else 0)
    threads = scene.render.threads if scene.render.threads_mode == "FIXED" else 0
    return {"spp": int(settings.samples), "seed": int(seed) % 2147483647,
            "max_depth": int(settings.max_depth), "threads": int(threads),
            "clamp": float(settings.clamp),
            "multiscale": {"mode": settings.multiscale_mode.lower()},
            "ply_method": settings.ply_method.lower()}


def _guarded(problems, ob, export, *args):
    """Runs one object's export; an unexpected failure skips that object with a warning."""
    try:
        return export(*args)
    except (RuntimeError, ValueError, TypeError, AttributeError, IndexError, KeyError,
            FloatingPointError, MemoryError) as error:
        problems.warning(ob.name, "could not be exported ({}: {}); skipped".format(type(error).__name__, error))
        return []


def collect_yarns(depsgraph, problems):
    """Every yarn-like object of the depsgraph as checked YarnCurves (world space)."""
    render_mode = _is_render_mode(depsgraph)
    found = []
    for instance in depsgraph.object_instances:
        ob = instance.object
        matrix = instance.matrix_world.copy()  # the iterator reuses its matrix
        if instance.show_particles and len(ob.particle_systems) > 0:
            found += _guarded(problems, ob, yarns.particle_hair, ob, matrix, render_mode)
        if not instance.show_self:
            continue
        if ob.type == "CURVES":
            found += _guarded(problems, ob, yarns.hair_curves, ob, matrix, problems)
        elif ob.type == "CURVE":
            found += _guarded(problems, ob, yarns.curve_object, ob, matrix, problems)
    return [y for y in (yarns.checked(y, problems) for y in found) if y is not None]


def export_scene(depsgraph, size=None, temp_dir=None):
    """Exports the evaluated depsgraph. `size` overrides the film size (the engine's result size);
    `temp_dir` receives packed images written out for the native module."""
    scene = depsgraph.scene
    problems = Problems()
    arrays = {}
    result = {"version": 1}

    camera_object = scene.camera.evaluated_get(depsgraph) if scene.camera is not None else None
    cam = camera.export_camera(camera_object, problems)
    if cam is not None:
        result["camera"] = cam
    result["film"] = camera.export_film(scene, size)
    result["render"] = render_settings(scene)
    result["world"] = world.export_world(scene.world, problems, temp_dir)

    yarn_sets, stats = [], {"curves": 0, "points": 0, "triangles": 0, "lights": 0}
    found_yarns = collect_yarns(depsgraph, problems)
    for index, yarn in enumerate(found_yarns):
        key = "yarn{}".format(index)
        arrays[key] = yarn.arrays()
        yarn_sets.append({"name": yarn.name, "arrays": key, "id": index + 1,
                          "material": yarn_material(yarn.material, problems)})
        stats["curves"] += yarn.curve_count
        stats["points"] += len(yarn.points)

    mesh_sets, light_list = [], []
    view_layer = depsgraph.view_layer
    for instance in depsgraph.object_instances:
        ob = instance.object
        if not instance.show_self:
            continue
        original = ob.original if ob.original is not None else ob
        if ob.type in MESH_TYPES:
            if instance.is_instance and original.type == "CURVE":
                continue  # a curve's bevel tube: the curve is exported as yarn instead
            holdout = _is_holdout(original, view_layer)
            for mesh in _guarded(problems, ob, meshes.mesh_object, ob, instance.matrix_world.copy(), holdout):
                key = "mesh{}".format(len(mesh_sets))
                arrays[key] = mesh.arrays()
                mesh_sets.append({"name": mesh.name, "arrays": key, "color": list(mesh.color),
                                  "holdout": mesh.holdout})
                stats["triangles"] += len(mesh.triangles)
        elif ob.type == "LIGHT":
            light = _guarded(problems, ob, lights.export_light, ob, instance.matrix_world.copy(), problems)
            if light:
                light_list.append(light)
    stats["lights"] = len(light_list)

    result["lights"] = light_list
    result["yarns"] = yarn_sets
    result["meshes"] = mesh_sets
    if not yarn_sets and not mesh_sets:
        problems.error(scene.name, "nothing to render: no yarn curves and no meshes are visible")
    return Export(result, arrays, problems, stats, {y.source for y in found_yarns if y.source})
