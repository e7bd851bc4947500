"""The bpy module route (docs/blender-addon.md, "The bpy module"): the extension installed once
stays installed, but every new process starts with factory preferences, so a script enables it
(before or after opening a file: the file keeps the engine's name) before it renders; without that
Blender says "Engine 'PURL' not available" and renders with EEVEE. Each step runs in a fresh
process of the same Python, as a script would."""
import os
import subprocess
import sys
import textwrap

import bpy
import pytest

ZIP = os.environ.get("PURL_EXTENSION_ZIP", "")
MODULE = "bl_ext.user_default.purl"

pytestmark = pytest.mark.skipif(bpy.app.version < (4, 2, 0) or bpy.app.binary_path.endswith("blender")
                                or not ZIP, reason="the bpy module with the extension zip (scripts/test_blender.sh bpy)")


def run(tmp_path, code):
    """Runs `code` in a new process of this Python (the bpy module) with its own user folders."""
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    process = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], env=env, capture_output=True,
                             text=True, timeout=300)
    assert process.returncode == 0, process.stdout[-2000:] + process.stderr[-2000:]
    return process.stdout + process.stderr


def test_saved_files_keep_the_purl_engine(tmp_path):
    blend = str(tmp_path / "scene.blend")
    run(tmp_path, """
        import bpy
        assert bpy.ops.extensions.package_install_files(filepath={zip!r}, repo="user_default",
                                                        enable_on_install=True) == {{"FINISHED"}}
        bpy.context.scene.render.engine = "PURL"
        bpy.ops.wm.save_as_mainfile(filepath={blend!r})
        """.format(zip=ZIP, blend=blend))
    # Not enabled: Blender says so and falls back (what the docs warn about).
    log = run(tmp_path, """
        import bpy
        bpy.ops.wm.open_mainfile(filepath={blend!r})
        print("engine:", bpy.context.scene.render.engine)
        """.format(blend=blend))
    assert "Engine 'PURL' not available" in log and "engine: PURL" not in log  # and renders use EEVEE
    # Enabled first (the documented order): the engine stays.
    log = run(tmp_path, """
        import bpy
        import addon_utils  # importable once bpy is
        addon_utils.enable({module!r}, default_set=True)
        bpy.ops.wm.open_mainfile(filepath={blend!r})
        print("engine:", bpy.context.scene.render.engine, bpy.context.scene.purl.samples)
        """.format(module=MODULE, blend=blend))
    assert "engine: PURL 64" in log and "not available" not in log
    # Enabled after opening: the file kept the name, so the scene is Purl's again.
    log = run(tmp_path, """
        import bpy
        import addon_utils  # importable once bpy is
        bpy.ops.wm.open_mainfile(filepath={blend!r})
        addon_utils.enable({module!r}, default_set=True)
        print("engine:", bpy.context.scene.render.engine)
        """.format(module=MODULE, blend=blend))
    assert "engine: PURL" in log
