"""Purl's settings stored in the .blend: render settings on the Scene and yarn settings on each
Material. The yarn parameters are generated at register time from purlcore.material_parameters(),
one PropertyGroup per material model, so units, ranges, defaults and tooltips are never retyped.
"""
import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, PointerProperty, StringProperty)

from . import native, parameters

BLENDER_FLOAT_LIMIT = 3.0e38  # FloatProperty rejects infinite bounds

def _registry_list(key):
    """One list of the native registry (purlcore.choices(), native/src/base/registry.h), or None."""
    core = native.purlcore()
    if core is None or not hasattr(core, "choices"):
        return None
    return core.choices().get(key)


def choice_items(key):
    """EnumProperty items of a native choice list, identifiers in upper case. Blender stores an enum
    by its position, so the default comes first and the rest follow in the registry's order: the
    order saved files have always used."""
    entry = _registry_list(key)
    if entry is None:
        return [("NONE", "None", "purlcore is not loaded")]
    ordered = sorted(entry["choices"], key=lambda c: c["name"] != entry["default"])
    return [(c["name"].upper(), c["label"], c["doc"]) for c in ordered]


def render_setting(name):
    """The native declaration of one render setting (purlcore.render_settings()), or None."""
    core = native.purlcore()
    if core is None or not hasattr(core, "render_settings"):
        return None
    return next((s for s in core.render_settings() if s["name"] == name), None)


def _setting_limits(name, whole):
    """min, max, default and description of a render setting as bpy.props arguments ({} without purlcore)."""
    s = render_setting(name)
    if s is None:
        return {}
    number = int if whole else float
    return dict(min=number(s["min"]), max=number(min(s["max"], BLENDER_FLOAT_LIMIT)),
                default=number(s["default"]), description=s["doc"])


MODE_ITEMS = choice_items("render.multiscale.mode")
PLY_METHOD_ITEMS = choice_items("render.ply_method")

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
# The Left/Right choice of a sign parameter: the native twist directions, S (-1) then Z (+1).
_TWIST = (_registry_list("handedness") or {"choices": []})["choices"]
SIGN_ITEMS = [(c["name"], c["label"], c["doc"]) for c in _TWIST]


def _sign_choice(parameter):
    """A Left/Right menu over a parameter stored as -1 or +1."""
    name = parameter["name"]
    values = [float(c["value"]) for c in _TWIST]

    def get(self):
        value = 1.0 if getattr(self, name) >= 0 else -1.0
        return values.index(value) if value in values else 0

    def set(self, index):
        setattr(self, name, values[index])

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
    # Ranges, defaults and tooltips of the render settings come from the native registry.
    samples: IntProperty(name="Samples", soft_max=4096, **_setting_limits("spp", True))
    preview_samples: IntProperty(name="Viewport Samples", default=32, min=1, soft_max=1024, update=tag_owner,
                                 description="Samples per pixel of the rendered viewport (rendered in passes "
                                             "of 1, 2, 4, ... samples after a coarse first image)")
    seed: IntProperty(name="Seed", update=tag_owner, **_setting_limits("seed", True))
    use_animated_seed: BoolProperty(name="Animated Seed", default=False,
                                    description="Add the frame number to the seed, so noise changes per frame")
    max_depth: IntProperty(name="Max Bounces", update=tag_owner, **_setting_limits("max_depth", True))
    clamp: FloatProperty(name="Clamp", update=tag_owner, **_setting_limits("clamp", False))
    multiscale_mode: EnumProperty(name="Scale", items=MODE_ITEMS, update=tag_owner,
                                  description="Which scale of the multi-scale BYSDF shades camera hits "
                                              "(docs/multiscale.md); bounces are always shaded near")
    ply_method: EnumProperty(name="Ply Search", items=PLY_METHOD_ITEMS, update=tag_owner,
                             description="How BYSDF yarns find the ply under a hit (docs/implicit-geometry.md)")
    filter_glossy: FloatProperty(name="Filter Glossy", update=tag_owner, **_setting_limits("filter_glossy", False))
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

