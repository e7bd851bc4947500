"""Progressive rendering: one purlcore.RenderJob renders consecutive sample ranges (passes of 1, 1,
2, 4, ... samples), and their average is exactly the one-shot render of all the samples (the
image is a function of scene, seed and sample count). Used by F12 and the rendered viewport.
"""
import time

import numpy as np

POLL_SECONDS = 0.05


FIRST_PASS_ONLY = {"YarnID", "PlyIndex", "PlyUV"}  # sample 0's, as in a one-shot render


class Accumulator:
    """The running average of sample passes: Combined, the denoising guides and any other pass
    weighted by samples; Depth keeps the nearest hit; Normal the renormalised mean; YarnID,
    PlyIndex and PlyUV stay the first pass's."""

    def __init__(self):
        self.samples = 0
        self.passes = None
        self._normal_sum = None

    def add(self, passes, samples):
        if self.passes is None:
            self.passes = {name: np.array(pixels, dtype=np.float32) for name, pixels in passes.items()}
            self._normal_sum = self.passes["Normal"] * samples
            self.samples = samples
            return
        self.samples += samples
        for name, pixels in passes.items():
            if name not in FIRST_PASS_ONLY | {"Depth", "Normal"}:
                mean = self.passes[name]
                mean += (pixels - mean) * (samples / self.samples)
        np.minimum(self.passes["Depth"], passes["Depth"], out=self.passes["Depth"])
        self._normal_sum += passes["Normal"] * samples
        length = np.linalg.norm(self._normal_sum, axis=-1, keepdims=True)
        np.divide(self._normal_sum, length, out=self.passes["Normal"], where=length > 0)


class PassPlan:
    """Sample ranges (first, count): 1, 1, 2, 4, ... so the image has 1, 2, 4, 8 ... samples after
    each pass, each pass at most about `max_seconds` long (measured on the ones before)."""

    def __init__(self, total, max_seconds=2.0):
        self.total = int(total)
        self.max_seconds = max_seconds
        self.done = 0
        self._seconds_per_sample = None

    def next(self):
        """The next (first, count), or None when all samples are planned."""
        if self.done >= self.total:
            return None
        count = max(1, self.done)
        if self._seconds_per_sample:
            count = min(count, max(1, int(self.max_seconds / self._seconds_per_sample)))
        return self.done, min(count, self.total - self.done)

    def finished(self, count, seconds):
        self.done += count
        per_sample = seconds / max(count, 1)
        previous = self._seconds_per_sample
        self._seconds_per_sample = per_sample if previous is None else 0.5 * (previous + per_sample)


def sample_passes(total, max_seconds=2.0):
    """Yields (first sample, count) of each pass of a PassPlan, timing each pass as the time until
    the caller asks for the next."""
    plan = PassPlan(total, max_seconds)
    step = plan.next()
    while step is not None:
        started = time.monotonic()
        yield step
        plan.finished(step[1], time.monotonic() - started)
        step = plan.next()


class StatusLine:
    """Progress and status for RenderEngine.update_stats/update_progress. A background render
    (blender -b) prints every stats update, so there it updates at most once a second."""

    def __init__(self, engine, background, interval=1.0):
        self.engine = engine
        self.interval = interval if background else 0.0
        self._last = -1e9

    def show(self, text, progress=None, force=False):
        now = time.monotonic()
        if not force and now - self._last < self.interval:
            return
        self._last = now
        if progress is not None:
            self.engine.update_progress(min(max(progress, 0.0), 1.0))
        self.engine.update_stats("", text)


def far_field_status(core):
    """'tabulating the far field 12/32' while a table is built in this process, else ''."""
    done, total = core.far_field_progress()
    return "tabulating the far field {}/{}".format(done, total) if total else ""
