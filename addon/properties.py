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


def tag_owner(self, context):
    """Property update: bpy.props values do not tag their data-block for the depsgraph, so a
    rendered viewport would not hear of the edit."""
    self.id_data.update_tag()


def make_property(parameter, update=None):
    """A bpy property for one native parameter declaration: label and unit from the declaration,
    an integer field for whole numbers, a colour picker for colours. Every edit tags the
    data-block (tag_owner), after `update` when one is given."""
    on_change = tag_owner
    if update is not None:
        def on_change(self, context):
            update(self, context)
            tag_owner(self, context)
    low, high = _bounds(parameter)
    name = parameters.label(parameter)
    components = int(parameter["components"])
    default = parameter["default"]
    if is_count(parameter):
        return IntProperty(name=name, description=_tooltip(parameter), min=int(low), max=int(high),
                           default=int(round(float(default))), update=on_change)
    subtype, unit = _UNIT_SUBTYPES.get(parameter.get("unit") or "", ("NONE", "NONE"))
    common = dict(name=name, description=_tooltip(parameter), min=low, max=high,
                  soft_min=low, soft_max=high, unit=unit, update=on_change)
    if components == 1:
        value = float(default[0] if isinstance(default, (list, tuple)) else default)
        return FloatProperty(default=min(max(value, low), high), subtype=subtype, **common)
    values = [min(max(float(v), low), high) for v in list(default)[:components]]
    # Vector properties have their own subtypes; a unit still shows through `unit`.
    subtype = "COLOR" if parameter.get("is_color") else "NONE"
    return FloatVectorProperty(size=components, default=values, subtype=subtype, **common)


SIGN_SUFFIX = "_choice"  # the Left/Right menu shown for a sign parameter (is_sign)
SIGN_ITEMS = [("S", "Left (S)", "S twist: turns like the middle of the letter S (left-handed), stored as -1"),
              ("Z", "Right (Z)", "Z twist: turns like the middle of the letter Z (right-handed), stored as +1")]


def _sign_choice(parameter):
    """A Left/Right menu over a parameter stored as -1 or +1."""
    name = parameter["name"]

    def get(self):
        return 1 if getattr(self, name) >= 0 else 0

    def set(self, index):
        setattr(self, name, 1.0 if index == 1 else -1.0)

    return EnumProperty(name=parameters.label(parameter), items=SIGN_ITEMS, get=get, set=set,
                        description=_tooltip(parameter))


def _params_class(name, declarations, updates=None):
    updates = updates or {}
    annotations = {p["name"]: make_property(p, updates.get(p["name"])) for p in declarations}
    for p in declarations:
        if p.get("is_sign"):
            annotations[p["name"] + SIGN_SUFFIX] = _sign_choice(p)
    return type(name, (bpy.types.PropertyGroup,), {"__annotations__": annotations})


def _color_changed(self, context):
    """Picking a yarn colour switches it on: one control makes a red yarn."""
    settings = getattr(self.id_data, "purl", None)
    if settings is not None and not settings.use_color:
        settings.use_color = True


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
    preview_samples: IntProperty(name="Viewport Samples", default=32, min=1, soft_max=1024, update=tag_owner,
                                 description="Samples per pixel of the rendered viewport (rendered in passes "
                                             "of 1, 2, 4, ... samples after a coarse first image)")
    seed: IntProperty(name="Seed", description="The image is a function of scene, seed and samples",
                      default=0, min=0, update=tag_owner)
    use_animated_seed: BoolProperty(name="Animated Seed", default=False,
                                    description="Add the frame number to the seed, so noise changes per frame")
    max_depth: IntProperty(name="Max Bounces", description="Path length limit", default=8, min=1,
                           max=1024, update=tag_owner)
    clamp: FloatProperty(name="Clamp", description="Clamp sample radiance (0 turns clamping off)",
                         default=0.0, min=0.0, update=tag_owner)
    multiscale_mode: EnumProperty(name="Scale", items=MODE_ITEMS, default="AUTO", update=tag_owner,
                                  description="Which scale of the multi-scale BYSDF shades camera hits "
                                              "(docs/multiscale.md); bounces are always shaded near")
    ply_method: EnumProperty(name="Ply Search", items=PLY_METHOD_ITEMS, default="ELLIPTICAL", update=tag_owner,
                             description="How BYSDF yarns find the ply under a hit (docs/implicit-geometry.md)")
    filter_glossy: FloatProperty(
        name="Filter Glossy", default=1.0, min=0.0, soft_max=10.0, update=tag_owner,
        description="As in Cycles: after a diffuse-like bounce, glossy lobes are blurred by this much, which "
                    "removes most fireflies at a small bias in indirect highlights (0: off)")
    use_denoise: BoolProperty(
        name="Denoise", default=False,
        description="Denoise the image with Intel Open Image Denoise after the last sample, guided by the "
                    "Denoising Albedo and Normal passes (needs `pip install pyoidn`; the noisy image is kept "
                    "as the Noisy Image pass)")
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
    _model_items = [(m, parameters.model_label(m), "Yarn scattering model '{}'".format(m))
                    for m in models] or [("placeholder", "Placeholder", "purlcore is not loaded")]
    model_classes = [_model_params_class(m) for m in models]
    geometry_class = _params_class("PURL_PG_yarn_geometry", parameters.yarn_geometry())
    artist_class = _params_class("PURL_PG_artist", parameters.artist_parameters(), {"color": _color_changed})
    annotations = {
        "model": StringProperty(name="Model", default=_model_items[0][0]),
        "model_choice": EnumProperty(name="Model", description="Yarn scattering model", update=tag_owner,
                                     items=_model_enum_items, get=_get_model_index, set=_set_model_index),
        "color_attribute": StringProperty(
            name="Colour Attribute", update=tag_owner,
            description="Per-curve colour attribute of the yarn objects (empty: none)"),
        "use_color": BoolProperty(
            name="Yarn Colour", default=False, update=tag_owner,
            description="Give the yarn this colour (on: replaces the hue of the body albedos, keeping their "
                        "strengths; off: the material's own albedos, or a Principled Hair BSDF's colour)"),
        "preset_label": StringProperty(name="Preset", description="The preset last applied to this material"),
        "preset_description": StringProperty(name="Preset Description"),
    }
    for model, cls in zip(models, model_classes):
        annotations["params_" + model] = PointerProperty(type=cls)
    annotations["yarn_geometry"] = PointerProperty(type=geometry_class)
    annotations["artist"] = PointerProperty(type=artist_class)
    material_class = type("PURL_PG_material", (bpy.types.PropertyGroup,), {"__annotations__": annotations})
    _classes[:] = model_classes + [geometry_class, artist_class, PurlSceneSettings, material_class]
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

