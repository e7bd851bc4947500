"""Panels shown when Purl is the render engine: render settings, yarn material, lights, world."""
import bpy

from . import native, parameters
from .compat import uses_nodes
from .engine import PurlRenderEngine
from .export.hair_color import hair_color
from .presets import PURL_MT_presets, PURL_OT_preset_save
from .properties import SIGN_SUFFIX

ENGINE = PurlRenderEngine.bl_idname


class PurlPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    COMPAT_ENGINES = {ENGINE}

    @classmethod
    def poll(cls, context):
        return context.engine == ENGINE


def _native_status(layout):
    error = native.load_error()
    if error:
        box = layout.box()
        box.alert = True
        box.label(text="Purl's native module is missing", icon="ERROR")
        box.label(text=error[:120])
        return False
    return True


class PURL_PT_render(PurlPanel, bpy.types.Panel):
    bl_label = "Purl"
    bl_context = "render"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        if _native_status(layout):
            layout.label(text="purlcore {}".format(getattr(native.purlcore(), "__version__", "?")))
        settings = context.scene.purl
        layout.prop(settings, "samples")
        layout.prop(settings, "preview_samples")
        row = layout.row(align=True)
        row.prop(settings, "seed")
        row.prop(settings, "use_animated_seed", text="", icon="TIME")
        layout.prop(settings, "max_depth")
        layout.prop(settings, "clamp")
        layout.prop(settings, "filter_glossy")
        layout.prop(settings, "use_denoise")
        layout.prop(settings, "multiscale_mode")
        layout.prop(settings, "ply_method")
        layout.prop(context.scene.render, "film_transparent")
        layout.prop(settings, "use_cycles_composite", text="Cycles Composite")  # fits the default width
        if settings.use_cycles_composite:
            layout.prop(settings, "cycles_samples")


class PURL_PT_material(PurlPanel, bpy.types.Panel):
    """The yarn in an artist's terms: preset, model, yarn colour, sheen, softness, translucency.
    The physics parameters are in the Advanced sub-panel (docs/artist-controls.md)."""
    bl_label = "Yarn"
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        return context.engine == ENGINE and getattr(context, "material", None) is not None

    def draw(self, context):
        layout = self.layout
        if not _native_status(layout):
            return
        material = context.material
        settings = material.purl
        row = layout.row(align=True)
        row.menu(PURL_MT_presets.bl_idname, text=settings.preset_label or "Presets", icon="PRESET")
        row.operator(PURL_OT_preset_save.bl_idname, text="", icon="ADD")
        if settings.model == "bysdf":
            row.operator("purl.fit_to_image", text="", icon="IMAGE_DATA")  # addon/fit.py
        layout.use_property_split = True
        layout.prop(settings, "model_choice")
        values = getattr(settings, "params_" + settings.model, None)
        if values is None:
            layout.label(text="Unknown model '{}'".format(settings.model), icon="ERROR")
            return
        if settings.model in parameters.ARTIST_MODELS:
            _draw_artist_controls(layout, material)
        else:
            column = layout.column()
            for parameter in parameters.parameters(settings.model):
                if not parameters.is_ply_color(parameter):
                    column.prop(values, parameter["name"])
        layout.prop(settings, "color_attribute", icon="GROUP_VCOL")
        # Same settings in Cycles through the OSL shader (cycles_setup.py, docs/osl.md).
        layout.operator("purl.setup_cycles", icon="NODE_MATERIAL")


def _draw_artist_controls(layout, material):
    settings = material.purl
    row = layout.row(heading="Yarn Colour")
    row.prop(settings, "use_color", text="")
    sub = row.row()
    sub.active = settings.use_color
    sub.prop(settings.artist, "color", text="")
    if not settings.use_color:
        color, source = hair_color(material)
        if color is not None:
            layout.label(text="Colour from " + source, icon="INFO")
    for parameter in parameters.artist_parameters():
        if parameter["name"] != "color":
            layout.prop(settings.artist, parameter["name"])


def _draw_parameters(layout, values, declarations):
    """Physics parameters with the label inside each field, where the whole width leaves room for
    a label and its unit; a sign (is_sign) as a Left/Right choice, a colour beside its label."""
    column = layout.column(align=False)
    for parameter in declarations:
        name = parameter["name"]
        if parameter.get("is_sign") or parameter.get("is_color"):
            row = column.split(factor=0.5)
            row.label(text=parameters.label(parameter))
            if parameter.get("is_sign"):
                row.row(align=True).prop(values, name + SIGN_SUFFIX, expand=True)
            else:
                row.prop(values, name, text="")
        else:
            column.prop(values, name)


COUNT = parameters.PLY_COLOR_PREFIX + "count"


class YarnSubPanel(PurlPanel):
    """A closed sub-panel of the Yarn panel."""
    bl_context = "material"
    bl_parent_id = "PURL_PT_material"
    bl_options = {"DEFAULT_CLOSED"}


class PURL_PT_material_plies(YarnSubPanel, bpy.types.Panel):
    bl_label = "Ply Colours"

    @classmethod
    def poll(cls, context):
        if not PURL_PT_material.poll(context):
            return False
        model = context.material.purl.model
        return any(p["name"] == COUNT for p in parameters.parameters(model))

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.material.purl
        values = getattr(settings, "params_" + settings.model)
        layout.prop(values, COUNT)
        names = {p["name"] for p in parameters.parameters(settings.model)}
        grid = layout.grid_flow(columns=3, even_columns=True, align=True)
        for index in range(1, int(getattr(values, COUNT)) + 1):
            name = parameters.PLY_COLOR_PREFIX + str(index)
            if name in names:
                grid.prop(values, name, text="")


