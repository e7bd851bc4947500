"""Meshes as diffuse occluders (base colour of their material) or holdouts, in world space."""
from dataclasses import dataclass

import numpy as np

from ..compat import uses_nodes
from .transforms import transform_points

DEFAULT_COLOR = (0.8, 0.8, 0.8)


@dataclass
class MeshTriangles:
    name: str
    vertices: np.ndarray   # float32 (V, 3), world space relative to `origin`
    triangles: np.ndarray  # int32 (T, 3)
    color: tuple
    holdout: bool
    origin: np.ndarray     # float64 (3,), world space

    def arrays(self):
        return {"vertices": self.vertices, "triangles": self.triangles}


def _output_surface_node(material):
    """The node linked to the active Material Output's Surface input, or None."""
    tree = material.node_tree if material is not None else None
    if tree is None:
        return None
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"]
    active = [n for n in outputs if n.is_active_output] or outputs
    if not active:
        return None
    surface = active[0].inputs.get("Surface")
    if surface is None or not surface.is_linked:
        return None
    return surface.links[0].from_node


def material_color_and_holdout(material):
    """(linear RGB, holdout) of a mesh material: a Principled or Diffuse BSDF's colour, a Holdout
    shader, or the viewport colour when the material has no nodes."""
    if material is None:
        return DEFAULT_COLOR, False
    node = _output_surface_node(material) if uses_nodes(material) else None
    if node is not None:
        if node.bl_idname == "ShaderNodeHoldout":
            return DEFAULT_COLOR, True
        for socket_name in ("Base Color", "Color"):
            socket = node.inputs.get(socket_name)
            if socket is not None and hasattr(socket, "default_value"):
                return tuple(float(c) for c in socket.default_value[:3]), False
    return tuple(float(c) for c in material.diffuse_color[:3]), False


def mesh_object(ob, matrix_world, holdout_object):
    """One MeshTriangles per material used by the evaluated mesh of `ob`."""
    try:
        mesh = ob.to_mesh()
    except RuntimeError:
        return []
    if mesh is None:
        return []
    try:
        mesh.calc_loop_triangles()
        n_vertices, n_triangles = len(mesh.vertices), len(mesh.loop_triangles)
        if n_vertices == 0 or n_triangles == 0:
            return []
        co = np.empty(n_vertices * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", co)
        triangles = np.empty(n_triangles * 3, dtype=np.int32)
        mesh.loop_triangles.foreach_get("vertices", triangles)
        material_index = np.empty(n_triangles, dtype=np.int32)
        mesh.loop_triangles.foreach_get("material_index", material_index)
    finally:
        ob.to_mesh_clear()
    vertices, origin = transform_points(co.reshape(-1, 3), matrix_world)
    triangles = triangles.reshape(-1, 3)
    result = []
    for index in np.unique(material_index):
        material = ob.material_slots[index].material if index < len(ob.material_slots) else None
        color, holdout = material_color_and_holdout(material)
        subset = triangles[material_index == index]
        name = ob.name if len(result) == 0 and len(np.unique(material_index)) == 1 else \
            "{} ({})".format(ob.name, material.name if material else index)
        result.append(MeshTriangles(name, vertices, subset, color, holdout or holdout_object, origin))
    return result
