"""Yarn materials: the Purl settings stored on a Blender material, as the scene format's object."""
from .. import parameters
from .hair_color import hair_color


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
    if model in parameters.ARTIST_MODELS:
        result.update(artist_values(material))
    geometry = parameters.yarn_geometry() if model in parameters.YARN_GEOMETRY_MODELS else []
    if geometry:
        result["yarn"] = {p["name"]: parameters.value_for_export(p, getattr(settings.yarn_geometry, p["name"]))
                          for p in geometry}
    return result


def yarn_color(material):
    """(colour or None, where it comes from): the Yarn Colour when it is on, else the colour of a
    Principled Hair (or Hair) BSDF set up for Cycles, else None (the material's own albedos)."""
    settings = material.purl
    if settings.use_color:
        return [float(c) for c in settings.artist.color], "Yarn Colour"
    return hair_color(material)


def artist_values(material):
    """The artist controls as the scene format's keys ("color" only when there is a colour)."""
    settings = material.purl
    values = {p["name"]: parameters.value_for_export(p, getattr(settings.artist, p["name"]))
              for p in parameters.artist_parameters() if p["name"] != "color"}
    color, _ = yarn_color(material)
    if color is not None:
        values["color"] = color
    return values
