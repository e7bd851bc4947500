"""Blender depsgraph -> Purl scene (the JSON object of docs/scene-format.md) + in-memory arrays.

export_scene() is a pure function of the evaluated depsgraph: it reads, never writes, Blender data.
Problems (bad objects, unsupported settings) are collected and returned, never raised, so one bad
object costs a warning instead of the render.
"""
from dataclasses import dataclass, field

from . import camera, lights, meshes, world, yarns
from .materials import yarn_material
from .transforms import placed_at
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
            "ply_method": settings.ply_method.lower(),
            "denoise": bool(settings.use_denoise),
            "filter_glossy": float(settings.filter_glossy)}


def _guarded(problems, ob, export, *args):
    """Runs one object's export; an unexpected failure skips that object with a warning."""
    try:
        return export(*args)
    except (RuntimeError, ValueError, TypeError, AttributeError, IndexError, KeyError,
            FloatingPointError, MemoryError) as error:
        problems.warning(ob.name, "could not be exported ({}: {}); skipped".format(type(error).__name__, error))
        return []


@dataclass
class InstanceExport:
    """What one object instance contributes: checked yarn sets (with their material objects
    already converted, so a cached part keeps no Blender data), meshes and lights."""
    yarns: list = field(default_factory=list)      # YarnCurves, world space
    materials: list = field(default_factory=list)  # the scene format's material object per yarn set
    material_names: set = field(default_factory=set)
    meshes: list = field(default_factory=list)     # MeshTriangles
    lights: list = field(default_factory=list)     # the scene format's light objects


def instance_key(instance):
    """Names an object instance across depsgraph updates: the object, or for an instance the
    object that made it, the instanced object and its persistent id."""
    ob = instance.object
    name = ob.original.name if ob.original is not None else ob.name
    if not instance.is_instance or instance.parent is None:
        return (name,)
    parent = instance.parent.original.name if instance.parent.original is not None else instance.parent.name
    return (parent, name, tuple(instance.persistent_id))


def export_instance(instance, problems, render_mode, view_layer, yarns_only=False):
    """One object instance of the depsgraph as an InstanceExport."""
    part = InstanceExport()
    ob = instance.object
    matrix = instance.matrix_world.copy()  # the iterator reuses its matrix
    found = []
    if instance.show_particles and len(ob.particle_systems) > 0:
        found += _guarded(problems, ob, yarns.particle_hair, ob, matrix, render_mode)
    if instance.show_self:
        original = ob.original if ob.original is not None else ob
        if ob.type == "CURVES":
            found += _guarded(problems, ob, yarns.hair_curves, ob, matrix, problems)
        elif ob.type == "CURVE":
            found += _guarded(problems, ob, yarns.curve_object, ob, matrix, problems)
        elif yarns_only:
            pass
        elif ob.type in MESH_TYPES and not (instance.is_instance and original.type == "CURVE"):
            # (a curve's bevel tube is skipped: the curve is exported as yarn instead)
            holdout = _is_holdout(original, view_layer)
            part.meshes = _guarded(problems, ob, meshes.mesh_object, ob, matrix, holdout)
        elif ob.type == "LIGHT":
            light = _guarded(problems, ob, lights.export_light, ob, matrix, problems)
            part.lights = [light] if light else []
    part.yarns = [y for y in (yarns.checked(y, problems) for y in found) if y is not None]
    part.materials = [yarn_material(y.material, problems) for y in part.yarns]
    part.material_names = {y.material.name for y in part.yarns if y.material is not None}
    return part


def collect_yarns(depsgraph, problems):
    """Every yarn-like object of the depsgraph as checked YarnCurves (world space)."""
    render_mode = _is_render_mode(depsgraph)
    return [y for instance in depsgraph.object_instances
            for y in export_instance(instance, problems, render_mode, depsgraph.view_layer, yarns_only=True).yarns]


def export_scene(depsgraph, size=None, temp_dir=None):
    """Exports the evaluated depsgraph. `size` overrides the film size (the engine's result size);
    `temp_dir` receives packed images written out for the native module."""
    problems = Problems()
    render_mode = _is_render_mode(depsgraph)
    parts = [export_instance(instance, problems, render_mode, depsgraph.view_layer)
             for instance in depsgraph.object_instances]
    return assemble(depsgraph, parts, problems, size, temp_dir)


def assemble(depsgraph, parts, problems, size=None, temp_dir=None, with_camera=True):
    """The Export of instance exports plus the scene's camera (unless the caller brings its own
    view, as the viewport does), film, render settings and world."""
    scene = depsgraph.scene
    result = {"version": 1}
    if with_camera:
        camera_object = scene.camera.evaluated_get(depsgraph) if scene.camera is not None else None
        cam = camera.export_camera(camera_object, problems)
        if cam is not None:
            result["camera"] = cam
    result["film"] = camera.export_film(scene, size)
    result["render"] = render_settings(scene)
    result["world"] = world.export_world(scene.world, problems, temp_dir)

    arrays, yarn_sets, mesh_sets, light_list = {}, [], [], []
    stats = {"curves": 0, "points": 0, "triangles": 0, "lights": 0}
    sources = set()
    for part in parts:
        for yarn, material in zip(part.yarns, part.materials):
            key = "yarn{}".format(len(yarn_sets))
            arrays[key] = yarn.arrays()
            yarn_sets.append({"name": yarn.name, "arrays": key, "id": len(yarn_sets) + 1,
                              "matrix_world": placed_at(yarn.origin), "material": material})
            stats["curves"] += yarn.curve_count
            stats["points"] += len(yarn.points)
            if yarn.source:
                sources.add(yarn.source)
        for mesh in part.meshes:
            key = "mesh{}".format(len(mesh_sets))
            arrays[key] = mesh.arrays()
            mesh_sets.append({"name": mesh.name, "arrays": key, "matrix_world": placed_at(mesh.origin),
                              "color": list(mesh.color), "holdout": mesh.holdout})
            stats["triangles"] += len(mesh.triangles)
        light_list += part.lights
    stats["lights"] = len(light_list)
    result["lights"] = light_list
    result["yarns"] = yarn_sets
    result["meshes"] = mesh_sets
    if not yarn_sets and not mesh_sets:
        problems.error(scene.name, "nothing to render: no yarn curves and no meshes are visible")
    return Export(result, arrays, problems, stats, sources)
