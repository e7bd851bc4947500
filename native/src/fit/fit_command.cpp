#include "fit/fit_command.h"

#include <cstdio>
#include <filesystem>

#include "base/input_error.h"
#include "fit/fitter.h"
#include "fit/preset_file.h"

namespace purl {

namespace fs = std::filesystem;

int run_fit_command(const FitCommand& c) {
    if (c.targets.empty()) throw InputError("--target", "", "give at least one target image");
    if (c.scenes.size() != 1 && c.scenes.size() != c.targets.size())
        throw InputError("purl fit", "", "give one scene for all targets or one per target (" +
                                             std::to_string(c.scenes.size()) + " scenes, " +
                                             std::to_string(c.targets.size()) + " targets)");
    if (!c.masks.empty() && c.masks.size() != c.targets.size())
        throw InputError("--mask", "", "give one mask per target or none");
    if (fs::path(c.output).extension() != ".json") throw InputError(c.output, "", "the preset must end in .json");

    FitOptions options;
    options.unknowns = parse_fit_parameters(c.params.empty() ? default_fit_parameter_list() : c.params, "--params");
    options.max_iterations = c.iterations;
    options.spp = c.spp;
    options.seed = c.seed;
    options.threads = c.threads;
    options.tolerance = c.tolerance;
    options.block = c.block;
    options.error = fit_error_from_name(c.error, "--error");

    std::vector<FitTarget> targets;
    std::vector<FitSource> sources;
    for (size_t i = 0; i < c.targets.size(); ++i) {
        const std::string& scene = c.scenes.size() == 1 ? c.scenes[0] : c.scenes[i];
        const std::string mask = c.masks.empty() ? "" : c.masks[i];
        targets.push_back(load_fit_target(scene, c.targets[i], mask));
        sources.push_back({scene, c.targets[i], mask});
    }
    std::fprintf(stderr, "purl fit: %zu unknowns, %zu target(s), %d x %d px\n", options.unknowns.size(),
                 targets.size(), targets[0].width, targets[0].height);
    options.progress = [](const FitProgress& p) {
        if (p.event == "jacobian") {  // one line per column, rewritten in place
            std::fprintf(stderr, "\r  iteration %2d  derivative %d/%d  %.0f s, at most ~%.0f s left   ", p.iteration,
                         p.column, p.columns, p.seconds, p.seconds_left);
            return true;
        }
        std::fprintf(stderr,
                     "\r  iteration %2d  %-8s  mse %.6g  lambda %.2g  renders %d  %.1f s  (~%.0f s an iteration, "
                     "at most ~%.0f s left)\n",
                     p.iteration, p.event.c_str(), p.error, p.lambda, p.renders, p.seconds, p.seconds_per_iteration,
                     p.seconds_left);
        return true;
    };
    const BysdfParams start = starting_params(targets);
    const FitResult result = fit_bysdf(targets, start, options);

    MaterialDesc base;
    for (const YarnSetDesc& y : targets[0].scene.yarns)
        if (y.material.model == MaterialModel::Bysdf) {
            base = y.material;
            break;
        }
    const std::string name = c.name.empty() ? fs::path(c.output).stem().string() : c.name;
    write_json_file(c.output, fit_preset_json(name, base, result, sources, options));
    for (size_t k = 0; k < result.unknowns.size(); ++k)
        std::fprintf(stderr, "  %-32s %.4g -> %.4g\n", result.unknowns[k].label.c_str(), result.start_values[k],
                     result.values[k]);
    std::fprintf(stderr, "purl fit: mse %.6g -> %.6g after %d iterations (%d renders, %.1f s, %s); wrote %s\n",
                 result.initial_error, result.final_error, result.iterations, result.renders, result.seconds,
                 result.stop_reason.c_str(), c.output.c_str());
    return 0;
}

}  // namespace purl
