"""Yarn materials: the Purl settings stored on a Blender material, as the scene format's object."""
from .. import parameters


def yarn_material(material, problems):
    """{"model": ..., <parameter>: value, ...}; the native defaults when the material has none."""
    models = parameters.models()
    settings = getattr(material, "purl", None) if material is not None else None
    if settings is None:
        return {"model": models[0]} if models else {}
    model = settings.model
    if model not in models:
        problems.warning(material.name, "yarn model '{}' is not known to this version of Purl "
                       "(known: {}); the first is used".format(model, ", ".join(models)))
        model = models[0]
    values = getattr(settings, "params_" + model, None)
    result = {"model": model}
    if values is None:
        return result
    for parameter in parameters.parameters(model):
        result[parameter["name"]] = parameters.value_for_export(parameter, getattr(values, parameter["name"]))
    geometry = parameters.yarn_geometry() if model in parameters.YARN_GEOMETRY_MODELS else []
    if geometry:
        result["yarn"] = {p["name"]: parameters.value_for_export(p, getattr(settings.yarn_geometry, p["name"]))
                          for p in geometry}
    return result
