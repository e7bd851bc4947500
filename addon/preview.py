"""Material previews (bl_use_preview): the material tab's preview and the material browser's icons
show the yarn look on a small knitted swatch under two soft lights, instead of Blender's preview
sphere (a yarn material on a mesh would show nothing of plies and fibers).
"""
from .export import Export
from .export.materials import yarn_material
from .export.problems import Problems

SAMPLES = 4
MAX_BOUNCES = 2
# A stockinette swatch of 5 rows of 4 loops, 0.5 mm yarn, seen from above and in front.
SWATCH = {"kind": "knit", "radius": 0.0005, "courses": 5, "wales": 4}
CAMERA = {"position": [0.0, -0.014, 0.030], "look_at": [0.0, 0.0, 0.0], "lens": 50.0,
          "clip_start": 0.001, "clip_end": 10.0}
LIGHTS = [
    {"type": "area", "size": 0.03, "position": [-0.04, -0.05, 0.06], "look_at": [0, 0, 0], "power": 3.0,
     "color": [1.0, 0.97, 0.92]},
    {"type": "area", "size": 0.05, "position": [0.06, 0.03, 0.03], "look_at": [0, 0, 0], "power": 1.5,
     "color": [0.85, 0.9, 1.0]},
]
WORLD = {"color": [0.35, 0.36, 0.4]}


def previewed_material(depsgraph):
    """The material being previewed. Blender's preview scene assigns it to its shape objects,
    whose names start with "p"; the floor keeps its own."""
    found = []
    for instance in depsgraph.object_instances:
        ob = instance.object
        if not instance.show_self:
            continue
        for slot in getattr(ob, "material_slots", []):
            if slot.material is not None:
                found.append((not ob.name.startswith("p"), slot.material))
    found.sort(key=lambda item: item[0])
    return found[0][1] if found else None


def preview_export(depsgraph, width, height):
    """The preview scene as an Export, ready for the engine's render path."""
    problems = Problems()
    material = yarn_material(previewed_material(depsgraph), problems)
    scene = {
        "version": 1,
        "camera": CAMERA,
        "film": {"width": int(width), "height": int(height)},
        "render": {"spp": SAMPLES, "max_depth": MAX_BOUNCES, "multiscale": {"mode": "near"}},
        "world": WORLD,
        "lights": LIGHTS,
        "yarns": [{"name": "preview swatch", "generate": SWATCH, "material": material}],
        "meshes": [],
    }
    stats = {"curves": SWATCH["courses"], "points": 0, "triangles": 0, "lights": len(LIGHTS)}
    return Export(scene, {}, problems, stats)
