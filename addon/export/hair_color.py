"""The colour an artist gave a material for Cycles' hair shaders, as a yarn colour.

A Principled Hair BSDF stores its colour in one of three ways (parametrization): a colour, melanin
concentrations, or an absorption coefficient. The last two are turned into the colour they look
like with the inverse of the mapping Chiang et al. 2016 (section 4.2) give and Cycles uses:
    sigma_a = (ln(c) / f(beta))^2,  f(beta) = 5.969 - 0.215 b + 2.532 b^2 - 10.73 b^3 + 5.574 b^4 + 0.245 b^5
so c = exp(-sqrt(sigma_a) f(beta)) with beta the radial roughness; melanin m with redness r gives
sigma_a = q ((1 - r) (0.506, 0.841, 1.653) + r (0.343, 0.733, 1.924)), q = -ln(max(1 - m, 1e-4)),
plus the sigma_a of the tint colour. A plain Hair BSDF's Color is taken as it is.
"""
import math

HAIR_NODES = ("ShaderNodeBsdfHairPrincipled", "ShaderNodeBsdfHair")
EUMELANIN = (0.506, 0.841, 1.653)
PHEOMELANIN = (0.343, 0.733, 1.924)


def _roughness_factor(beta):
    return 5.969 - 0.215 * beta + 2.532 * beta ** 2 - 10.73 * beta ** 3 + 5.574 * beta ** 4 + 0.245 * beta ** 5


def sigma_from_color(color, beta):
    factor = _roughness_factor(beta)
    return [(math.log(max(c, 1e-4)) / factor) ** 2 for c in color]


def color_from_sigma(sigma, beta):
    factor = _roughness_factor(beta)
    return [math.exp(-math.sqrt(max(s, 0.0)) * factor) for s in sigma]


def melanin_sigma(melanin, redness):
    quantity = -math.log(max(1.0 - melanin, 1e-4))
    return [quantity * ((1.0 - redness) * e + redness * p) for e, p in zip(EUMELANIN, PHEOMELANIN)]


def _value(node, name, default):
    socket = node.inputs.get(name)
    if socket is None:
        return default
    value = socket.default_value
    return [float(v) for v in value[:3]] if hasattr(value, "__len__") else float(value)


def hair_node(material):
    """The first Principled Hair or Hair BSDF of the material's node tree, or None."""
    tree = getattr(material, "node_tree", None) if material is not None else None
    if tree is None:
        return None
    return next((n for n in tree.nodes if n.bl_idname in HAIR_NODES), None)


def hair_color(material):
    """(linear RGB in [0, 1], description) of the material's hair shader, or (None, "") without one."""
    node = hair_node(material)
    if node is None:
        return None, ""
    mode = getattr(node, "parametrization", "COLOR")
    beta = _value(node, "Radial Roughness", 0.3)
    if node.bl_idname == "ShaderNodeBsdfHair" or mode == "COLOR":
        color = _value(node, "Color", [0.8, 0.8, 0.8])
    elif mode == "MELANIN":
        sigma = melanin_sigma(_value(node, "Melanin", 0.8), _value(node, "Melanin Redness", 1.0))
        tint = sigma_from_color(_value(node, "Tint", [1.0, 1.0, 1.0]), beta)
        color = color_from_sigma([s + t for s, t in zip(sigma, tint)], beta)
    else:  # ABSORPTION
        color = color_from_sigma(_value(node, "Absorption Coefficient", [0.245531, 0.52, 1.365]), beta)
    return [min(max(c, 0.0), 1.0) for c in color], "{} ({})".format(node.name, mode.lower())
