"""Inside Blender: the job settings the Flamenco add-on would submit for the open file.

    blender -b file.blend --addons purl --python farm/flamenco/submit_settings.py -- \\
        job_type.json job.json out.json

job_type.json is the job type as `local_manager.js <script> job-type` prints it; job.json holds
{"name": ..., "settings": {...}} with what the artist typed in the submission panel. Settings the
artist left alone get their value the way the add-on gives it: an `eval` expression is evaluated
(eval(expr, {}, names) with the add-on's names: bpy, C, jobname, Path, abspath,
last_n_dir_parts, settings) when the setting is hidden from the panel, read-only, has an automatic
value toggle, or has no default; otherwise the default, or the type's zero. `blendfile` is the
open file unless given (the add-on gives the path of the copy it packed for the farm).
"""
import json
import os
import sys
from pathlib import Path

import bpy

_ZERO = {"string": "", "int32": 0, "float": 0.0, "bool": False}
_COERCE = {"string": str, "int32": int, "float": float, "bool": bool}


class _Settings:
    """`settings` in eval expressions: the values known so far, as attributes."""

    def __init__(self, values):
        self._values = values

    def __getattr__(self, key):
        try:
            return self._values[key]
        except KeyError:
            raise AttributeError(key) from None


def _last_n_dir_parts(n, filepath=None):
    folder = Path(bpy.path.abspath(filepath) if filepath else bpy.data.filepath).absolute().parent
    return Path(*folder.parts[-n:]) if n > 0 else Path()


def _evaluated(setting, given):
    """True when the add-on would fill this setting from its eval expression."""
    if not setting.get("eval") or setting["key"] in given:
        return False
    hidden = setting.get("visible", "visible") not in ("visible", "submission", True)
    automatic = bool(setting.get("evalInfo", {}).get("showLinkButton"))
    return hidden or automatic or setting.get("editable") is False or not setting.get("default")


def submitted_settings(job_type, name, given):
    values = {}
    for setting in job_type["settings"]:
        kind = setting["type"]
        if setting["key"] in given:
            values[setting["key"]] = given[setting["key"]]
        else:
            values[setting["key"]] = _COERCE[kind](setting["default"]) if "default" in setting else _ZERO[kind]
    names = {"bpy": bpy, "C": bpy.context, "jobname": name, "Path": Path,
             "abspath": lambda p: Path(bpy.path.abspath(str(p))).absolute(),
             "last_n_dir_parts": _last_n_dir_parts, "settings": _Settings(values)}
    for setting in job_type["settings"]:
        if _evaluated(setting, given):
            values[setting["key"]] = _COERCE[setting["type"]](eval(setting["eval"], {}, names))
    if not given.get("blendfile"):
        values["blendfile"] = bpy.data.filepath
    return values


def main():
    job_type_path, job_path, out_path = sys.argv[sys.argv.index("--") + 1:]
    with open(job_type_path) as f:
        job_type = json.load(f)
    with open(job_path) as f:
        job = json.load(f)
    name = job.get("name") or os.path.splitext(os.path.basename(bpy.data.filepath))[0]
    job = {"name": name, "type": job_type["name"],
           "settings": submitted_settings(job_type, name, job.get("settings", {}))}
    with open(out_path, "w") as f:
        json.dump(job, f, indent=2)


if __name__ == "__main__":
    main()
