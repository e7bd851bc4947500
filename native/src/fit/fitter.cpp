#include "fit/fitter.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "base/input_error.h"
#include "math/vec.h"
#include "render/renderer.h"

namespace purl {
namespace {

using Clock = std::chrono::steady_clock;

// Solves the small dense system A x = b (row-major n x n) by Gaussian elimination with
// partial pivoting; false when A is singular.
bool solve_dense(std::vector<double> A, std::vector<double> b, int n, std::vector<double>& x) {
    for (int col = 0; col < n; ++col) {
        int pivot = col;
        for (int r = col + 1; r < n; ++r)
            if (std::abs(A[r * n + col]) > std::abs(A[pivot * n + col])) pivot = r;
        if (!(std::abs(A[pivot * n + col]) > 1e-300)) return false;
        if (pivot != col) {
            for (int k = 0; k < n; ++k) std::swap(A[col * n + k], A[pivot * n + k]);
            std::swap(b[col], b[pivot]);
        }
        for (int r = col + 1; r < n; ++r) {
            const double f = A[r * n + col] / A[col * n + col];
            for (int k = col; k < n; ++k) A[r * n + k] -= f * A[col * n + k];
            b[r] -= f * b[col];
        }
    }
    x.assign(n, 0.0);
    for (int r = n - 1; r >= 0; --r) {
        double s = b[r];
        for (int k = r + 1; k < n; ++k) s -= A[r * n + k] * x[k];
        x[r] = s / A[r * n + r];
    }
    return true;
}

// Renders every target at unit-cube point u and returns the stacked, weighted residuals whose
// squared sum is the objective.
class Objective {
public:
    Objective(const std::vector<FitTarget>& targets, const BysdfParams& start, const FitOptions& options)
        : targets_(targets), start_(start), options_(options) {}

    BysdfParams params_at(const std::vector<double>& u) const {
        std::vector<float> values(u.size());
        for (size_t k = 0; k < u.size(); ++k) values[k] = options_.unknowns[k].value_at(u[k]);
        return apply_unknowns(start_, options_.unknowns, values);
    }

    std::vector<double> residuals(const std::vector<double>& u, std::vector<double>* per_target = nullptr) {
        const BysdfParams p = params_at(u);
        std::vector<double> r;
        if (per_target) per_target->clear();
        for (const FitTarget& t : targets_) {
            const std::vector<float> rgb = render_target(t, p, options_.spp, options_.seed, options_.threads);
            ++renders_;
            // Residuals of b x b block means: averaging cuts the render noise that would otherwise
            // bias the minimum (E[(X - T)^2] grows with Var X, which shrinks as albedos shrink).
            const int b = std::max(1, options_.block);
            const int bw = (t.width + b - 1) / b, bh = (t.height + b - 1) / b;
            std::vector<double> rendered(size_t(bw) * bh * 3, 0.0), target(rendered.size(), 0.0),
                weight(size_t(bw) * bh, 0.0);
            for (int y = 0; y < t.height; ++y)
                for (int x = 0; x < t.width; ++x) {
                    const size_t i = size_t(y) * t.width + x, k = size_t(y / b) * bw + x / b;
                    const double w = t.weight.empty() ? 1.0 : t.weight[i];
                    weight[k] += w;
                    for (int c = 0; c < 3; ++c) {
                        rendered[k * 3 + c] += w * rgb[i * 3 + c];
                        target[k * 3 + c] += w * t.rgb[i * 3 + c];
                    }
                }
            double total_weight = 0;
            for (double w : weight) total_weight += w;
            // Each target's weighted MSE (of block means) enters with weight 1 / (number of targets);
            // relative: divided by the target's own mean square, so a dim target counts as much as
            // a bright one.
            const double norm = 1.0 / (3.0 * total_weight * double(targets_.size()));
            double scale = 1.0;
            if (options_.error == FitError::Relative) {
                double square = 0;
                for (size_t k = 0; k < weight.size(); ++k)
                    for (int c = 0; c < 3; ++c)
                        if (weight[k] > 0) square += target[k * 3 + c] * target[k * 3 + c] / weight[k];
                square /= 3.0 * total_weight;
                scale = square > 0 ? 1.0 / std::sqrt(square) : 1.0;
            }
            double sum = 0;
            for (size_t k = 0; k < weight.size(); ++k)
                for (int c = 0; c < 3; ++c) {
                    const size_t j = k * 3 + c;
                    const double d = weight[k] > 0 ? scale * (encoded(rendered[j] / weight[k]) -
                                                              encoded(target[j] / weight[k]))
                                                   : 0.0;
                    r.push_back(std::sqrt(weight[k] * norm) * d);
                    sum += weight[k] * d * d;
                }
            if (per_target) per_target->push_back(sum / (3.0 * total_weight));
        }
        return r;
    }
    int renders() const { return renders_; }

private:
    double encoded(double linear) const {
        if (options_.error != FitError::Srgb) return linear;
        return srgb_encode(float(std::min(linear, 1.0)));
    }

