#include "yarn/ply_crossings.h"

#include <algorithm>
#include <cmath>

namespace purl {

PlySection ply_section(const CurvePoint& cross_section, const YarnDescription& d, const YarnTwist& twist, int ply,
                       Vec3 hit) {
    PlySection s;
    const float radius = std::max(cross_section.radius, 1e-30f);
    s.tangent = cross_section.tangent;
    s.hit_outward = ply_centre(cross_section, d, twist, ply).outward;
    s.offset = (hit - cross_section.position) / radius;
    s.ply_turn = twist.ply_rate * radius;
    s.stretch = twist.ply_stretch;
    return s;
}

namespace {

// Yarn radii inside each ply along `direction` over `chord` (inside[k], every ply).
void march(const PlySection& section, const YarnDescription& d, int hit_ply, Vec3 direction, float chord,
           float inside[kMaxCrossedPlies]) {
    const int plies = std::clamp(d.plies(), 1, kMaxCrossedPlies);
    chord = std::min(chord, 4.0f);  // a chord longer than the diameter only runs along the yarn
    const Vec3 t = section.tangent, out0 = section.hit_outward, around0 = cross(t, out0);
    const float inv_radius2 = 1 / (d.ply_radius * d.ply_radius), inv_stretch = 1 / std::max(section.stretch, 1.0f);
    // Steps of a quarter ply radius; where a ply's boundary lies inside a step is interpolated
    // linearly from the ply's implicit function at the step's two ends.
    const int steps = std::clamp(int(std::ceil(chord / (0.25f * d.ply_radius))), 4, 64);
    const float h = chord / steps;
    float cos_k[kMaxCrossedPlies], sin_k[kMaxCrossedPlies], previous[kMaxCrossedPlies];
    for (int k = 0; k < plies; ++k) inside[k] = 0;
    // Ply k sits 2 pi (k - hit_ply) / plies around from the hit ply: one rotation per ply.
    const float c_ply = std::cos(2 * kPi / plies), s_ply = std::sin(2 * kPi / plies);
    float c_m = 1, s_m = 0;
    for (int m = 0; m < plies; ++m) {
        const int k = (((hit_ply + m) % plies) + plies) % plies;
        cos_k[k] = c_m;
        sin_k[k] = s_m;
        const float c_next = c_m * c_ply - s_m * s_ply;
        s_m = s_m * c_ply + c_m * s_ply;
        c_m = c_next;
    }
    // The arrangement turns by ply_turn s since the section's cross-section; s grows by the
    // same amount each step, so the turn's cosine and sine advance by one fixed rotation.
    const float s0 = dot(section.offset, t), ds = dot(direction, t) * h;
    float c = std::cos(section.ply_turn * s0), sn = std::sin(section.ply_turn * s0);
    const float c_step = std::cos(section.ply_turn * ds), s_step = std::sin(section.ply_turn * ds);
    for (int j = 0; j <= steps; ++j) {
        const Vec3 p = section.offset + direction * (j * h);
        const Vec3 q = p - t * dot(p, t);  // in the cross-section through p, centre-line at 0
        if (j > 0) {
            const float c_next = c * c_step - sn * s_step;
            sn = sn * c_step + c * s_step;
            c = c_next;
        }
        const Vec3 out_s = out0 * c + around0 * sn, around_s = around0 * c - out0 * sn;
        const float qo = dot(q, out_s), qa = dot(q, around_s);
        for (int k = 0; k < plies; ++k) {
            // q in ply k's axes (outward, around): rotate by the ply's fixed phase offset;
            // f < 0 inside the ply's elliptical cut.
            const float a = qo * cos_k[k] + qa * sin_k[k] - d.ply_distance;
            const float b = (qa * cos_k[k] - qo * sin_k[k]) * inv_stretch;
            const float f = (a * a + b * b) * inv_radius2 - 1;
            if (j > 0) {
                const float f0 = previous[k];
                if (f0 < 0 && f < 0) inside[k] += h;
                else if (f0 < 0 || f < 0) inside[k] += h * (f0 < 0 ? f0 : f) / (f0 - f) * (f0 < 0 ? 1 : -1);
            }
            previous[k] = f;
        }
    }
}

// Exit distance of a straight tube of radius 1 around `tangent` from `offset` along `w`.
float straight_chord(Vec3 offset, Vec3 tangent, Vec3 w) {
    const Vec3 q = offset - tangent * dot(offset, tangent), v = w - tangent * dot(w, tangent);
    const float a = dot(v, v), b = dot(q, v), c = std::min(dot(q, q) - 1, 0.0f);
    return a > 1e-12f ? (-b + std::sqrt(std::max(0.0f, b * b - a * c))) / a : 4.0f;
}

}  // namespace

PlyCrossings cross_plies(const PlySection& section, const YarnDescription& d, int hit_ply, Vec3 direction,
                         float chord) {
    PlyCrossings out;
    const int plies = std::clamp(d.plies(), 1, kMaxCrossedPlies);
    if (!(chord > 0) || !(d.ply_radius > 0)) return out;  // also NaN
    float inside[kMaxCrossedPlies];
    march(section, d, hit_ply, direction, chord, inside);
    for (int k = 0; k < plies; ++k) {
        if (k == hit_ply) out.own = inside[k];
        else if (inside[k] > 0) out.other[out.others++] = inside[k];
    }
    out.yarn = &d;
    out.section = section;
    out.hit_ply = hit_ply;
    out.direction = direction;
    return out;
}

void add_spread(PlyCrossings& out) {
    if (out.spread_done || !out.yarn) return;
    out.spread_done = true;
    const YarnDescription& d = *out.yarn;
    const int plies = std::clamp(d.plies(), 1, kMaxCrossedPlies);
    if (!(d.ply_radius > 0)) return;
    // The ray tilted by kSpreadAngle toward +-u and +-v around it.
    Vec3 u = cross(out.direction, out.section.tangent);
    if (length_squared(u) < 1e-8f) u = cross(out.direction, out.section.hit_outward);
    u = normalize(u);
    const Vec3 v = cross(out.direction, u);
    const float c = std::cos(kSpreadAngle), sn = std::sin(kSpreadAngle);
    const Vec3 tilt[kSpreadDirections] = {u, -u, v, -v};
    float inside[kMaxCrossedPlies];
    for (int m = 0; m < kSpreadDirections; ++m) {
        const Vec3 w = out.direction * c + tilt[m] * sn;
        march(out.section, d, out.hit_ply, w, straight_chord(out.section.offset, out.section.tangent, w), inside);
        for (int k = 0; k < plies; ++k)
            if (k != out.hit_ply && inside[k] > 0) out.spread[m][out.spread_others[m]++] = inside[k];
    }
}

}  // namespace purl
