"""Screenshots of Purl's Yarn material panel and render settings at Blender's default layout.

    xvfb-run -s "-screen 0 1920x2600x24" blender --factory-startup -p 0 0 1920 2600 \
        --python tools/panel_screenshots.py -- docs/images [preset]

The window is tall so every panel fits, but as wide as a 1920-pixel screen, so the Properties
editor has the width a new user sees. The add-on is the one in addon/ with purlcore from
$PURL_BUILD_DIR (a CMake build folder). The sub-panels are registered open. The Yarn panel shows a
preset (default: wool when presets/wool.json exists, else cotton) with a red yarn colour.
Writes yarn-panel.png and render-panel.png (the whole Properties editor) into the folder given;
docs/images holds them cropped to the panels:
    oiiotool yarn-panel.png --cut 333x1380+0+150 -o yarn-panel.png
    oiiotool render-panel.png --cut 333x460+0+0 -o render-panel.png
"""
import os
import sys
import tempfile

import addon_utils
import bpy

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ADDON = "purl"
RED = (0.6, 0.03, 0.03)


def _arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    out = os.path.abspath(argv[0] if argv else os.path.join(REPO, "docs", "images"))
    wool = os.path.join(REPO, "presets", "wool.json")
    preset = argv[1] if len(argv) > 1 else ("wool" if os.path.exists(wool) else "cotton")
    return out, preset


def _enable_addon():
    link_dir = tempfile.mkdtemp(prefix="purl_shots_")
    os.symlink(os.path.join(REPO, "addon"), os.path.join(link_dir, ADDON))
    sys.path.insert(0, link_dir)
    if addon_utils.enable(ADDON, default_set=True) is None:
        raise RuntimeError("the Purl add-on did not enable")
    return sys.modules[ADDON]


def _open_sub_panels(package):
    """Registers the Yarn panel's sub-panels open, so one screenshot shows them."""
    for cls in package.ui.classes:
        if "DEFAULT_CLOSED" in getattr(cls, "bl_options", set()):
            bpy.utils.unregister_class(cls)
            cls.bl_options = set(cls.bl_options) - {"DEFAULT_CLOSED"}
            bpy.utils.register_class(cls)


def _set_up_material(package, preset_name):
    scene = bpy.context.scene
    scene.render.engine = "PURL"
    material = bpy.data.objects["Cube"].active_material
    path = os.path.join(REPO, "presets", preset_name + ".json")
    for warning in package.presets.apply_preset(material, package.presets.read_preset(path)):
        print("panel_screenshots: preset warning:", warning)
    material.purl.artist.color = RED  # switches the yarn colour on
    scene.purl.use_denoise = True


def _properties_area(window):
    return max((a for a in window.screen.areas if a.type == "PROPERTIES"), key=lambda a: a.height)


def _show(context_name):
    _properties_area(bpy.context.window_manager.windows[0]).spaces[0].context = context_name


def _shoot(out, file_name):
    window = bpy.context.window_manager.windows[0]
    area = _properties_area(window)
    with bpy.context.temp_override(window=window, area=area):
        bpy.ops.screen.screenshot_area(filepath=os.path.join(out, file_name))
    print("panel_screenshots: {} ({} x {} px Properties editor)".format(file_name, area.width, area.height))


def main():
    out, preset = _arguments()
    os.makedirs(out, exist_ok=True)
    package = _enable_addon()
    _open_sub_panels(package)
    _set_up_material(package, preset)
    steps = [lambda: _shoot(out, "yarn-panel.png"), lambda: _show("RENDER"),
             lambda: _shoot(out, "render-panel.png")]

    def step():
        # A second between steps, so the editor has drawn what a screenshot shows.
        if steps:
            steps.pop(0)()
            return 1.0
        bpy.ops.wm.quit_blender()
        return None

    _show("MATERIAL")
    bpy.app.timers.register(step, first_interval=2.0)


main()
