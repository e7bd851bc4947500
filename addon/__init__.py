"""Purl: yarn-level cloth rendering in Blender (legacy add-on on 3.x, extension on 4.2+).

Relative imports only: the package is installed under whatever name Blender gives it.
"""
bl_info = {
    "name": "Purl",
    "author": "Purl developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > Render Engine > Purl; File > Import > Yarn Curves (.bcc)",
    "description": "Renders yarn curves with implicit plies and fibers (multi-scale BYSDF)",
    "category": "Render",
}

from . import bcc_import, cycles_setup, engine, fit, presets, properties, scripting, ui  # noqa: E402  (bl_info first)

_modules = (properties, engine, presets, fit, scripting, cycles_setup, bcc_import, ui)


def register():
    for module in _modules:
        module.register()


def unregister():
    for module in reversed(_modules):
        module.unregister()
