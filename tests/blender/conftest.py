"""Shared fixtures for the Blender suite: the add-on's package, purlcore, an empty scene per test."""
import importlib
import os
import sys

import bpy
import pytest

from builders import add_camera, compat

if "PURL_ADDON_PACKAGE" not in os.environ:
    sys.exit("run these tests through tests/blender/run_tests.py (it enables the add-on)")


@pytest.fixture(scope="session")
def purl():
    """The add-on package, whatever name Blender installed it under."""
    return importlib.import_module(os.environ["PURL_ADDON_PACKAGE"])


@pytest.fixture(scope="session")
def core(purl):
    """purlcore; tests that need it skip with the reason when it is not built, or fail when
    PURL_REQUIRE_NATIVE is set (CI, scripts/test_blender.sh), so a broken build is never silent."""
    native = importlib.import_module(purl.__name__ + ".native")
    module = native.purlcore()
    if module is None:
        if os.environ.get("PURL_REQUIRE_NATIVE"):
            pytest.fail(native.load_error())
        pytest.skip(native.load_error())
    return module


_DATA = ("objects", "meshes", "curves", "hair_curves", "lights", "cameras", "materials",
         "particles", "images", "worlds", "node_groups")


@pytest.fixture
def scene():
    """An empty scene rendered by Purl at a small size, with a camera looking at the origin."""
    for collection_name in _DATA:
        collection = getattr(bpy.data, collection_name, None)
        if collection is not None:
            for block in list(collection):
                collection.remove(block)
    scene = bpy.context.scene
    for prop in scene.purl.bl_rna.properties:  # settings a previous test changed (composite mode...)
        if prop.identifier != "rna_type":
            scene.purl.property_unset(prop.identifier)
    scene.render.engine = "PURL"
    scene.render.resolution_x, scene.render.resolution_y = 64, 48
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    scene.render.film_transparent = False
    compat.set_image_format(scene.render.image_settings, "PNG")
    scene.purl.samples = 4
    scene.world = bpy.data.worlds.new("World")
    add_camera(scene, location=(0.0, -4.0, 0.0), rotation=(1.5707963, 0.0, 0.0))
    return scene
