// How finely the explicit references (reference/explicit_models.h) sample their plies and
// fibers, and how much memory they may take: plain data, read from the scene's render.explicit.
#pragma once

namespace purl {

struct ExplicitOptions {
    float ply_tolerance = 5e-3f;    // ply radii: bound on a ply curve's distance from its helix
    float fiber_tolerance = 0.05f;  // fiber radii: the same for fibers
    // The centre-line curvature the knot step is planned for: the one this share of the yarn's
    // length stays below (1 = the sharpest bend; never above 1 / yarn radius, where the tube
    // itself folds). Real data has rare kinks that would otherwise set the step everywhere.
    float curvature_quantile = 0.99f;
    double memory_budget_bytes = 8.0 * 1024 * 1024 * 1024;  // refuse scenes whose geometry needs more
};

}  // namespace purl
