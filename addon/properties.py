"""Purl's settings stored in the .blend: render settings on the Scene and yarn settings on each
Material. The yarn parameters are generated at register time from purlcore.material_parameters(),
one PropertyGroup per material model, so units, ranges, defaults and tooltips are never retyped.
"""
import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, PointerProperty, StringProperty)

from . import parameters

BLENDER_FLOAT_LIMIT = 3.0e38  # FloatProperty rejects infinite bounds

MODE_ITEMS = [
    ("AUTO", "Auto", "Pick near, multi or far scale from the yarn's pixel coverage"),
    ("NEAR", "Near", "Always shade plies and fibers individually"),
    ("MULTI", "Multi", "Average the yarn over the part a pixel covers (near where it covers one fiber)"),
    ("FAR", "Far", "Average the whole yarn width (for yarns thinner than a pixel)"),
]

PLY_METHOD_ITEMS = [
    ("ELLIPTICAL", "Elliptical", "Exact ply search along the ray (the default)"),
    ("LOCAL", "Local", "The yarn straightened at each hit: about a fifth faster, exact on straight yarns, "
                       "drifts on tight bends"),
    ("CIRCULAR", "Circular", "The older perpendicular cross-section: fastest, for comparison only"),
]

# Units of the native declaration -> (Blender subtype, Blender unit).
_UNIT_SUBTYPES = {
    "m": ("DISTANCE", "LENGTH"),
    "rad": ("ANGLE", "ROTATION"),
}


def _bounds(parameter):
    low = max(float(parameter["min"]), -BLENDER_FLOAT_LIMIT)
    high = min(float(parameter["max"]), BLENDER_FLOAT_LIMIT)
    return low, high


def _tooltip(parameter):
    unit = parameter.get("unit") or ""
    doc = parameter.get("doc") or parameter["name"]
    return "{} [{}]".format(doc, unit) if unit and unit not in _UNIT_SUBTYPES else doc


def is_count(parameter):
    """Native parameters are stored as floats; those declared whole numbers (is_integer) are shown
    as integers. Modules built before the flag existed: a scalar "..._count" with whole bounds."""
    if "is_integer" in parameter:
        return bool(parameter["is_integer"]) and int(parameter["components"]) == 1
    return (parameter["name"].endswith("_count") and int(parameter["components"]) == 1
            and float(parameter["min"]).is_integer() and float(parameter["max"]).is_integer())


def make_property(parameter):
    """A bpy property for one native parameter declaration."""
    low, high = _bounds(parameter)
    name = parameter["name"].replace("_", " ").capitalize()
    components = int(parameter["components"])
    default = parameter["default"]
    if is_count(parameter):
        return IntProperty(name=name, description=_tooltip(parameter), min=int(low), max=int(high),
                           default=int(round(float(default))))
    subtype, unit = _UNIT_SUBTYPES.get(parameter.get("unit") or "", ("NONE", "NONE"))
    common = dict(name=name, description=_tooltip(parameter), min=low, max=high,
                  soft_min=low, soft_max=high, unit=unit)
    if components == 1:
        value = float(default[0] if isinstance(default, (list, tuple)) else default)
        return FloatProperty(default=min(max(value, low), high), subtype=subtype, **common)
    values = [min(max(float(v), low), high) for v in list(default)[:components]]
    # Vector properties have their own subtypes; a unit still shows through `unit`.
    subtype = "COLOR" if parameter.get("is_color") else "NONE"
    return FloatVectorProperty(size=components, default=values, subtype=subtype, **common)


def _params_class(name, declarations):
    annotations = {p["name"]: make_property(p) for p in declarations}
    return type(name, (bpy.types.PropertyGroup,), {"__annotations__": annotations})


def _model_params_class(model):
    return _params_class("PURL_PG_params_" + model, parameters.parameters(model))


# EnumProperty items must stay referenced while Blender uses them.
_model_items = []


def _model_enum_items(self, context):
    return _model_items


def _get_model_index(self):
    names = [item[0] for item in _model_items]
    return names.index(self.model) if self.model in names else 0


def _set_model_index(self, index):
    if 0 <= index < len(_model_items):
        self.model = _model_items[index][0]


class PurlSceneSettings(bpy.types.PropertyGroup):
    samples: IntProperty(name="Samples", description="Samples per pixel", default=64, min=1,
                         soft_max=4096)
    seed: IntProperty(name="Seed", description="The image is a function of scene, seed and samples",
                      default=0, min=0)
    use_animated_seed: BoolProperty(name="Animated Seed", default=False,
                                    description="Add the frame number to the seed, so noise changes per frame")
    max_depth: IntProperty(name="Max Bounces", description="Path length limit", default=8, min=1,
                           max=1024)
    clamp: FloatProperty(name="Clamp", description="Clamp sample radiance (0 turns clamping off)",
                         default=0.0, min=0.0)
    multiscale_mode: EnumProperty(name="Scale", items=MODE_ITEMS, default="AUTO",
                                  description="Which scale of the multi-scale BYSDF shades camera hits "
                                              "(docs/multiscale.md); bounces are always shaded near")
    ply_method: EnumProperty(name="Ply Search", items=PLY_METHOD_ITEMS, default="ELLIPTICAL",
                             description="How BYSDF yarns find the ply under a hit (docs/implicit-geometry.md)")
    use_cycles_composite: BoolProperty(
        name="Composite with Cycles", default=False,
        description="Cycles renders the rest of the scene (yarns hidden from its camera but casting "
                    "shadows), Purl the yarns with meshes as holdouts, and the two are laid over each other")
    cycles_samples: IntProperty(name="Cycles Samples", default=64, min=1, soft_max=4096,
                                description="Samples per pixel of the Cycles half of a composite render")


_classes = []


def register():
    global _model_items
    models = parameters.models()
    # Stored as a string, so a model added or reordered natively never remaps saved files.
    _model_items = [(m, m.replace("_", " ").title(), "Yarn scattering model '{}'".format(m))
                    for m in models] or [("placeholder", "Placeholder", "purlcore is not loaded")]
    model_classes = [_model_params_class(m) for m in models]
    geometry_class = _params_class("PURL_PG_yarn_geometry", parameters.yarn_geometry())
    annotations = {
        "model": StringProperty(name="Model", default=_model_items[0][0]),
        "model_choice": EnumProperty(name="Model", description="Yarn scattering model",
                                     items=_model_enum_items, get=_get_model_index, set=_set_model_index),
        "color_attribute": StringProperty(
            name="Colour Attribute",
            description="Per-curve colour attribute of the yarn objects (empty: none)"),
    }
    for model, cls in zip(models, model_classes):
        annotations["params_" + model] = PointerProperty(type=cls)
    annotations["yarn_geometry"] = PointerProperty(type=geometry_class)
    material_class = type("PURL_PG_material", (bpy.types.PropertyGroup,), {"__annotations__": annotations})
    _classes[:] = model_classes + [geometry_class, PurlSceneSettings, material_class]
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.Material.purl = PointerProperty(type=material_class)
    bpy.types.Scene.purl = PointerProperty(type=PurlSceneSettings)


def unregister():
    del bpy.types.Scene.purl
    del bpy.types.Material.purl
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
    _classes.clear()

