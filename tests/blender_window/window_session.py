"""Runs inside Blender 3.4 with a window (under Xvfb), driven by a modal operator's timer as a user would work:
File > Import the BCC file, Rendered shading, a material colour edit, the Render and Material
tabs, F12. Writes what it measured to $PURL_WINDOW_RESULT (JSON) and screenshots to
$PURL_WINDOW_ARTIFACTS, then quits. tests/blender_window/test_window.py starts it and checks.

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup blank.blend --python window_session.py
"""
import json
import os
import struct
import sys
import time
import traceback
import zlib

import bpy
import numpy as np
from mathutils import Vector

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "blender"))
import run_tests  # noqa: E402  (enables the add-on the way the headless suite does)

RESULT = os.environ["PURL_WINDOW_RESULT"]
ARTIFACTS = os.environ["PURL_WINDOW_ARTIFACTS"]
BCC = os.environ["PURL_WINDOW_BCC"]
FBDIR = os.environ["PURL_WINDOW_FBDIR"]
TIMEOUT = float(os.environ.get("PURL_WINDOW_STEP_TIMEOUT", "180"))
WATCHDOG = float(os.environ.get("PURL_WINDOW_WATCHDOG", "600"))  # the whole session, then a hard exit
START = time.monotonic()
result = {"steps": [], "errors": []}


def log(message):
    print("[window {:6.2f}] {}".format(time.monotonic() - START, message), flush=True)


def area(kind):
    window = bpy.context.window_manager.windows[0]
    return window, next(a for a in window.screen.areas if a.type == kind)


def read_screen():
    """The X screen as uint8 (H, W, 3), rows top to bottom, from the frame buffer file Xvfb keeps
    in $PURL_WINDOW_FBDIR (XWD, 32 bits a pixel, BGRX). Read outside Blender: Blender refuses its
    screenshot operator while any render or preview job runs."""
    with open(os.path.join(FBDIR, "Xvfb_screen0"), "rb") as f:
        data = f.read()
    fields = struct.unpack(">25I", data[:100])
    header_size, width, height, bits, bytes_per_line, colours = (fields[0], fields[4], fields[5], fields[11],
                                                                 fields[12], fields[19])
    assert bits == 32, "Xvfb depth 24 keeps 32 bits a pixel"
    start = header_size + 12 * colours
    pixels = np.frombuffer(data, dtype=np.uint8, count=bytes_per_line * height, offset=start)
    return pixels.reshape(height, bytes_per_line)[:, :4 * width].reshape(height, width, 4)[..., 2::-1]


def write_png(path, rgb):
    rows = b"".join(b"\x00" + row.tobytes() for row in np.ascontiguousarray(rgb, dtype=np.uint8))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    header = struct.pack(">IIBBBBB", rgb.shape[1], rgb.shape[0], 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows, 6))
                + chunk(b"IEND", b""))


def screenshot(name):
    """Saves the screen as ARTIFACTS/name.png; returns the pixels (H, W, 3)."""
    screen = read_screen()
    path = os.path.join(ARTIFACTS, name + ".png")
    write_png(path, screen)
    result.setdefault("screenshots", []).append(path)
    return screen


def region_pixels(screen, kind="VIEW_3D"):
    """Mean RGB (0..1) of an editor's main region in a screenshot."""
    _, found = area(kind)
    region = next(r for r in found.regions if r.type == "WINDOW")
    top = screen.shape[0] - (region.y + region.height)  # Blender counts rows from the bottom
    crop = screen[top:top + region.height, region.x:region.x + region.width]
    return (crop.reshape(-1, 3).mean(axis=0) / 255.0).tolist()


def idle():
    """No render or preview job runs: Blender refuses operators while one does."""
    return not any(bpy.app.is_job_running(kind) for kind in ("RENDER", "RENDER_PREVIEW"))


def quit_when_idle():
    """Quits once no job runs, without Blender's own shutdown: with the write flag stuck (see
    WindowSessionOperator) every add-on's unregister would fail on the way out."""
    if not idle() and time.monotonic() - START - result["seconds"] < 60:
        return 0.25
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


