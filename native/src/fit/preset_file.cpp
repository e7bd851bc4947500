#include "fit/preset_file.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "base/input_error.h"
#include "bsdf/fiber_bcsdf_params.h"
#include "yarn/yarn_description.h"

namespace purl {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Four significant digits keep presets readable; the renders cannot tell the rest apart.
double tidy(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", double(v));
    return std::strtod(text, nullptr);
}

template <class Params>
void put_params(json& out, const std::vector<ParamInfo>& table, const Params& p, int ply_colors = 12) {
    for (const ParamInfo& info : table) {
        const std::string name = info.name;
        if (name.rfind("ply_color_", 0) == 0 && name != "ply_color_count" &&
            std::stoi(name.substr(10)) > ply_colors)
            continue;
        const float* v = param_field(p, info);
        // Rounding must not step outside the range (0.001f rounds to a double below 0.001f).
        const auto in_range = [&](float x) {
            return std::clamp(tidy(x), double(info.min_value), double(info.max_value));
        };
        if (info.components == 1) out[name] = in_range(v[0]);
        else out[name] = {in_range(v[0]), in_range(v[1]), in_range(v[2])};
    }
}

}  // namespace

json bysdf_material_json(const MaterialDesc& m) {
    json out = {{"model", "bysdf"}};
    put_params(out, bysdf_param_table(), m.bysdf, int(m.bysdf.ply_color_count));
    json yarn = json::object();
    put_params(yarn, yarn_description_params(), m.yarn);
    out["yarn"] = yarn;
    json fiber = json::object();
    put_params(fiber, fiber_bcsdf_param_table(), m.fiber);
    out["fiber"] = fiber;
    return out;
}

json fit_preset_json(const std::string& name, const MaterialDesc& base, const FitResult& result,
                     const std::vector<FitSource>& sources, const FitOptions& options) {
    MaterialDesc fitted = base;
    fitted.bysdf = result.params;
    json targets = json::array();
    for (size_t i = 0; i < sources.size(); ++i) {
        json t = {{"scene", sources[i].scene}, {"image", sources[i].image}};
        if (!sources[i].mask.empty()) t["mask"] = sources[i].mask;
        if (i < result.target_errors.size()) t["mse"] = result.target_errors[i];
        targets.push_back(t);
    }
    json fitted_values = json::object();
    for (size_t k = 0; k < result.unknowns.size(); ++k)
        fitted_values[result.unknowns[k].label] = {{"start", tidy(result.start_values[k])},
                                                   {"fitted", tidy(result.values[k])}};
    json preset = {
        {"name", name},
        {"description", "BYSDF parameters fitted by purl fit to " + std::to_string(sources.size()) +
                            " target image(s)"},
        {"source", "purl fit"},
        {"material", bysdf_material_json(fitted)},
        {"provenance",
         {{"tool", "purl fit"},
          {"objective", std::string("mean squared error of ") + fit_error_compared(options.error) +
                            " (of block x block pixel means), averaged over the targets"},
          {"error", fit_error_name(options.error)},
          {"targets", targets},
          {"parameters", fitted_values},
          {"initial_mse", result.initial_error},
          {"final_mse", result.final_error},
          {"iterations", result.iterations},
          {"renders", result.renders},
          {"seconds", result.seconds},
          {"stop_reason", result.stop_reason},
          {"spp", options.spp},
          {"seed", options.seed},
          {"block", options.block}}},
    };
    return preset;
}

void write_json_file(const std::string& path, const json& value) {
    const std::string temporary = path + ".tmp";
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) throw InputError(path, "", "cannot open for writing");
        out << value.dump(2) << "\n";
        if (!out) throw InputError(path, "", "cannot write");
    }
    std::error_code ec;
    fs::rename(temporary, path, ec);
    if (ec) throw InputError(path, "", "cannot write: " + ec.message());
}

}  // namespace purl
