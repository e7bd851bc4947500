"""Image error measures of the benchmark (pure numpy, plus FLIP from the PyPI flip-evaluator).

quality  relative MSE of a render against the same method's converged image. The converged
         image is the mean of two independent halves A and B; its own noise would add
         E[(A+B)/2 - truth]^2 = E[(A-B)^2] / 4 per pixel to the error, so that much is subtracted
         (same per-pixel weights), which keeps low errors from levelling off at the reference's
         noise floor.
accuracy RMSE (linear radiance) and mean FLIP (LDR FLIP on the sRGB-encoded, clipped images:
         what the PNG output shows) of a converged image against the converged explicit-ply image.
"""
import numpy as np

EPSILON = 1e-2  # relMSE denominators: (reference^2 + EPSILON), as in Rousselle et al. 2011


def relative_mse(image, reference_a, reference_b):
    reference = 0.5 * (reference_a + reference_b)
    weight = 1.0 / (reference * reference + EPSILON)
    raw = np.mean((image - reference) ** 2 * weight)
    reference_noise = np.mean((reference_a - reference_b) ** 2 * weight) / 4.0
    return float(max(raw - reference_noise, 1e-12)), float(reference_noise)


def rmse(image, reference):
    return float(np.sqrt(np.mean((image - reference) ** 2)))


def srgb(linear):
    x = np.clip(linear, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055).astype(np.float32)


def flip(image, reference):
    """Mean LDR FLIP, or None when flip-evaluator is not installed."""
    try:
        import flip_evaluator
    except ImportError:
        return None
    _, mean, _ = flip_evaluator.evaluate(srgb(reference), srgb(image), "LDR", inputsRGB=True, applyMagma=False)
    return float(mean)


def time_to_quality(points, target):
    """Seconds a method needs to reach relMSE `target`, from its measured (seconds, relMSE)
    points: log-log interpolation inside the measured range; outside it the Monte Carlo law
    relMSE ~ 1/time from the nearest point (flagged, as the second value)."""
    pts = sorted((t, e) for t, e in points if t > 0 and e > 0)
    if not pts:
        return None, False
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if (e0 - target) * (e1 - target) <= 0 and e0 != e1:
            a = (np.log(target) - np.log(e0)) / (np.log(e1) - np.log(e0))
            return float(np.exp(np.log(t0) + a * (np.log(t1) - np.log(t0)))), False
    # Outside: extrapolate from the closest end along the 1/time law.
    t, e = min(pts, key=lambda p: abs(np.log(p[1]) - np.log(target)))
    return float(t * e / target), True
