// Fits BYSDF parameters so that renders of one or more target scenes match their images.
//
// Objective: the pixel-wise mean squared error of the Combined RGB (optionally of b x b block
// means; linear, relative or sRGB-encoded: FitError), weighted by each target's mask, averaged over the targets (so front-lit and back-lit images count alike whatever
// their size). Optimiser: Levenberg-Marquardt on the per-pixel residuals, with forward-
// difference Jacobians. Every render uses the same seed and sample count (common random
// numbers), so the objective is a deterministic, nearly smooth function of the parameters
// and differences of two renders measure the parameter's effect rather than noise. Steps
// are only accepted when they lower the error, so the error never rises.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "fit/fit_params.h"
#include "fit/fit_target.h"

namespace purl {

struct FitProgress {
    int iteration = 0;    // Jacobian evaluations so far
    int renders = 0;      // renders so far (all targets count one each)
    double error = 0;     // best error so far
    double lambda = 0;    // Levenberg-Marquardt damping
    double seconds = 0;
    // Estimate from the mean render time so far: to the end of the iteration cap (the fit may
    // stop sooner, when a step gains less than the tolerance), and for one more iteration.
    double seconds_left = 0, seconds_per_iteration = 0;
    std::string event;    // "start", "jacobian" (after each column), "accepted", "rejected"
    int column = 0, columns = 0;  // "jacobian": finite differences done in this iteration, of
};

// What a residual compares: linear RGB; linear RGB over the target's own root mean square (a dim
// target, e.g. front light beside back light, counts as much as a bright one); or sRGB-encoded
// values clamped to [0, 1], as LDR FLIP and a display see them (dark regions count as much as
// highlights; values above 1 are the same white).
enum class FitError { Linear, Relative, Srgb };
FitError fit_error_from_name(const std::string& name, const std::string& where);  // "linear" | "relative" | "srgb"
const char* fit_error_name(FitError error);
const char* fit_error_compared(FitError error);  // "linear RGB", ...: what the objective compares

struct FitOptions {
    std::vector<FitUnknown> unknowns;
    int max_iterations = 20;     // Jacobian evaluations
    int spp = 0;                 // 0: each scene's own
    long long seed = -1;         // -1: each scene's own
    int threads = 0;             // 0: all cores
    double tolerance = 1e-3;     // stop when an accepted step lowers the error by less than this fraction
    double step = 0.02;          // finite-difference step in the unit cube
    int block = 1;               // compare b x b block means (1: single pixels)
    FitError error = FitError::Linear;
    // Called after every step; returning false stops the fit (the best parameters so far are kept).
    std::function<bool(const FitProgress&)> progress;
};

struct FitResult {
    BysdfParams params;                 // the start with the fitted unknowns set
    std::vector<FitUnknown> unknowns;
    std::vector<float> start_values, values;
    double initial_error = 0, final_error = 0;
    std::vector<double> target_errors;  // final, per target
    std::vector<double> history;        // error after every iteration
    int iterations = 0, renders = 0;
    double seconds = 0;
    std::string stop_reason;            // "converged", "max_iterations", "no_improvement", "stopped"
};

// The starting material: the first bysdf yarn set of the first target.
BysdfParams starting_params(const std::vector<FitTarget>& targets);

FitResult fit_bysdf(const std::vector<FitTarget>& targets, const BysdfParams& start, const FitOptions& options);

// Renders a target's scene with every bysdf yarn set given `params` (always the bysdf model);
// returns linear RGB, rows top to bottom.
std::vector<float> render_target(const FitTarget& target, const BysdfParams& params, int spp, long long seed,
                                 int threads);

// Weighted mean squared error of `rgb` against the target.
double target_error(const FitTarget& target, const std::vector<float>& rgb);

}  // namespace purl