class Session:
    """The steps, each a generator that yields seconds to wait; runs from one UI timer."""

    def __init__(self):
        self.steps = self.run()
        self.viewport_module = None

    def tick(self):
        try:
            if time.monotonic() - START > WATCHDOG:
                raise TimeoutError("the session took more than {:.0f} s".format(WATCHDOG))
            return next(self.steps)
        except StopIteration:
            self.finish()
        except Exception:
            result["errors"].append(traceback.format_exc())
            traceback.print_exc()
            self.finish()
        return None

    def finish(self):
        result["seconds"] = time.monotonic() - START
        with open(RESULT, "w") as f:
            json.dump(result, f, indent=1)

    def viewport(self):
        views = list(self.viewport_module.ACTIVE)
        return views[0].session if views else None

    def wait_for(self, what, condition, every=0.01):
        started = time.monotonic()
        while not condition():
            if time.monotonic() - started > TIMEOUT:
                raise TimeoutError("waited {:.0f} s for {}".format(TIMEOUT, what))
            yield every
        return time.monotonic() - started

    def run(self):
        package = run_tests._enable_legacy(os.environ.get("PURL_LEGACY_ZIP", ""))
        self.viewport_module = __import__(package + ".viewport", fromlist=["ACTIVE"])
        engine_module = __import__(package + ".engine", fromlist=["PurlRenderEngine"])
        scene = bpy.context.scene
        scene.render.engine = "PURL"
        scene.render.resolution_x, scene.render.resolution_y = 256, 256  # F12 kept short: the suite runs in CI
        scene.purl.samples = 4
        # Near field: F12 shows its passes from the start. Auto would first tabulate the far field
        # (about 6 s for the glove on an idle machine since it carries the traced ply crossing),
        # which bench/lookdev.py and docs/blender-addon.md report.
        scene.purl.multiscale_mode = "NEAR"
        scene.purl.preview_samples = 16
        yield 0.5

        # File > Import > Yarn Curves (.bcc), as the menu's operator runs it.
        window, view3d = area("VIEW_3D")
        for ob in [o for o in scene.objects if o.type == "MESH"]:
            bpy.data.objects.remove(ob)
        started = time.monotonic()
        with bpy.context.temp_override(window=window, area=view3d):
            assert bpy.ops.purl.import_bcc(filepath=BCC) == {"FINISHED"}
        yarn = bpy.context.active_object
        result["import_seconds"] = time.monotonic() - started
        log("imported {} in {:.2f} s".format(yarn.name, result["import_seconds"]))
        # Frame it: the camera looks at the yarns from the front, a sun and a grey world light them.
        size = max(yarn.dimensions)
        centre = sum((yarn.matrix_world @ Vector(corner) for corner in yarn.bound_box), Vector()) / 8.0
        scene.camera.location = centre + Vector((0.0, -1.6 * size, 0.3 * size))
        scene.camera.rotation_euler = (1.39, 0.0, 0.0)
        light = next(o for o in scene.objects if o.type == "LIGHT")
        light.data.type = "SUN"
        light.data.energy = 3.0
        light.rotation_euler = (0.7, 0.2, 0.4)
        scene.world.color = (0.05, 0.05, 0.06)
        settings = yarn.active_material.purl.params_bysdf  # a light grey yarn, so colour shows
        settings.body_reflection_albedo, settings.body_transmission_albedo = (0.3, 0.3, 0.3), (0.6, 0.6, 0.6)
        space = view3d.spaces.active
        space.region_3d.view_perspective = "CAMERA"
        space.overlay.show_overlays = False  # software GL under load: keep Blender's own drawing light
        yield 0.5

        # Rendered shading.
        started = time.monotonic()
        space.shading.type = "RENDERED"
        yield from self.wait_for("the viewport engine", lambda: self.viewport() is not None)
        session = self.viewport()
        yield from self.wait_for("the first image", lambda: session.image is not None)
        result["first_image_seconds"] = time.monotonic() - started
        result["first_image_size"] = list(session.image.pixels.shape[:2])
        result["first_image_events"] = [(what, at - started) for what, at in session.events]
        yield from self.wait_for("the first full-size image", lambda: session.image.samples >= 1)
        result["first_full_image_seconds"] = time.monotonic() - started
        yield from self.wait_for("2 samples", lambda: session.image.samples >= 2)
        log("viewport: first image {:.2f} s, first full-size {:.2f} s".format(
            result["first_image_seconds"], result["first_full_image_seconds"]))
        yield 0.3
        before_image = session.image.pixels.copy()
        before_shot = region_pixels(screenshot("1_viewport_rendered"))

        # A material colour edit restarts the render with the new colour.
        material = yarn.active_material
        started = time.monotonic()
        old = session.image
        material.purl.params_bysdf.ply_color_1 = (0.15, 0.35, 1.0)
        yield from self.wait_for("the new colour", lambda: session.image is not old and session.image is not None)
        result["restart_seconds"] = time.monotonic() - started
        result["restart_events"] = [(what, at - started) for what, at in session.events]
        yield from self.wait_for("2 samples of the new colour", lambda: session.image.samples >= 2)
        yield 0.3
        after_image = session.image.pixels
        after_shot = region_pixels(screenshot("2_viewport_blue"))
        # Yarn pixels: those that differ from the world colour.
        covered = np.abs(before_image[..., :3] - np.array(scene.world.color)).max(axis=-1) > 0.02
        result["viewport_yarn_share"] = float(covered.mean())
        result["viewport_rgb_before"] = before_image[covered][:, :3].mean(axis=0).tolist()
        result["viewport_rgb_after"] = after_image[covered][:, :3].mean(axis=0).tolist()
        result["screenshot_rgb_before"], result["screenshot_rgb_after"] = before_shot, after_shot
        log("colour edit: new image after {:.2f} s".format(result["restart_seconds"]))

        # A camera move restarts too (the view, no rebuild).
        old = session.image
        started = time.monotonic()
        scene.camera.location.x += 0.05 * size
        yield from self.wait_for("the moved view", lambda: session.image is not old)
        result["camera_restart_seconds"] = time.monotonic() - started
        result["camera_restart_events"] = [(what, at - started) for what, at in session.events]

        # The Render and Material tabs draw without Python errors.
        _, properties = area("PROPERTIES")
        for tab in ("RENDER", "MATERIAL"):
            properties.spaces.active.context = tab
            properties.tag_redraw()
            started = time.monotonic()
            yield 1.0
            yield from self.wait_for("the material preview", idle)
            result["tab_{}_seconds".format(tab.lower())] = time.monotonic() - started
            screenshot("3_tab_" + tab.lower())
        # F12: sample passes show as they finish.
        writes = []
        original = engine_module.PurlRenderEngine._write_result

        def recording(engine, *args, **kwargs):
            writes.append(time.monotonic() - started)
            return original(engine, *args, **kwargs)

        engine_module.PurlRenderEngine._write_result = recording
        space.shading.type = "SOLID"
        # Wait for preview jobs and the viewport's worker, and ask again if Blender refuses,
        # printing every Python thread's stack the first time (see WindowSessionOperator).
        for attempt in range(40):
            yield from self.wait_for("no render or preview job", idle)
            yield from self.wait_for("the viewport to stop", lambda: self.viewport() is None or self.viewport().idle)
            started = time.monotonic()
            try:
                bpy.ops.render.render("INVOKE_DEFAULT")
                break
            except RuntimeError as error:
                if "can't modify blend data" not in str(error) or attempt == 39:
                    raise
                if attempt == 0:  # what holds Blender in its drawing/rendering state
                    for thread_id, frame in sys._current_frames().items():
                        log("thread {}:\n{}".format(thread_id, "".join(traceback.format_stack(frame))))
                log("F12 refused; asking again")
                yield 0.25
        yield from self.wait_for("F12's second pass", lambda: len(writes) >= 2)
        screenshot("4_f12_in_progress")
        yield from self.wait_for("F12", lambda: not bpy.app.is_job_running("RENDER"))
        result["f12_seconds"] = time.monotonic() - started
        result["f12_pass_seconds"] = writes
        engine_module.PurlRenderEngine._write_result = original
        yield 0.5
        screenshot("5_f12_result")
        log("F12: {} passes shown, done in {:.2f} s".format(len(writes), result["f12_seconds"]))


