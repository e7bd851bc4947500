"""The native material parameter declarations, read once from purlcore.

Everything that lists yarn parameters in the add-on (properties, panel, export, presets) reads
them from here, so the native declaration stays the only place they are written down.
"""
from . import native

_tables = None  # model name -> list of parameter dicts
_yarn_geometry = None  # the bysdf model's yarn geometry parameters (material.yarn)

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


def yarn_geometry():
    """[{name, unit, components, min, max, default, doc, is_color, is_integer}] of material.yarn."""
    global _yarn_geometry
    if _yarn_geometry is None:
        core = native.purlcore()
        if core is None or not hasattr(core, "yarn_parameters"):
            return []
        _yarn_geometry = list(core.yarn_parameters())
    return _yarn_geometry


def models():
    return list(tables().keys())


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
