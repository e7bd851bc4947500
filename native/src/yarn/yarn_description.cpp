#include "yarn/yarn_description.h"

#include <cmath>
#include <cstddef>

#include "base/input_error.h"
#include "base/registry.h"
#include "math/number_text.h"
#include "math/vec.h"

namespace purl {
namespace {

ParamInfo field(const char* label, const char* name, const char* unit, float lo, float hi, float def,
                const char* doc, size_t offset) {
    return labelled({name, unit, 1, lo, hi, {def, 0, 0}, doc, offset, false}, label);
}
// A parameter that only takes whole numbers (stored as a float like the others).
ParamInfo whole(const char* label, const char* name, const char* unit, float lo, float hi, float def,
                const char* doc, size_t offset) {
    ParamInfo info = field(label, name, unit, lo, hi, def, doc, offset);
    info.kind = ParamKind::Integer;
    return info;
}
// A twist direction: +1 (Z, right-handed) or -1 (S).
ParamInfo sign(const char* label, const char* name, float def, const char* doc, size_t offset) {
    ParamInfo info = field(label, name, "", -1, 1, def, doc, offset);
    info.kind = ParamKind::Enum;
    info.choices = &twist_directions();
    return info;
}

// The prototype's three touching plies: ply radius 0.9 at yarn radius 2.
constexpr float kPrototypePlyRadius = 0.45f;

std::vector<ParamInfo> build_table() {
    const float touching_distance = kPrototypePlyRadius / std::sin(kPi / 3);
    return {
        whole("Plies", "ply_count", "", 1, kMaxPlies, 3, "Number of plies in the yarn (whole number).",
              offsetof(YarnDescription, ply_count)),
        field("Ply Radius", "ply_radius", "R", 0.02f, 1, kPrototypePlyRadius, "Ply radius in yarn radii.",
              offsetof(YarnDescription, ply_radius)),
        field("Ply Distance", "ply_distance", "R", 0, 1, touching_distance,
              "Distance from the yarn centre-line to each ply centre-line, in yarn radii.",
              offsetof(YarnDescription, ply_distance)),
        field("Ply Twist", "ply_twist", "rad/R", 0, 10, 2.0f / 3.0f,
              "Ply turn rate around the yarn, radians per yarn radius of yarn length.",
              offsetof(YarnDescription, ply_twist)),
        sign("Ply Direction", "ply_handedness", 1, "+1 for Z-twisted (right-handed) plies, -1 for S.",
              offsetof(YarnDescription, ply_handedness)),
        whole("Fibers per Ply", "fiber_count", "", 1, 2000, 25, "Fibers per ply (whole number).",
              offsetof(YarnDescription, fiber_count)),
        field("Fiber Radius", "fiber_radius", "ply radii", 0.002f, 0.5f, 1.0f / std::sqrt(50.0f),
              "Fiber radius in ply radii.", offsetof(YarnDescription, fiber_radius)),
        field("Fiber Twist", "fiber_twist", "rad/R", 0, 20, 2.0f / 3.0f,
              "Fiber turn rate around the ply, radians per yarn radius of ply length.",
              offsetof(YarnDescription, fiber_twist)),
        sign("Fiber Direction", "fiber_handedness", -1, "+1 for Z-twisted fibers, -1 for S.",
              offsetof(YarnDescription, fiber_handedness)),
        field("Migration Min", "migration_rho_min", "", 0, 1, 0.8f,
              "Smallest distance of a migrating fiber from the ply centre, as a fraction of its rest distance.",
              offsetof(YarnDescription, migration_rho_min)),
        field("Migration Max", "migration_rho_max", "", 0, 1, 1,
              "Largest distance of a migrating fiber from the ply centre, as a fraction of its rest distance.",
              offsetof(YarnDescription, migration_rho_max)),
        field("Migration Rate", "migration_frequency", "1/turn", 0, 10, 1.5f,
              "s_i: migration cycles per fiber turn around the ply.",
              offsetof(YarnDescription, migration_frequency)),
        field("Edge Density", "density_eps", "", 0, 0.5f, 0.1f,
              "Zhao's eps: fiber density at the ply boundary relative to the centre's 1 - eps.",
              offsetof(YarnDescription, density_eps)),
        field("Density Falloff", "density_beta", "", 0, 4, 0.5f,
              "Zhao's beta: exponent of the fiber density fall-off toward the ply boundary.",
              offsetof(YarnDescription, density_beta)),
        whole("Map Resolution", "map_resolution", "", 16, 4096, 256,
              "Samples around the circumference in each 1D fiber and ply-shadow map (whole number).",
              offsetof(YarnDescription, map_resolution)),
        whole("Map Variants", "migration_variants", "", 1, 16, 4,
              "Fiber-map variants switched along each ply to imitate migration (whole number).",
              offsetof(YarnDescription, migration_variants)),
        whole("Seed", "seed", "", 0, 1 << 24, 1, "Seed of the procedural fiber cross-sections (whole number).",
              offsetof(YarnDescription, seed)),
    };
}

// One row of Zhao et al.'s table (their units: scene units of the source data).
struct ZhaoSet {
    const char* name;
    int plies, fibers;
    float yarn_alpha, alpha, yarn_radius, ellipse_long, ellipse_short, eps, beta, s_i, rho_min;
};
constexpr ZhaoSet kZhaoSets[] = {
    {"A", 2, 150, 0.639f, 0.710f, 0.0507f, 0.0531f, 0.0356f, 0.139f, 0.682f, 1.9f, 0.85f},
    {"B", 3, 75, 0.453f, 0.369f, 0.0378f, 0.0257f, 0.0200f, 0.0f, 0.148f, 1.1f, 0.80f},
    {"C", 2, 80, 0.372f, 0.381f, 0.0287f, 0.0283f, 0.0209f, 0.052f, 0.293f, 1.6f, 0.85f},
    {"D", 2, 122, 0.498f, 0.560f, 0.0452f, 0.0483f, 0.0343f, 0.361f, 0.671f, 1.7f, 0.70f},
    {"E", 2, 143, 0.638f, 0.609f, 0.0418f, 0.0441f, 0.0335f, 0.0f, 0.640f, 1.9f, 0.95f},
    {"F", 3, 37, 0.336f, 0.436f, 0.0330f, 0.0247f, 0.0180f, 0.033f, 0.430f, 1.9f, 0.95f},
    {"G", 3, 33, 0.526f, 0.458f, 0.0376f, 0.0253f, 0.0216f, 0.0f, 0.462f, 1.8f, 0.95f},
    {"H", 3, 47, 0.702f, 0.556f, 0.0451f, 0.0306f, 0.0252f, 0.405f, 0.554f, 1.2f, 0.70f},
    {"I", 2, 60, 0.370f, 0.379f, 0.0287f, 0.0285f, 0.0211f, 0.202f, 0.258f, 1.5f, 0.75f},
};

// Zhao's ply centres sit at yarn_radius / 2; our plies are circles of the ellipse's
// area-equivalent radius, and the yarn tube just encloses them. Zhao gives no fiber
// radius, so fibers fill half the ply's area, as in the prototype (25 fibers of 1/sqrt(50)).
YarnDescription from_zhao(const ZhaoSet& z) {
    YarnDescription d = default_yarn_description();
    const float centre = 0.5f * z.yarn_radius;
    const float ply = std::sqrt(z.ellipse_long * z.ellipse_short);
    const float yarn = centre + ply;
    d.ply_count = static_cast<float>(z.plies);
    d.ply_radius = ply / yarn;
    d.ply_distance = centre / yarn;
    d.ply_twist = 2 * kPi * yarn / z.yarn_alpha;
    d.fiber_count = static_cast<float>(z.fibers);
    d.fiber_radius = std::sqrt(0.5f / z.fibers);
    d.fiber_twist = 2 * kPi * yarn / z.alpha;
    d.migration_rho_min = z.rho_min;
    d.migration_rho_max = 1.0f;
    d.migration_frequency = z.s_i;
    d.density_eps = z.eps;
    d.density_beta = z.beta;
    return d;
}

bool is_whole(float v) { return v == std::floor(v); }

}  // namespace

const std::vector<ParamInfo>& yarn_description_params() {
    static const std::vector<ParamInfo> table = build_table();
    return table;
}

YarnDescription default_yarn_description() {
    YarnDescription d;
    apply_defaults(d, yarn_description_params());
    return d;
}

YarnDescription yarn_preset(const std::string& name) {
    if (name == "prototype") return default_yarn_description();
    for (const ZhaoSet& z : kZhaoSets)
        if (name == z.name) return from_zhao(z);
    std::string known = "prototype";
    for (const ZhaoSet& z : kZhaoSets) known += std::string(", ") + z.name;
    throw InputError("", "yarn preset \"" + name + "\"", "unknown; known presets: " + known);
}

std::vector<std::string> yarn_preset_names() {
    std::vector<std::string> names = {"prototype"};
    for (const ZhaoSet& z : kZhaoSets) names.push_back(z.name);
    return names;
}

void check_yarn_description(const YarnDescription& d, const std::string& file, const std::string& place) {
    auto fail = [&](const char* name, const std::string& reason) {
        throw InputError(file, place + "." + name, reason);
    };
    for (const ParamInfo& info : yarn_description_params()) {
        const float v = *param_field(d, info);
        if (!(v >= info.min_value && v <= info.max_value))  // also catches NaN
            fail(info.name, "value " + number_text(v) + " outside [" + number_text(info.min_value) +
                                ", " + number_text(info.max_value) + "]");
    }
    const std::pair<const char*, float> whole[] = {
        {"ply_count", d.ply_count},          {"fiber_count", d.fiber_count},
        {"map_resolution", d.map_resolution}, {"migration_variants", d.migration_variants},
        {"seed", d.seed}};
    for (const auto& [name, v] : whole)
        if (!is_whole(v)) fail(name, "must be a whole number, got " + number_text(v));
    if (std::fabs(d.ply_handedness) != 1.0f) fail("ply_handedness", "must be +1 (Z) or -1 (S)");
    if (std::fabs(d.fiber_handedness) != 1.0f) fail("fiber_handedness", "must be +1 (Z) or -1 (S)");
    if (d.ply_distance + d.ply_radius > 1.0f + 1e-4f)
        fail("ply_radius", "plies stick out of the yarn tube: ply_distance + ply_radius = " +
                               std::to_string(d.ply_distance + d.ply_radius) + " > 1");
    if (d.ply_count > 1 && d.ply_distance <= 0)
        fail("ply_distance", "must be > 0 when there is more than one ply (they would coincide)");
    if (d.migration_rho_min > d.migration_rho_max)
        fail("migration_rho_min", "must not exceed migration_rho_max");
}

}  // namespace purl
