"""The rendered viewport: a worker thread renders the view progressively while Blender's UI thread
only hands it changes and draws the latest image.

Each (scene, view) is rendered as: coarse passes of 1 sample at 1/s of the region's size (s = 8,
4, 2, from the largest that keeps to COARSE_PIXELS), then full-size passes of 1, 1, 2, 4, ...
samples accumulated up to the viewport sample count. A scene change (geometry, materials, lights,
world, settings) builds a new purlcore.RenderJob; a view change keeps it (RenderJob.set_view).
Either cancels the pass under way, which stops within a pixel's work.
"""
import atexit
import shutil
import tempfile
import threading
import time
import traceback
import weakref
from dataclasses import dataclass

import bpy
import numpy as np

from . import progressive
from .export.problems import Problems
from .viewport_scene import SceneCache, scene_key, view_from_region

COARSE_PIXELS = 128 * 128   # largest first pass, in pixels
POLL_SECONDS = 0.02         # how often a pass under way checks for newer work
REDRAW_SECONDS = 0.05       # how often the UI thread looks for a new image
FULL_PASS_SECONDS = 1.0     # longest full-size pass before the image is shown again
ACTIVE = weakref.WeakSet()  # the open rendered viewports, for tests and diagnostics


@dataclass
class ViewImage:
    pixels: np.ndarray  # float32 (H, W, 4), premultiplied RGBA, rows bottom to top (as GPU textures)
    samples: int        # 0 for a coarse pass
    serial: int         # grows with every new image


