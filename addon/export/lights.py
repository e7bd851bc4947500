"""Point, spot, sun and area lights with Cycles' radiometry (power in W, sun in W/m^2)."""
import math

import bpy
import numpy as np

from .transforms import split_scale


def _light_area(light, scale):
    """Blender's BKE_light_area: the area an unnormalized light's power is spread over."""
    if light.type == "AREA":
        size_x = light.size * scale[0]
        size_y = (light.size_y if light.shape in {"RECTANGLE", "ELLIPSE"} else light.size) * scale[1]
        area = size_x * size_y
        return area * (math.pi / 4.0) if light.shape in {"DISK", "ELLIPSE"} else area
    if light.type in {"POINT", "SPOT"}:
        radius = light.shadow_soft_size
        return 4.0 * math.pi * radius * radius if radius > 0.0 else 4.0
    half = light.angle / 2.0
    return math.pi * math.sin(half) ** 2 if half > 0.0 else 1.0


# Cycles 4.x emits an area light's power as radiance P / (pi A); 3.x (and Purl's scene format)
# as P / (4 A). Measured: the same plane is 4/pi brighter under Cycles 4.5 than under 3.4.
AREA_POWER_FACTOR = 4.0 / math.pi if bpy.app.version >= (4, 0, 0) else 1.0


def export_light(ob, matrix_world, problems):
    light = ob.data
    if light.type not in {"POINT", "SPOT", "SUN", "AREA"}:
        problems.warning(ob.name, "light type {} is not supported".format(light.type))
        return None
    matrix, scale = split_scale(matrix_world)
    color = np.array(light.color[:3], dtype=np.float64)
    if getattr(light, "use_temperature", False):  # Blender 4.5+
        color = color * np.array(light.temperature_color[:3])
    power = light.energy * 2.0 ** getattr(light, "exposure", 0.0)  # exposure: Blender 4.5+
    if not getattr(light, "normalize", True):
        power *= _light_area(light, scale)
    if getattr(light, "use_nodes", False):
        problems.warning(ob.name, "light nodes are ignored")
    result = {"type": light.type.lower(), "matrix_world": matrix,
              "color": [float(c) for c in color]}
    if light.type == "SUN":
        result.update(strength=float(power), angle=float(light.angle))
    else:
        result["power"] = float(power)
    if light.type in {"POINT", "SPOT"}:
        result["radius"] = float(light.shadow_soft_size)
    if light.type == "SPOT":
        result.update(spot_size=float(light.spot_size), spot_blend=float(light.spot_blend))
    if light.type == "AREA":
        result["power"] *= AREA_POWER_FACTOR
        # Cycles scales an area light's size by the object's scale; an unevenly scaled square
        # or disk becomes a rectangle or ellipse.
        shape = light.shape
        size_y = light.size_y if shape in {"RECTANGLE", "ELLIPSE"} else light.size
        if shape in {"SQUARE", "DISK"} and abs(scale[0] - scale[1]) > 1e-6 * max(scale[0], scale[1]):
            shape = "RECTANGLE" if shape == "SQUARE" else "ELLIPSE"
        result.update(shape=shape, size=float(light.size * scale[0]))
        if shape in {"RECTANGLE", "ELLIPSE"}:
            result["size_y"] = float(size_y * scale[1])
    return result
