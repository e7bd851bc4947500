"""Runs the Blender test suite with pytest inside Blender, with the Purl add-on enabled.

    blender -b --factory-startup --python-exit-code 1 --python tests/blender/run_tests.py -- [pytest args]
    /opt/purl-bpy/bin/python tests/blender/run_tests.py [pytest args]          (bpy module from PyPI)

How the add-on is loaded:
  PURL_EXTENSION_ZIP=dist/purl-<v>-extension.zip  installed as an extension (Blender 4.2+), wheel included;
  PURL_LEGACY_ZIP=dist/purl-<v>-legacy.zip        unpacked and enabled as the legacy add-on "purl";
  neither                                         addon/ from the tree as the legacy add-on "purl", with
                                                  purlcore from PURL_BUILD_DIR (a CMake build folder) if set.
The exit status is pytest's, so `--python-exit-code 1` (or the plain Python) reports failures.
"""
import os
import sys
import tempfile
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
ADDON_NAME = "purl"


def _pytest_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    # Blender's own arguments end up in sys.argv when no "--" is given; drop them.
    if "--" not in sys.argv and any(a.startswith("--python") for a in argv):
        argv = []
    return [HERE, "-p", "no:cacheprovider", "-q", "-rs"] + argv


def _isolate_user_folders():
    """Keeps the user's own Blender config and extensions out of the tests (set before bpy loads)."""
    if "PURL_TEST_KEEP_USER_RESOURCES" not in os.environ and "BLENDER_USER_RESOURCES" not in os.environ:
        os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="purl_blender_user_")


def _enable_legacy(zip_path):
    import addon_utils
    link_dir = tempfile.mkdtemp(prefix="purl_addon_")
    if zip_path:
        zipfile.ZipFile(zip_path).extractall(link_dir)
        if not os.path.isdir(os.path.join(link_dir, ADDON_NAME)):
            raise RuntimeError("{} holds no {}/ folder".format(zip_path, ADDON_NAME))
    else:
        os.symlink(os.path.join(REPO, "addon"), os.path.join(link_dir, ADDON_NAME))
    sys.path.insert(0, link_dir)
    module = addon_utils.enable(ADDON_NAME, default_set=True, handle_error=_raise)
    if module is None:
        raise RuntimeError("the add-on did not enable")
    return ADDON_NAME


def _enable_extension(zip_path):
    import bpy
    result = bpy.ops.extensions.package_install_files(filepath=os.path.abspath(zip_path),
                                                       repo="user_default", enable_on_install=True)
    if result != {"FINISHED"}:
        raise RuntimeError("installing {} as an extension failed: {}".format(zip_path, result))
    names = [name for name in bpy.context.preferences.addons.keys() if name.endswith("." + ADDON_NAME)]
    if not names:
        raise RuntimeError("the extension installed but is not enabled")
    return names[0]


def _raise(error):
    raise error


def main():
    _isolate_user_folders()
    import bpy
    import pytest

    extension_zip = os.environ.get("PURL_EXTENSION_ZIP", "")
    legacy_zip = os.environ.get("PURL_LEGACY_ZIP", "")
    package = _enable_extension(extension_zip) if extension_zip else _enable_legacy(legacy_zip)
    os.environ["PURL_ADDON_PACKAGE"] = package
    print("purl tests: Blender {}, add-on package {}".format(bpy.app.version_string, package), flush=True)
    return pytest.main(_pytest_args())


if __name__ == "__main__":
    status = main()
    sys.stdout.flush()
    sys.exit(int(status))