class PURL_PT_material_geometry(YarnSubPanel, bpy.types.Panel):
    bl_label = "Yarn Geometry"

    @classmethod
    def poll(cls, context):
        return (PURL_PT_material.poll(context) and context.material.purl.model in parameters.YARN_GEOMETRY_MODELS
                and bool(parameters.yarn_geometry()))

    def draw(self, context):
        _draw_parameters(self.layout, context.material.purl.yarn_geometry, parameters.yarn_geometry())


class PURL_PT_material_advanced(YarnSubPanel, bpy.types.Panel):
    """The BYSDF's physics parameters (docs/parameters.md); the artist controls act on top."""
    bl_label = "Advanced"

    @classmethod
    def poll(cls, context):
        return PURL_PT_material.poll(context) and context.material.purl.model in parameters.ARTIST_MODELS

    def draw(self, context):
        settings = context.material.purl
        _draw_parameters(self.layout, getattr(settings, "params_" + settings.model),
                         [p for p in parameters.parameters(settings.model) if not parameters.is_ply_color(p)])


class PURL_PT_light(PurlPanel, bpy.types.Panel):
    bl_label = "Light"
    bl_context = "data"

    @classmethod
    def poll(cls, context):
        return context.engine == ENGINE and getattr(context, "light", None) is not None

    def draw(self, context):
        layout = self.layout
        light = context.light
        layout.row().prop(light, "type", expand=True)
        layout.use_property_split = True
        layout.prop(light, "color")
        layout.prop(light, "energy", text="Strength" if light.type == "SUN" else "Power")
        for name in ("exposure", "normalize"):  # Blender 4.5+
            if hasattr(light, name):
                layout.prop(light, name)
        if light.type in {"POINT", "SPOT"}:
            layout.prop(light, "shadow_soft_size", text="Radius")
        if light.type == "SPOT":
            layout.prop(light, "spot_size", text="Spot Size")
            layout.prop(light, "spot_blend", text="Blend")
        elif light.type == "SUN":
            layout.prop(light, "angle")
        elif light.type == "AREA":
            layout.prop(light, "shape")
            if light.shape in {"RECTANGLE", "ELLIPSE"}:
                layout.prop(light, "size", text="Size X")
                layout.prop(light, "size_y", text="Y")
            else:
                layout.prop(light, "size")


class PURL_PT_world(PurlPanel, bpy.types.Panel):
    bl_label = "World"
    bl_context = "world"

    @classmethod
    def poll(cls, context):
        return context.engine == ENGINE and context.scene.world is not None

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        world = context.scene.world
        tree = world.node_tree if uses_nodes(world) else None
        background = None
        if tree is not None:
            background = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeBackground"), None)
        if background is None:
            layout.prop(world, "color")
            return
        for socket in (background.inputs["Color"], background.inputs["Strength"]):
            if socket.is_linked:
                layout.label(text="{}: from {}".format(socket.name, socket.links[0].from_node.name))
            else:
                layout.prop(socket, "default_value", text=socket.name)


classes = (PURL_PT_render, PURL_PT_material, PURL_PT_material_plies, PURL_PT_material_geometry,
           PURL_PT_material_advanced, PURL_PT_light, PURL_PT_world)

# Blender's own panels that make sense for Purl: output, camera, object data, hair particles,
# physics (cloth simulations drive yarns). Light panels are left out: PURL_PT_light shows what
# Purl renders.
_BUILTIN_PANEL_PREFIXES = (
    "RENDER_PT_format", "RENDER_PT_frame_range", "RENDER_PT_output", "RENDER_PT_color_management",
    "RENDER_PT_stamp", "RENDER_PT_post_processing", "RENDER_PT_time_stretching", "RENDER_PT_encoding",
    "VIEWLAYER_PT_layer", "CAMERA_PT_", "DATA_PT_camera", "DATA_PT_lens", "DATA_PT_context_",
    "DATA_PT_custom_props", "DATA_PT_CURVES_attributes", "DATA_PT_curves_surface",
    "DATA_PT_mesh_attributes", "DATA_PT_vertex_groups", "DATA_PT_shape_keys", "DATA_PT_uv_texture",
    "DATA_PT_customdata", "DATA_PT_texture_space", "PARTICLE_", "PHYSICS_", "OBJECT_PT_",
    "MATERIAL_PT_custom_props", "MATERIAL_PT_preview", "EEVEE_MATERIAL_PT_context_material", "WORLD_PT_context_world",
    "WORLD_PT_custom_props",
)
_BUILTIN_PANEL_EXCLUDED = ("_dof", "_passes")  # depth of field and other engines' passes
_patched_panels = []


def _compatible_builtin_panels():
    for name in dir(bpy.types):
        if not name.startswith(_BUILTIN_PANEL_PREFIXES) or any(x in name for x in _BUILTIN_PANEL_EXCLUDED):
            continue
        cls = getattr(bpy.types, name, None)
        engines = getattr(cls, "COMPAT_ENGINES", None)
        if isinstance(engines, set) and ENGINE not in engines:
            yield cls


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    for panel in _compatible_builtin_panels():
        panel.COMPAT_ENGINES.add(ENGINE)
        _patched_panels.append(panel)


def unregister():
    for panel in _patched_panels:
        panel.COMPAT_ENGINES.discard(ENGINE)
    _patched_panels.clear()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
