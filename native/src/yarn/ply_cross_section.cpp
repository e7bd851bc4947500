#include "yarn/ply_cross_section.h"

#include <cmath>

#include "math/rng.h"

namespace purl {

float fiber_density(float r, float eps, float beta) {
    constexpr float e = 2.718281828f;
    const float fall = std::max(0.0f, (e - std::exp(clamp(r, 0.0f, 1.0f))) / (e - 1));
    return (1 - 2 * eps) * std::pow(fall, beta) + eps;
}

int Circles2D::first_hit(Vec2 o, Vec2 d, float t_min, float& t, int skip) const {
    int best = -1;
    t = 1e30f;
    const float r2 = radius * radius;
    for (size_t i = 0; i < centres.size(); ++i) {
        if (static_cast<int>(i) == skip) continue;
        const Vec2 w = o - centres[i];
        const float b = dot(w, d), c = dot(w, w) - r2;
        const float disc = b * b - c;
        if (disc < 0) continue;
        const float root = std::sqrt(disc);
        float hit = -b - root;
        if (hit <= t_min) hit = -b + root;  // starting inside: the far side
        if (hit > t_min && hit < t) {
            t = hit;
            best = static_cast<int>(i);
        }
    }
    return best;
}

Circles2D ply_fibers(const YarnDescription& d, float migration_phase) {
    Circles2D c;
    c.radius = d.fiber_radius;
    Rng rng(static_cast<uint64_t>(d.seed), 0xf1be5);
    const float p_max = std::max(1 - d.density_eps, d.density_eps);
    c.centres.reserve(d.fibers());
    while (static_cast<int>(c.centres.size()) < d.fibers()) {
        // Rest position: uniform in the unit disk, kept with probability p(R) / p_max.
        const float x = 2 * rng.next_float() - 1, y = 2 * rng.next_float() - 1;
        const float r0 = std::sqrt(x * x + y * y);
        const float keep = rng.next_float(), migration_start = 2 * kPi * rng.next_float();
        if (r0 > 1 || keep * p_max > fiber_density(r0, d.density_eps, d.density_beta)) continue;
        const float swing = 0.5f * (std::cos(migration_phase + migration_start) + 1);
        const float scale = d.migration_rho_min + (d.migration_rho_max - d.migration_rho_min) * swing;
        c.centres.emplace_back(x * scale, y * scale);
    }
    return c;
}

Circles2D yarn_plies(const YarnDescription& d) {
    Circles2D c;
    c.radius = d.ply_radius;
    for (int i = 0; i < d.plies(); ++i) {
        const float a = 2 * kPi * i / d.plies();
        c.centres.emplace_back(d.ply_distance * std::cos(a), d.ply_distance * std::sin(a));
    }
    return c;
}

float occlusion_2d(const Circles2D& circles, Vec2 point, Vec2 normal, int self, int directions) {
    // Cosine-weighted in 2D: the angle from the normal has density cos(a) / 2, so stratified
    // a = asin(2u - 1) samples it exactly.
    int blocked = 0;
    const Vec2 side(-normal.y, normal.x);
    const Vec2 start = point + normal * (1e-4f * circles.radius);
    for (int k = 0; k < directions; ++k) {
        const float a = std::asin(2 * (k + 0.5f) / directions - 1);
        const Vec2 dir = normal * std::cos(a) + side * std::sin(a);
        float t;
        if (circles.first_hit(start, dir, 0.0f, t, self) >= 0) ++blocked;
    }
    return static_cast<float>(blocked) / directions;
}

}  // namespace purl
