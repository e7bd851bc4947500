"""Denoising a Purl render from Blender, in a child process.

The blender binary links jemalloc, and the Open Image Denoise library that PyPI's pyoidn installs
frees some of its memory with glibc's free: loaded into Blender it aborts the whole program
(measured: "double free or corruption" at oidnCommitDevice in Blender 3.4). purlcore refuses there,
and the add-on runs purlcore.denoise in a plain Python child instead, in every Blender (denoise_worker.py), with the passes
handed over as a .npz file (docs/denoising.md).
"""
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
WORKER = os.path.join(HERE, "denoise_worker.py")
GUIDES = ("Combined", "Denoising Albedo", "Denoising Normal")
_LIBRARY = os.path.join("oidn", "lib", "libOpenImageDenoise.so.2")


def _pyoidn_library():
    """The OIDN library of a pyoidn installed in Blender's own Python, if any."""
    try:
        spec = importlib.util.find_spec("pyoidn")
    except (ImportError, ValueError):
        return None
    if spec is None or not spec.submodule_search_locations:
        return None
    path = os.path.join(list(spec.submodule_search_locations)[0], _LIBRARY)
    return path if os.path.isfile(path) else None


def python_executable():
    """A Python 3 interpreter for the child: Blender's own (sys.executable), else python3 on PATH."""
    name = os.path.basename(sys.executable or "")
    if name.startswith("python"):
        return sys.executable
    return shutil.which("python3.11") or shutil.which("python3")


def child_environment(core):
    env = dict(os.environ)
    module_dir = os.path.dirname(os.path.abspath(core.__file__))
    env["PYTHONPATH"] = os.pathsep.join(p for p in (module_dir, env.get("PYTHONPATH", "")) if p)
    if not env.get("PURL_OIDN_LIBRARY") and _pyoidn_library():
        env["PURL_OIDN_LIBRARY"] = _pyoidn_library()
    return env


def denoise_passes(core, passes, cancelled=lambda: False, poll_seconds=0.05):
    """(passes with Combined denoised and "Noisy Image" added, None) or (None, why not)."""
    python = python_executable()
    if python is None:
        return None, "no Python interpreter found to run Open Image Denoise in"
    folder = tempfile.mkdtemp(prefix="purl_denoise_")
    try:
        source, target = os.path.join(folder, "in.npz"), os.path.join(folder, "out.npz")
        np.savez(source, **{name: passes[name] for name in GUIDES if name in passes})
        child = subprocess.Popen([python, WORKER, source, target], env=child_environment(core),
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        while child.poll() is None:
            if cancelled():
                child.kill()  # our own child, by its id
                child.wait()
                return None, "cancelled"
            time.sleep(poll_seconds)
        output = child.stdout.read().decode(errors="replace").strip()
        if child.returncode != 0 or not os.path.isfile(target):
            return None, output.splitlines()[-1] if output else "the denoiser exited with {}".format(child.returncode)
        result = dict(passes)
        with np.load(target) as denoised:
            result["Combined"] = denoised["Combined"]
            result["Noisy Image"] = denoised["Noisy Image"]
        return result, None
    finally:
        shutil.rmtree(folder, ignore_errors=True)
