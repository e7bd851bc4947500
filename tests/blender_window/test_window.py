"""The look-dev loop in a real window: Debian's Blender 3.4 under Xvfb imports a BCC file through
File > Import, switches the viewport to Rendered, edits a material colour, opens the Render and
Material tabs and renders F12 (window_session.py does it inside Blender). Fails on any Python
error (a draw function's traceback included), on a viewport that does not change with the colour
and on an F12 that does not show its passes as they finish. Screenshots, the log and the measured
times stay in $PURL_TEST_ARTIFACTS (default test-artifacts/window, not committed).

    python3 -m pytest -q -s tests/blender_window          (scripts/test_blender.sh window)
"""
import json
import os
import shutil
import subprocess
import tempfile

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
SHARED = os.environ.get("PURL_SHARED_DATA_DIR", os.path.join(REPO, "..", "shared", "data"))


def blank_blend(blender, path, env):
    """A saved empty start-up file: opening a file keeps the splash screen away."""
    subprocess.run([blender, "-b", "--factory-startup", "--python-expr",
                    "import bpy; bpy.ops.wm.save_as_mainfile(filepath={!r})".format(str(path))],
                   check=True, capture_output=True, timeout=120, env=env)


def knit_rows(path):
    """A stand-in BCC file when the shared glove is not there: 12 closed wavy rows, C0."""
    import struct
    rows = []
    for k in range(12):
        t = np.linspace(0.0, 2 * np.pi, 96, endpoint=False)
        rows.append(np.stack([3 * np.cos(t), 3 * np.sin(t), 0.25 * k + 0.08 * np.sin(12 * t)], axis=1))
    with open(path, "wb") as f:
        f.write(b"BCC\x44C0" + bytes([3, 2]) + struct.pack("<QQ", len(rows), sum(map(len, rows))) + bytes(40))
        for row in rows:
            f.write(struct.pack("<i", -len(row)) + row.astype("<f4").tobytes())
    return str(path)


def test_look_dev_loop_in_a_window(tmp_path):
    blender = shutil.which("blender")
    if blender is None or shutil.which("xvfb-run") is None:
        pytest.skip("needs Debian's blender and xvfb-run (apt-get install blender xvfb)")
    artifacts = os.environ.get("PURL_TEST_ARTIFACTS", os.path.join(REPO, "test-artifacts", "window"))
    shutil.rmtree(artifacts, ignore_errors=True)
    os.makedirs(artifacts)
    glove = os.path.join(SHARED, "glove.bcc")
    bcc = glove if os.path.exists(glove) else knit_rows(tmp_path / "rows.bcc")
    result_path = tmp_path / "result.json"
    # Blender's embedded Python finds its home from the python3 on PATH: Debian's, not a pyenv or
    # venv one that pytest may run from (its site-packages have no numpy for Blender).
    fbdir = tmp_path / "screen"
    fbdir.mkdir()
    env = dict(os.environ, PURL_WINDOW_RESULT=str(result_path), PURL_WINDOW_ARTIFACTS=artifacts,
               PURL_WINDOW_FBDIR=str(fbdir),
               PURL_WINDOW_BCC=bcc, BLENDER_USER_RESOURCES=tempfile.mkdtemp(prefix="purl_window_user_"),
               PATH=os.path.dirname(os.path.realpath(blender)) + os.pathsep + os.environ.get("PATH", ""))
    blank = tmp_path / "blank.blend"
    blank_blend(blender, blank, env)
    command = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24 -fbdir " + str(fbdir), blender, "--factory-startup", "--python-exit-code", "1", str(blank),
               "--python", os.path.join(HERE, "window_session.py")]
    log_path = os.path.join(artifacts, "blender.log")
    with open(log_path, "w") as log_file:  # streamed, so a stuck session can be looked at
        subprocess.run(command, env=env, stdout=log_file, stderr=subprocess.STDOUT, timeout=900)
    with open(log_path) as f:
        log = f.read()
    assert result_path.exists(), "the session wrote no result:\n" + log[-3000:]
    result = json.loads(result_path.read_text())
    with open(os.path.join(artifacts, "times.json"), "w") as f:
        json.dump({k: v for k, v in result.items() if k.endswith("seconds") or k.endswith("size")}, f, indent=1)
    print("\nwindow session ({}): {}".format(os.path.basename(bcc), json.dumps(
        {k: v for k, v in result.items() if k.endswith("seconds")}, indent=1)))
    assert not result["errors"], result["errors"]
    assert "Traceback" not in log, log[log.index("Traceback") - 200:][:3000]
    # The colour edit (ply colour -> blue) shows in the viewport image and on the screen.
    before, after = np.array(result["viewport_rgb_before"]), np.array(result["viewport_rgb_after"])
    assert result["viewport_yarn_share"] > 0.05, "the yarns should be in view"
    assert after[2] / max(after[0], 1e-6) > 1.5 * before[2] / max(before[0], 1e-6), (before, after)
    shot_before, shot_after = np.array(result["screenshot_rgb_before"]), np.array(result["screenshot_rgb_after"])
    assert shot_after[2] - shot_after[0] > shot_before[2] - shot_before[0] + 0.002, (shot_before, shot_after)
    # F12 with 4 samples shows its passes (1, 1, 2 samples) as they finish, the last when the render
    # ends; a pass in between is skipped when showing it would cost more than a quarter of the time
    # since the last (engine.py), which a loaded machine can make happen, so only the first and the
    # last are certain.
    passes = result["f12_pass_seconds"]
    assert len(passes) >= 2 and passes[-1] <= result["f12_seconds"], passes
    assert passes[0] < 0.7 * result["f12_seconds"], "the first pass shows long before the end"
