"""Yarn presets: JSON files listed in a menu, applied to the active material, saved by the user.

A preset file holds the scene format's material object, so the CLI reads the same file:
    {"name": "wool", "label": "Wool (knit)", "description": "one line an artist reads",
     "source": "where the numbers come from",
     "material": {"model": "bysdf", ...},
     "blender": {"color_attribute": ""}}
"label" (else "name") is shown in the menu, "description" and "source" in its tooltip. "blender"
holds the settings the native material does not read yet; it is optional. A preset sets the
physics parameters; the artist controls (yarn colour, sheen, ...) stay as the artist set them
unless the preset names them.
"""
import json
import os

import bpy
from bpy.props import StringProperty

from . import parameters, properties
from .export.materials import artist_values

ADDON_DIR = os.path.dirname(os.path.abspath(__file__))


def user_preset_dir(create=False):
    return bpy.utils.user_resource("CONFIG", path=os.path.join("purl", "presets"), create=create)


def preset_dirs():
    """Folders searched for presets: shipped with the add-on, the repository's (when the add-on
    runs from a checkout) and the user's own."""
    candidates = [os.path.join(ADDON_DIR, "presets"),
                  os.path.join(os.path.dirname(ADDON_DIR), "presets"),
                  user_preset_dir()]
    seen, result = set(), []
    for folder in candidates:
        real = os.path.realpath(folder)
        if real not in seen and os.path.isdir(folder):
            seen.add(real)
            result.append(folder)
    return result


def list_presets():
    """[(label, path)] of every *.json preset, sorted by label within each folder."""
    found = []
    for folder in preset_dirs():
        entries = []
        for file_name in os.listdir(folder):
            if file_name.endswith(".json"):
                path = os.path.join(folder, file_name)
                entries.append((_label(path), path))
        found += sorted(entries)
    return found


def _read_display(path):
    """The preset's display fields; {} when the file cannot be read."""
    try:
        with open(path, encoding="utf-8") as f:
            preset = json.load(f)
        return preset if isinstance(preset, dict) else {}
    except (OSError, ValueError):
        return {}


def preset_label(preset, file_stem):
    """What the menu shows: "label", else "name" with a capital, else the file's name."""
    name = preset.get("label") or str(preset.get("name") or file_stem)
    return name[:1].upper() + name[1:]


def _label(path):
    preset, stem = _read_display(path), os.path.basename(path)[:-5]
    return preset_label(preset, stem) if preset else stem + " (unreadable)"


def preset_tooltip(path):
    """Description and source of a preset, for its menu item's tooltip."""
    preset = _read_display(path)
    parts = [str(preset.get(key)) for key in ("description", "source") if preset.get(key)]
    return ". Source: ".join(parts) if parts else path


def read_preset(path):
    """The preset dict; ValueError naming the file and the reason when it is not a preset."""
    try:
        with open(path, encoding="utf-8") as f:
            preset = json.load(f)
    except OSError as error:
        raise ValueError("{}: cannot read ({})".format(path, error.strerror))
    except ValueError as error:
        raise ValueError("{}: not valid JSON ({})".format(path, error))
    if not isinstance(preset, dict) or not isinstance(preset.get("material"), dict):
        raise ValueError("{}: a preset needs a \"material\" object".format(path))
    return preset


def _apply_values(target, declarations, values, warnings, place=""):
    """Sets each declared value on a property group, with warnings for unknown keys and bad values."""
    declared = {p["name"]: p for p in declarations}
    for key, value in values.items():
        parameter = declared.get(key)
        if parameter is None:
            warnings.append("unknown parameter '{}{}' ignored".format(place, key))
            continue
        try:
            if properties.is_count(parameter):
                value = int(round(float(value)))
            elif parameter["components"] == 1:
                value = float(value)
            else:
                value = [float(v) for v in value]
                if len(value) != parameter["components"]:
                    raise ValueError
        except (TypeError, ValueError):
            warnings.append("'{}{}' needs {} number(s)".format(place, key, parameter["components"]))
            continue
        low, high = parameter["min"], parameter["max"]
        scalars = [value] if parameter["components"] == 1 else value
        if any(v < low or v > high for v in scalars):
            warnings.append("'{}{}' is outside [{}, {}] and was clamped".format(place, key, low, high))
        setattr(target, key, value)