def coarse_scales(width, height):
    """Downscale factors of the first passes: 8, 4, 2 ... down to 2, starting from the smallest
    power of two that keeps the pass within COARSE_PIXELS (none for small regions)."""
    scale = 1
    while (width // scale) * (height // scale) > COARSE_PIXELS:
        scale *= 2
    scales = []
    while scale > 1:
        scales.append(scale)
        scale //= 2
    return scales


class ViewportSession:
    """The worker thread and what it renders. Thread-safe: set_scene, set_view and stop come from
    the UI thread; `image` and `status` are read there."""

    def __init__(self, core, base_dir=""):
        self._core = core
        self._base_dir = base_dir
        self._cond = threading.Condition()
        self._scene = None    # (version, scene dict, arrays, samples, mode) or None
        self._view = None     # (version, camera, film)
        self._versions = [0, 0]
        self._finished = None  # the (scene, view) versions rendered to the end
        self._job = None
        self._stopped = False
        self.image = None
        self.status = "Purl | waiting for the scene"
        self.passes_started = 0  # for tests
        self.events = []  # (what, time.monotonic()) of the latest scene and view: build, first image ...
        self._thread = threading.Thread(target=self._run, name="Purl viewport", daemon=True)
        self._thread.start()

    # --- UI thread ---------------------------------------------------------------------------

    def set_scene(self, scene, arrays, samples, mode):
        """A new scene to render (None with a status message when there is nothing to render)."""
        self.events = [("scene", time.monotonic())]
        with self._cond:
            self._versions[0] += 1
            self._scene = (self._versions[0], scene, arrays, int(samples), mode)
            self._restart()

    def set_view(self, camera, film):
        """The view to render; the same view again changes nothing."""
        with self._cond:
            if self._view is not None and self._view[1:] == (camera, film):
                return False
            self._versions[1] += 1
            self._view = (self._versions[1], camera, film)
            self._event("view")
            self._restart()
            return True

    def stop(self, wait=0.0):
        with self._cond:
            self._stopped = True
            self._restart()
        self._thread.join(wait)

    @property
    def idle(self):
        """True when the current scene and view are rendered to the end (or failed)."""
        with self._cond:
            return self._finished == tuple(self._versions)

    def _restart(self):  # with the lock held
        if self._job is not None:
            self._job.cancel()  # the job stops within a pixel's work; the worker notices
        self._cond.notify_all()

    # --- worker thread -----------------------------------------------------------------------

    def _outdated(self, versions):
        return self._stopped or tuple(self._versions) != versions

    def _run(self):
        job, job_version = None, None
        while True:
            with self._cond:
                while not self._stopped and (self._scene is None or self._view is None
                                             or self._finished == tuple(self._versions)):
                    self._cond.wait()
                if self._stopped:
                    return
                versions = tuple(self._versions)
                (_, scene, arrays, samples, mode), (_, camera, film) = self._scene, self._view
            try:
                if scene is None:
                    job, job_version = None, None
                    self.image = None
                elif job_version != versions[0]:
                    job = None  # frees the old scene first
                    self.status = "Purl | building the scene"
                    self._event("build started")
                    job = self._core.RenderJob(dict(scene, camera=camera, film=film), arrays, self._base_dir,
                                               mode=mode)
                    job_version = versions[0]
                    self._event("built")
                if job is not None and not self._render(job, versions, camera, film, samples):
                    continue  # newer work came in
            except Exception as error:  # the thread must outlive any failure: show it, wait for the next change
                if not isinstance(error, (self._core.Error, RuntimeError, ValueError)):
                    traceback.print_exc()
                self.status = "Purl | {}".format(error)
                job, job_version = None, None
            with self._cond:
                if tuple(self._versions) == versions:
                    self._finished = versions

    def _render(self, job, versions, camera, film, samples):
        """Coarse passes, then full-size ones; False when newer work interrupted."""
        width, height = film["width"], film["height"]
        for scale in coarse_scales(width, height):
            job.set_view({"camera": camera, "film": dict(film, width=width // scale, height=height // scale)})
            if not self._pass(job, versions, 0, 1, 1):
                return False
            self._publish(job.passes()["Combined"], 0, versions)
        job.set_view({"camera": camera, "film": film})
        accumulated = progressive.Accumulator()
        start = time.monotonic()
        for first, count in progressive.sample_passes(samples, FULL_PASS_SECONDS):
            if not self._pass(job, versions, first, count, samples):
                return False
            accumulated.add(job.passes(), count)
            self._publish(accumulated.passes["Combined"], accumulated.samples, versions)
        self.status = "Purl | {} samples | {:.1f} s".format(accumulated.samples, time.monotonic() - start)
        return True

    def _pass(self, job, versions, first, count, samples):
        """Runs one pass; False (with the pass cancelled) when newer work came in."""
        with self._cond:
            if self._outdated(versions):
                return False
            self._job = job
        self.passes_started += 1
        job.start(spp=count, first_sample=first)
        try:
            while not job.wait(POLL_SECONDS):
                if self._outdated(versions):
                    job.cancel()
                else:
                    waiting = progressive.far_field_status(self._core)
                    self.status = "Purl | {}sample {} of {}".format(waiting + " | " if waiting else "",
                                                                   first + count, samples)
        finally:
            with self._cond:
                self._job = None
        if job.error:
            raise RuntimeError(job.error)
        return not job.cancelled and not self._outdated(versions)

    def _event(self, what):
        self.events.append((what, time.monotonic()))

    def _publish(self, combined, samples, versions):
        if self._outdated(versions):
            return
        self._event("image {}x{}, {} samples".format(combined.shape[1], combined.shape[0], samples))
        serial = self.image.serial + 1 if self.image is not None else 1
        self.image = ViewImage(np.ascontiguousarray(combined[::-1], dtype=np.float32), samples, serial)


class Viewport:
    """The rendered viewport of one RenderEngine: scene sync (view_update), drawing (view_draw)
    and a UI-thread timer that asks for a redraw when the worker has a new image."""

    def __init__(self, engine, core):
        self.engine = engine
        self.cache = SceneCache()
        self.temp_dir = tempfile.mkdtemp(prefix="purl_viewport_")
        self.session = ViewportSession(core)
        self._scene_key = None
        self._drawn = None       # serial of the image in the texture
        self._texture = None
        self._status = None
        bpy.app.timers.register(self._tick, first_interval=REDRAW_SECONDS)
        ACTIVE.add(self)

    def update(self, context, depsgraph):
        """view_update: re-export what changed; restart the render when the scene changed."""
        problems = Problems()
        changed = self.cache.sync(depsgraph, problems)
        exported = self.cache.scene(depsgraph, problems, self.temp_dir)
        settings = depsgraph.scene.purl
        exported.scene["render"]["spp"] = int(settings.preview_samples)
        # Never denoised here: OIDN cannot run inside Blender's process (addon/denoise.py).
        exported.scene["render"].pop("denoise", None)
        mode = settings.multiscale_mode.lower()
        # Auto waits for far-field tables (seconds, per material); near is the exact model
        # those tables average, so the viewport converges to the same look without the wait.
        mode = "near" if mode == "auto" else mode
        errors = problems.messages("ERROR")
        key = (scene_key(exported.scene), mode, tuple(errors))
        if changed or key != self._scene_key:
            self._scene_key = key
            if errors:
                self.session.set_scene(None, None, 0, mode)
                self.session.status = "Purl | " + "; ".join(errors)
            else:
                self.session.set_scene(exported.scene, exported.arrays, exported.scene["render"]["spp"], mode)
        self._set_view(context, depsgraph.scene)

    def _set_view(self, context, scene):
        view = view_from_region(context.region, context.region_data, scene.render.film_transparent)
        if view is None:
            self.session.status = "Purl | renders perspective views only (View > Perspective/Orthographic)"
            return
        self.session.set_view(*view)

    def draw(self, context, depsgraph):
        """view_draw: the latest image over the whole region, through Blender's display transform."""
        self._set_view(context, depsgraph.scene)
        image = self.session.image
        if image is None:
            return
        import gpu
        from gpu_extras.presets import draw_texture_2d
        if self._drawn != image.serial or self._texture is None:
            height, width = image.pixels.shape[:2]
            buffer = gpu.types.Buffer("FLOAT", image.pixels.size, image.pixels.ravel())
            self._texture = gpu.types.GPUTexture((width, height), format="RGBA16F", data=buffer)
            self._drawn = image.serial
        gpu.state.blend_set("ALPHA_PREMULT")
        self.engine.bind_display_space_shader(depsgraph.scene)
        draw_texture_2d(self._texture, (0, 0), context.region.width, context.region.height)
        self.engine.unbind_display_space_shader()
        gpu.state.blend_set("NONE")

    def _tick(self):
        """Timer on the UI thread: redraw for new images, show the status; stops with the engine."""
        try:
            self.engine.is_preview  # raises ReferenceError once Blender freed the engine
            image = self.session.image
            if image is not None and image.serial != self._drawn:
                self.engine.tag_redraw()
            if self.session.status != self._status:
                self._status = self.session.status
                self.engine.update_stats("", self._status)
        except ReferenceError:  # Blender freed the engine: the viewport is gone
            self.free()
            return None
        return REDRAW_SECONDS

    def free(self, wait=0.0):
        ACTIVE.discard(self)
        self.session.stop(wait)
        shutil.rmtree(self.temp_dir, ignore_errors=True)


@atexit.register
def stop_all(wait=5.0):
    """Stops every viewport's worker before Python shuts down: a worker still inside purlcore
    when the interpreter finalizes would abort Blender on quit."""
    for view in list(ACTIVE):
        view.free(wait)