    const std::vector<FitTarget>& targets_;
    BysdfParams start_;
    const FitOptions& options_;
    int renders_ = 0;
};

double squared_norm(const std::vector<double>& r) {
    double s = 0;
    for (double v : r) s += v * v;
    return s;
}

}  // namespace

std::vector<float> render_target(const FitTarget& target, const BysdfParams& params, int spp, long long seed,
                                 int threads) {
    SceneDesc scene = target.scene;
    scene.render.model = YarnModel::Bysdf;
    if (spp > 0) scene.render.spp = spp;
    if (seed >= 0) scene.render.seed = uint64_t(seed);
    if (threads > 0) scene.render.threads = threads;
    for (YarnSetDesc& y : scene.yarns)
        if (y.material.model == MaterialModel::Bysdf) y.material.bysdf = params;
    Renderer renderer(std::move(scene));
    RenderControl control;
    const RenderResult result = renderer.render(control);
    const ImagePass* combined = result.image.find("Combined");
    if (!combined) throw std::runtime_error("the renderer produced no Combined pass");
    const size_t pixels = size_t(result.image.width) * result.image.height;
    const int channels = combined->channels();
    std::vector<float> rgb(pixels * 3);
    for (size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = combined->pixels[i * channels + c];
    return rgb;
}

namespace {

struct FitErrorInfo {
    FitError error;
    const char* name;
    const char* compared;  // what the objective's squared differences are of
};
constexpr FitErrorInfo kFitErrors[] = {
    {FitError::Linear, "linear", "linear RGB"},
    {FitError::Relative, "relative", "linear RGB over each target's own mean square"},
    {FitError::Srgb, "srgb", "sRGB-encoded RGB clamped to [0, 1]"},
};

const FitErrorInfo& info(FitError error) {
    for (const FitErrorInfo& i : kFitErrors)
        if (i.error == error) return i;
    return kFitErrors[0];
}

}  // namespace

FitError fit_error_from_name(const std::string& name, const std::string& where) {
    for (const FitErrorInfo& i : kFitErrors)
        if (name == i.name) return i.error;
    throw InputError(where, "", "unknown error measure '" + name + "' (linear, relative or srgb)");
}

const char* fit_error_name(FitError error) { return info(error).name; }
const char* fit_error_compared(FitError error) { return info(error).compared; }

double target_error(const FitTarget& target, const std::vector<float>& rgb) {
    const size_t pixels = size_t(target.width) * target.height;
    double sum = 0, total_weight = 0;
    for (size_t i = 0; i < pixels; ++i) {
        const double w = target.weight.empty() ? 1.0 : target.weight[i];
        total_weight += w;
        for (int c = 0; c < 3; ++c) {
            const double d = double(rgb[i * 3 + c]) - double(target.rgb[i * 3 + c]);
            sum += w * d * d;
        }
    }
    return sum / (3.0 * total_weight);
}

BysdfParams starting_params(const std::vector<FitTarget>& targets) {
    for (const FitTarget& t : targets)
        for (const YarnSetDesc& y : t.scene.yarns)
            if (y.material.model == MaterialModel::Bysdf) return y.material.bysdf;
    throw InputError(targets.empty() ? "" : targets.front().name, "", "no yarn with a bysdf material to fit");
}

FitResult fit_bysdf(const std::vector<FitTarget>& targets, const BysdfParams& start, const FitOptions& options) {
    if (targets.empty()) throw InputError("", "", "no fitting targets given");
    if (options.unknowns.empty()) throw InputError("", "", "no parameters to fit");
    for (const FitTarget& t : targets) check_fit_target(t);
    const auto t0 = Clock::now();
    const int n = int(options.unknowns.size());
    Objective objective(targets, start, options);

    FitResult result;
    result.unknowns = options.unknowns;
    std::vector<double> u(n);
    for (int k = 0; k < n; ++k) {
        u[k] = options.unknowns[k].u_of(options.unknowns[k].get(start));
        result.start_values.push_back(options.unknowns[k].value_at(u[k]));
    }
    std::vector<double> r = objective.residuals(u);
    double error = squared_norm(r);
    result.initial_error = error;
    result.history.push_back(error);
    double lambda = 1e-2;

    // Renders one iteration takes at least: a Jacobian column per unknown and one trial step.
    const int renders_per_iteration = (n + 1) * int(targets.size());
    auto report = [&](int iteration, const char* event, int column = 0) {
        if (!options.progress) return true;
        FitProgress p;
        p.iteration = iteration;
        p.renders = objective.renders();
        p.error = error;
        p.lambda = lambda;
        p.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        const double per_render = p.seconds / std::max(1, p.renders);
        const int this_iteration = iteration == 0 ? 0 : (column > 0 ? n - column + 1 : 0) * int(targets.size());
        p.seconds_per_iteration = per_render * renders_per_iteration;
        p.seconds_left = per_render * (this_iteration + (options.max_iterations - iteration) * renders_per_iteration);
        p.event = event;
        p.column = column;
        p.columns = n;
        return options.progress(p);
    };
    result.stop_reason = "max_iterations";
    if (!report(0, "start")) result.stop_reason = "stopped";

    const size_t m = r.size();
    for (int it = 1; it <= options.max_iterations && result.stop_reason == "max_iterations"; ++it) {
        result.iterations = it;
        // Jacobian by forward differences, stepping inward at the upper bound.
        std::vector<double> J(m * n);
        for (int k = 0; k < n; ++k) {
            std::vector<double> u2 = u;
            const double h = u[k] + options.step <= 1.0 ? options.step : -options.step;
            u2[k] += h;
            const std::vector<double> r2 = objective.residuals(u2);
            for (size_t i = 0; i < m; ++i) J[i * n + k] = (r2[i] - r[i]) / h;
            if (!report(it, "jacobian", k + 1)) {
                result.stop_reason = "stopped";
                break;
            }
        }
        if (result.stop_reason == "stopped") break;
        std::vector<double> A(n * n, 0.0), g(n, 0.0);
        for (size_t i = 0; i < m; ++i) {
            const double* row = &J[i * n];
            for (int a = 0; a < n; ++a) {
                g[a] += row[a] * r[i];
                for (int b = 0; b <= a; ++b) A[a * n + b] += row[a] * row[b];
            }
        }
        for (int a = 0; a < n; ++a)
            for (int b = a + 1; b < n; ++b) A[a * n + b] = A[b * n + a];
        // Unknowns resting on a bound that the gradient pushes outward stay put this iteration.
        std::vector<int> free;
        for (int k = 0; k < n; ++k) {
            const bool pinned = (u[k] <= 0.0 && g[k] > 0) || (u[k] >= 1.0 && g[k] < 0);
            if (!pinned && A[k * n + k] > 0) free.push_back(k);
        }
        if (free.empty()) {
            result.stop_reason = "converged";
            break;
        }
        const int f = int(free.size());
        double max_diag = 0;
        for (int k : free) max_diag = std::max(max_diag, A[k * n + k]);
        bool accepted = false;
        for (int attempt = 0; attempt < 10 && !accepted; ++attempt) {
            std::vector<double> M(f * f), rhs(f), delta;
            for (int a = 0; a < f; ++a) {
                rhs[a] = -g[free[a]];
                for (int b = 0; b < f; ++b) M[a * f + b] = A[free[a] * n + free[b]];
                // Marquardt's scaling plus a floor, so flat directions do not take huge steps.
                M[a * f + a] += lambda * (A[free[a] * n + free[a]] + 1e-6 * max_diag);
            }
            if (!solve_dense(M, rhs, f, delta)) {
                lambda *= 4;
                continue;
            }
            std::vector<double> trial = u;
            double moved = 0;
            for (int a = 0; a < f; ++a) {
                const int k = free[a];
                trial[k] = std::clamp(u[k] + delta[a], 0.0, 1.0);
                moved = std::max(moved, std::abs(trial[k] - u[k]));
            }
            if (moved < 1e-7) break;  // the step vanished: nothing left to gain
            std::vector<double> r_trial = objective.residuals(trial);
            const double trial_error = squared_norm(r_trial);
            if (trial_error < error) {
                const double gain = (error - trial_error) / std::max(error, 1e-300);
                u = trial;
                r = std::move(r_trial);
                error = trial_error;
                lambda = std::max(lambda / 3, 1e-7);
                accepted = true;
                if (!report(it, "accepted")) result.stop_reason = "stopped";
                else if (gain < options.tolerance) result.stop_reason = "converged";
            } else {
                lambda *= 4;
                if (!report(it, "rejected")) {
                    result.stop_reason = "stopped";
                    break;
                }
            }
        }
        result.history.push_back(error);
        if (!accepted && result.stop_reason == "max_iterations") result.stop_reason = "no_improvement";
    }

    result.params = objective.params_at(u);
    for (int k = 0; k < n; ++k) result.values.push_back(options.unknowns[k].value_at(u[k]));
    // The final per-target errors are recomputed once (same seed: same images as the last step).
    objective.residuals(u, &result.target_errors);
    result.final_error = error;
    result.renders = objective.renders();
    result.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return result;
}

}  // namespace purl