def apply_preset(material, preset):
    """Sets the material's Purl settings from a preset; returns a list of warnings."""
    warnings = []
    settings = material.purl
    values = dict(preset["material"])
    model = values.pop("model", settings.model)
    if model not in parameters.models():
        return ["model '{}' is not known to this version of Purl".format(model)]
    settings.model = model
    geometry = values.pop("yarn", None)
    # The explicit-fiber reference's scattering parameters (what a preset was fitted against);
    # the add-on renders the BYSDF, which does not read them.
    values.pop("fiber", None)
    if model in parameters.ARTIST_MODELS:
        artist_names = {p["name"] for p in parameters.artist_parameters()}
        artist = {k: values.pop(k) for k in list(values) if k in artist_names}
        _apply_values(settings.artist, parameters.artist_parameters(), artist, warnings)
        if "color" in artist:
            settings.use_color = True
    _apply_values(getattr(settings, "params_" + model), parameters.parameters(model), values, warnings)
    if isinstance(geometry, dict) and model in parameters.YARN_GEOMETRY_MODELS:
        if "preset" in geometry:
            warnings.append("yarn presets are not read in Blender; give the yarn values instead")
            geometry = {k: v for k, v in geometry.items() if k != "preset"}
        _apply_values(settings.yarn_geometry, parameters.yarn_geometry(), geometry, warnings, "yarn.")
    elif geometry is not None:
        warnings.append("'yarn' is ignored for model '{}'".format(model))
    extra = preset.get("blender") or {}
    if "mode" in extra:  # presets saved before the scale became a render setting
        warnings.append("'mode' is a render setting now (Render Properties > Purl > Scale); ignored")
    if "color_attribute" in extra:
        settings.color_attribute = str(extra["color_attribute"])
    settings.preset_label = preset_label(preset, "preset")
    settings.preset_description = str(preset.get("description") or "")
    return warnings


def preset_from_material(material, name, description=""):
    settings = material.purl
    values = getattr(settings, "params_" + settings.model, None)
    result_material = {"model": settings.model}
    for parameter in parameters.parameters(settings.model):
        result_material[parameter["name"]] = parameters.value_for_export(
            parameter, getattr(values, parameter["name"]))
    if settings.model in parameters.ARTIST_MODELS:
        result_material.update(artist_values(material))
    if settings.model in parameters.YARN_GEOMETRY_MODELS and parameters.yarn_geometry():
        result_material["yarn"] = {p["name"]: parameters.value_for_export(p, getattr(settings.yarn_geometry, p["name"]))
                                   for p in parameters.yarn_geometry()}
    return {"name": name, "label": name, "description": description,
            "source": "saved from Blender material '{}'".format(material.name),
            "material": result_material,
            "blender": {"color_attribute": settings.color_attribute}}


def save_preset(material, name, folder=None):
    """Writes the material's settings as <folder>/<name>.json (the user's folder by default)."""
    folder = folder or user_preset_dir(create=True)
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, bpy.path.clean_name(name) + ".json")
    temp_path = path + ".tmp"
    with open(temp_path, "w", encoding="utf-8") as f:
        json.dump(preset_from_material(material, name), f, indent=2)
        f.write("\n")
    os.replace(temp_path, path)  # never leave a half-written preset behind
    return path


class PURL_OT_preset_apply(bpy.types.Operator):
    bl_idname = "purl.preset_apply"
    bl_label = "Apply Yarn Preset"
    bl_description = "Set the active material's yarn settings from a preset"
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(subtype="FILE_PATH", options={"SKIP_SAVE"})

    @classmethod
    def poll(cls, context):
        return getattr(context, "material", None) is not None

    @classmethod
    def description(cls, context, properties):
        return preset_tooltip(properties.filepath) if properties.filepath else cls.bl_description

    def execute(self, context):
        try:
            preset = read_preset(self.filepath)
        except ValueError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        for warning in apply_preset(context.material, preset):
            self.report({"WARNING"}, "{}: {}".format(os.path.basename(self.filepath), warning))
        return {"FINISHED"}


class PURL_OT_preset_save(bpy.types.Operator):
    bl_idname = "purl.preset_save"
    bl_label = "Save Yarn Preset"
    bl_description = "Save the active material's yarn settings as a preset in your config folder"

    name: StringProperty(name="Name", default="My yarn")

    @classmethod
    def poll(cls, context):
        return getattr(context, "material", None) is not None

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self)

    def execute(self, context):
        if not self.name.strip():
            self.report({"ERROR"}, "a preset needs a name")
            return {"CANCELLED"}
        try:
            path = save_preset(context.material, self.name.strip())
        except OSError as error:
            self.report({"ERROR"}, "cannot save the preset: {}".format(error))
            return {"CANCELLED"}
        self.report({"INFO"}, "saved {}".format(path))
        return {"FINISHED"}


class PURL_MT_presets(bpy.types.Menu):
    bl_idname = "PURL_MT_presets"
    bl_label = "Yarn Presets"

    def draw(self, context):
        layout = self.layout
        presets = list_presets()
        if not presets:
            layout.label(text="No presets found")
        for label, path in presets:
            layout.operator(PURL_OT_preset_apply.bl_idname, text=label).filepath = path


classes = (PURL_OT_preset_apply, PURL_OT_preset_save, PURL_MT_presets)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
