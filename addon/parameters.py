"""The native material parameter declarations, read once from purlcore.

Everything that lists yarn parameters in the add-on (properties, panel, export, presets) reads
them from here, so the native declaration stays the only place they are written down.
"""
from . import native

_tables = None  # model name -> list of parameter dicts

YARN_GEOMETRY_MODELS = {"bysdf"}  # models that read material.yarn


def tables():
    """{model: [{name, unit, components, min, max, default, doc, is_color}, ...]}; empty without purlcore."""
    global _tables
    if _tables is None:
        core = native.purlcore()
        if core is None:
            return {}
        _tables = {model: list(core.material_parameters(model)) for model in core.material_models()}
    return _tables


_lists = {}  # purlcore function name -> the list it returned


def _native_list(function):
    """What purlcore.<function>() returns, read once; [] without purlcore or without the function."""
    if function not in _lists:
        core = native.purlcore()
        if core is None or not hasattr(core, function):
            return []
        _lists[function] = list(getattr(core, function)())
    return _lists[function]


def yarn_geometry():
    """[{name, label, unit, components, min, max, default, doc, is_color, is_integer, is_sign}] of material.yarn."""
    return _native_list("yarn_parameters")


def models():
    return list(tables().keys())


def model_label(model):
    """The model's name as an artist reads it (purlcore.material_model_labels)."""
    core = native.purlcore()
    labels = core.material_model_labels() if core is not None and hasattr(core, "material_model_labels") else {}
    return labels.get(model) or model.replace("_", " ").title()


def artist_parameters():
    """[{name, label, doc, ...}] of the bysdf model's artist controls (colour, sheen, softness,
    translucency); their docs state how each maps onto the physics parameters."""
    return _native_list("artist_parameters")


ARTIST_MODELS = {"bysdf"}  # models with artist controls


# Units as a label suffix; "R" is the yarn radius. Units Blender shows itself are left out.
_UNIT_SUFFIX = {"ply radii": "ply r", "deg": "°"}


def label(parameter):
    """The UI label: the native label (or the name), with its unit in brackets."""
    text = parameter.get("label") or parameter["name"].replace("_", " ").capitalize()
    unit = parameter.get("unit") or ""
    if unit and unit not in ("m", "rad"):
        text += " ({})".format(_UNIT_SUFFIX.get(unit, unit))
    return text


def parameters(model):
    return tables().get(model, [])


PLY_COLOR_PREFIX = "ply_color_"  # ply_color_count and ply_color_1..N: drawn together in the UI


def is_ply_color(parameter):
    return parameter["name"].startswith(PLY_COLOR_PREFIX)


def value_for_export(parameter, value):
    """A property value as the scene format wants it: a number or a list of numbers."""
    if parameter["components"] == 1:
        return float(value)
    return [float(v) for v in value]
