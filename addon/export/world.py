"""The world: Background colour x strength, optionally an equirectangular Environment Texture."""
import os
import tempfile

import bpy

from ..compat import uses_nodes


def _linked_node(socket):
    return socket.links[0].from_node if socket.is_linked else None


def _world_output_surface(tree):
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld"]
    active = [n for n in outputs if n.is_active_output] or outputs
    return _linked_node(active[0].inputs["Surface"]) if active else None


def _image_path(image, problems, temp_dir):
    """A file the native module can read: the image's own file, or its packed bytes written out."""
    if image.packed_file is not None:
        name = bpy.path.basename(image.filepath) or (image.name + ".exr")
        path = os.path.join(temp_dir or tempfile.gettempdir(), "purl_" + bpy.path.clean_name(name))
        with open(path, "wb") as f:
            f.write(image.packed_file.data)
        return path
    path = bpy.path.abspath(image.filepath, library=image.library)
    if not os.path.isfile(path):
        problems.warning(image.name, "the environment image file {} does not exist".format(path))
        return None
    return os.path.normpath(path)


def _mapping_rotation_z(texture_node, problems):
    vector = texture_node.inputs.get("Vector")
    node = _linked_node(vector) if vector is not None else None
    if node is None:
        return 0.0
    if node.bl_idname != "ShaderNodeMapping":
        problems.warning("World", "only a Mapping node's Z rotation is used to orient the environment")
        return 0.0
    rotation = node.inputs.get("Rotation")
    return float(rotation.default_value[2]) if rotation is not None else 0.0


def export_world(world, problems, temp_dir=None):
    if world is None:
        return {"color": [0.0, 0.0, 0.0], "strength": 1.0}
    result = {"color": [float(c) for c in world.color[:3]], "strength": 1.0}
    if not uses_nodes(world):
        return result
    background = _world_output_surface(world.node_tree)
    if background is None:
        result["color"] = [0.0, 0.0, 0.0]
        return result
    if background.bl_idname != "ShaderNodeBackground":
        problems.warning(world.name, "the world surface is a {}, not a Background; Purl uses the "
                         "world colour instead".format(background.name))
        return result
    color, strength = background.inputs["Color"], background.inputs["Strength"]
    if strength.is_linked:
        problems.warning(world.name, "a linked Background strength is ignored (1 is used)")
    else:
        result["strength"] = float(strength.default_value)
    texture = _linked_node(color)
    if texture is None:
        result["color"] = [float(c) for c in color.default_value[:3]]
    elif texture.bl_idname == "ShaderNodeTexEnvironment" and texture.image is not None:
        if texture.projection != "EQUIRECTANGULAR":
            problems.warning(world.name, "only equirectangular environment textures are supported")
        colorspace = texture.image.colorspace_settings.name
        if not any(word in colorspace for word in ("Linear", "Non-Color", "Raw")):
            problems.warning(world.name, "the environment image '{}' is tagged {}; Purl reads its values "
                             "as linear (Cycles decodes them), so tag it linear or expect a different "
                             "brightness".format(texture.image.name, colorspace))
        path = _image_path(texture.image, problems, temp_dir)
        result["color"] = [1.0, 1.0, 1.0]
        if path is not None:
            result["texture"] = path
            result["rotation_z"] = _mapping_rotation_z(texture, problems)
    else:
        problems.warning(world.name, "the Background colour comes from a {} node, which Purl does "
                         "not evaluate; its default colour is used".format(texture.name))
        result["color"] = [float(c) for c in color.default_value[:3]]
    return result
