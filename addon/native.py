"""Finds the `purlcore` native module without ever failing the add-on's registration.

Three places are tried, in order: a copy bundled inside the add-on (legacy zip), an installed
module (the extension's wheel, or a developer's PYTHONPATH) and a build folder named by the
PURL_BUILD_DIR environment variable (tests, development).
"""
import importlib
import os
import sys

_module = None
_error = None


def _import_bundled():
    # A legacy zip carries purlcore*.so beside this file; import it as a submodule.
    return importlib.import_module(__package__ + ".purlcore")


def _import_installed():
    return importlib.import_module("purlcore")


def _import_from_build_dir():
    build_dir = os.environ.get("PURL_BUILD_DIR", "")
    if not build_dir or not os.path.isdir(build_dir):
        raise ImportError("PURL_BUILD_DIR is not set to a folder")
    if build_dir not in sys.path:
        sys.path.append(build_dir)
    return importlib.import_module("purlcore")


def purlcore():
    """The purlcore module, or None when it cannot be loaded (see `load_error`)."""
    global _module, _error
    if _module is not None or _error is not None:
        return _module
    reasons = []
    here = os.path.dirname(__file__)
    bundled = any(name.startswith("purlcore") and name.endswith(".so") for name in os.listdir(here))
    attempts = ([_import_bundled] if bundled else []) + [_import_installed, _import_from_build_dir]
    for attempt in attempts:
        try:
            _module = attempt()
            return _module
        except ImportError as error:  # also covers a .so that fails to link
            reasons.append(str(error))
    _error = "the native module purlcore could not be loaded (" + "; ".join(reasons) + ")"
    return None


def load_error():
    """Why purlcore() returned None, or None when it loaded."""
    purlcore()
    return _error


def require():
    """purlcore, or a RuntimeError that says why it is missing."""
    module = purlcore()
    if module is None:
        raise RuntimeError(_error)
    return module
