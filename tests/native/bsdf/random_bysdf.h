// Random BYSDF configurations shared by the chi-square, energy and fuzz tests.
#pragma once
#include <cmath>

#include "bsdf/bysdf.h"
#include "math/rng.h"

namespace purl::test {

inline float uniform(Rng& rng, float lo, float hi) { return lo + (hi - lo) * rng.next_float(); }
inline Vec3 random_color(Rng& rng) { return {rng.next_float(), rng.next_float(), rng.next_float()}; }

// Parameters inside the documented ranges, roughness limited to where a 20 x 40 grid
// resolves the lobes (alpha >= 0.05; sharper lobes are covered by the fuzz test).
inline BysdfParams random_bysdf_params(Rng& rng) {
    BysdfParams p = default_bysdf_params();
    p.eta = uniform(rng, 1.1f, 2.5f);
    p.specular_roughness_along = uniform(rng, 0.05f, 1.0f);
    p.specular_roughness_across = uniform(rng, 0.05f, 1.0f);
    p.transmission_roughness = uniform(rng, 0.1f, 1.0f);
    p.specular_reflection_albedo = random_color(rng);
    p.specular_transmission_albedo = random_color(rng);
    p.body_share = rng.next_float();
    p.body_reflection_share = rng.next_float();
    p.body_reflection_fresnel = rng.next_float() < 0.5f ? 0.0f : rng.next_float();
    p.body_reflection_albedo = random_color(rng);
    p.body_transmission_albedo = random_color(rng);
    p.lommel_seeliger_weight = rng.next_float();
    p.sigma_t_specular = uniform(rng, 0.0f, 20.0f);
    p.sigma_t_body = uniform(rng, 0.0f, 2.0f);
    p.ply_shadow_floor = rng.next_float();
    p.fiber_shadow_floor = rng.next_float();
    p.ply_crossing = rng.next_float() < 0.5f ? 0.0f : 1.0f;
    p.ply_color_count = float(1 + int(rng.next_float() * kMaxPlyColors));
    for (Vec3& c : p.ply_colors) c = random_color(rng);
    return p;
}

inline BysdfShadingPoint random_shading_point(Rng& rng) {
    BysdfShadingPoint sp;
    sp.ply_shadow = rng.next_float();
    sp.fiber_shadow = rng.next_float();
    sp.plies_crossed = 1 + int(rng.next_float() * 6);
    sp.ply_index = int(rng.next_float() * 12);
    sp.yarn_color = random_color(rng);
    sp.mean_fiber_shadow = rng.next_float();
    return sp;
}

// Direction with the given cos theta and a random azimuth.
inline Vec3 direction_with_cos(Rng& rng, float cos_theta) {
    const float phi = 2 * kPi * rng.next_float();
    const float s = std::sqrt(std::max(0.0f, 1 - cos_theta * cos_theta));
    return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

// White-furnace configuration: every albedo 1, no extinction, no shadowing.
inline BysdfParams white_bysdf_params(float body_share) {
    BysdfParams p = default_bysdf_params();
    p.specular_reflection_albedo = p.specular_transmission_albedo = Vec3(1.0f);
    p.body_reflection_albedo = p.body_transmission_albedo = Vec3(1.0f);
    p.sigma_t_specular = p.sigma_t_body = 0.0f;
    p.ply_shadow_floor = p.fiber_shadow_floor = 1.0f;
    p.body_share = body_share;
    return p;
}

}  // namespace purl::test