class WindowSessionOperator(bpy.types.Operator):
    """Runs the session's steps from window timer events. A modal operator, not bpy.app.timers:
    Blender 3.4 keeps one global "Python may not write" flag, saved and restored around each
    Python callback; a render callback on a job thread (the material preview, F12) interleaved
    with a draw callback on the UI thread can leave it set for good, after which bpy.ops called
    from a timer fails ("can't modify blend data in this state"). Operator callbacks always
    run with writes allowed."""
    bl_idname = "purl_window_test.session"
    bl_label = "Purl window session"

    def invoke(self, context, event):
        self.session = Session()
        self.finished = False
        self.next_step = time.monotonic()
        self.timer = context.window_manager.event_timer_add(0.01, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type != "TIMER" or time.monotonic() < self.next_step:
            return {"PASS_THROUGH"}
        delay = self.session.tick() if not self.finished else None
        if delay is None:  # the session has ended: quit Blender
            self.finished = True
            delay = quit_when_idle()
        self.next_step = time.monotonic() + delay
        return {"PASS_THROUGH"}


def start_session():
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window):
        bpy.ops.purl_window_test.session("INVOKE_DEFAULT")


def main():
    os.makedirs(ARTIFACTS, exist_ok=True)
    bpy.utils.register_class(WindowSessionOperator)
    bpy.app.timers.register(start_session, first_interval=1.0)


main()
