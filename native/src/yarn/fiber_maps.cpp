#include "yarn/fiber_maps.h"

#include <algorithm>
#include <cmath>

#include "math/rng.h"
#include "yarn/ply_cross_section.h"

namespace purl {
namespace {

// The angle half-way (by t) from a to b along the shorter arc.
float lerp_angle(float a, float b, float t) {
    float d = b - a;
    // remainder(d, 2 pi) without the library call for |d| < 3 pi (map phases differ by less
    // than 2 pi): the same value, since d -+ 2 pi is exact there.
    if (std::fabs(d) < 3 * kPi) {
        if (d > kPi) d -= 2 * kPi;
        else if (d < -kPi) d += 2 * kPi;
    } else {
        d = std::remainder(d, 2 * kPi);
    }
    return a + d * t;
}

FiberSample blend(const FiberSample& a, const FiberSample& b, float t) {
    FiberSample s;
    s.normal_angle = a.normal_angle + (b.normal_angle - a.normal_angle) * t;
    s.fiber_phase = lerp_angle(a.fiber_phase, b.fiber_phase, t);
    s.fiber_distance = a.fiber_distance + (b.fiber_distance - a.fiber_distance) * t;
    s.shadowing = a.shadowing + (b.shadowing - a.shadowing) * t;
    return s;
}

struct RawSample {
    bool hit = false;
    float normal_angle = 0, fiber_phase = 0, fiber_distance = 0, occlusion = 0;
};

// The first circle met by the ray from outside toward the centre at `angle`, seen from there.
RawSample probe(const Circles2D& circles, float angle, float outer_radius) {
    RawSample s;
    const Vec2 radial(std::cos(angle), std::sin(angle));
    float t;
    const int k = circles.first_hit(radial * outer_radius, radial * -1.0f, 0.0f, t);
    if (k < 0) return s;
    const Vec2 point = radial * (outer_radius - t);
    const Vec2 c = circles.centres[k];
    const Vec2 normal = (point - c) * (1.0f / circles.radius);
    s.hit = true;
    s.normal_angle = std::atan2(radial.x * normal.y - radial.y * normal.x, dot(radial, normal));
    s.fiber_phase = wrap_angle(std::atan2(c.y, c.x));
    s.fiber_distance = length(c);
    s.occlusion = occlusion_2d(circles, point, normal, k);
    return s;
}

uint16_t to_unit16(float v) { return static_cast<uint16_t>(std::lround(clamp(v, 0.0f, 1.0f) * 65535.0f)); }

// The two map samples around `angle` in a map of n samples around the circle (samples sit at
// the middle of their bins), wrapping around, and the blend weight between them. Without the
// divisions of (floor + n) % n in the usual case (x from a wrapped angle is in [-0.5, n - 0.5)).
struct Neighbours {
    int i0, i1;
    float f;
};
Neighbours neighbours(float angle, int n) {
    const float x = wrap_angle(angle) * (n / (2 * kPi)) - 0.5f;
    const float floor_x = std::floor(x);
    const int k = static_cast<int>(floor_x) + n;
    const int i0 = k >= 0 && k < 2 * n ? (k >= n ? k - n : k) : k % n;
    return {i0, i0 + 1 == n ? 0 : i0 + 1, x - floor_x};
}

}  // namespace

FiberMaps::FiberMaps(const YarnDescription& d) {
    check_yarn_description(d, "", "yarn");
    variants_ = d.variants();
    resolution_ = d.resolution();
    std::vector<RawSample> raw(size_t(variants_) * resolution_);
    float max_occlusion = 0;
    for (int v = 0; v < variants_; ++v) {
        const Circles2D fibers = ply_fibers(d, 2 * kPi * v / variants_);
        for (int i = 0; i < resolution_; ++i) {
            RawSample& s = raw[size_t(v) * resolution_ + i];
            s = probe(fibers, 2 * kPi * (i + 0.5f) / resolution_, 1 + 2 * d.fiber_radius);
            if (s.hit) max_occlusion = std::max(max_occlusion, s.occlusion);
        }
    }
    fiber_.resize(raw.size());
    double g_sum = 0;
    for (size_t i = 0; i < raw.size(); ++i) {
        RawSample s = raw[i];
        if (!s.hit) {  // the ray crossed the whole ply between fibers: as deep as it gets
            s.fiber_phase = 2 * kPi * ((i % resolution_) + 0.5f) / resolution_;
            s.occlusion = max_occlusion;
        }
        const float g = max_occlusion > 0 ? 1 - s.occlusion / max_occlusion : 1.0f;
        g_sum += g;
        fiber_[i] = {static_cast<int16_t>(std::lround(clamp(s.normal_angle, -kPi, kPi) * (32767.0f / kPi))),
                     static_cast<uint16_t>(std::lround(s.fiber_phase * (65536.0f / (2 * kPi))) & 0xffff),
                     static_cast<uint16_t>(std::lround(clamp(s.fiber_distance, 0.0f, 1.99f) * 32768.0f)),
                     to_unit16(g)};
    }

    mean_fiber_shadowing_ = raw.empty() ? 1.0f : float(g_sum / double(raw.size()));

    // G_p: the plies alone, probed from the yarn surface inward.
    const Circles2D plies = yarn_plies(d);
    std::vector<RawSample> ply_raw(resolution_);
    float max_ply = 0;
    for (int i = 0; i < resolution_; ++i) {
        ply_raw[i] = probe(plies, 2 * kPi * (i + 0.5f) / resolution_, 1.0f + 1e-3f);
        if (ply_raw[i].hit) max_ply = std::max(max_ply, ply_raw[i].occlusion);
    }
    ply_.resize(resolution_);
    for (int i = 0; i < resolution_; ++i) {
        const float occlusion = ply_raw[i].hit ? ply_raw[i].occlusion : max_ply;
        ply_[i] = to_unit16(max_ply > 0 ? 1 - occlusion / max_ply : 1.0f);
    }
}

FiberSample FiberMaps::unpack(const Packed& p) const {
    FiberSample s;
    s.normal_angle = p.normal_angle * (kPi / 32767.0f);
    s.fiber_phase = p.fiber_phase * (2 * kPi / 65536.0f);
    s.fiber_distance = p.fiber_distance * (1.0f / 32768.0f);
    s.shadowing = p.shadowing * (1.0f / 65535.0f);
    return s;
}

FiberSample FiberMaps::sample(int variant, float angle) const {
    const Neighbours n = neighbours(angle, resolution_);
    const Packed* row = fiber_.data() + size_t(variant) * resolution_;
    return blend(unpack(row[n.i0]), unpack(row[n.i1]), n.f);
}

FiberSample FiberMaps::sample_pair(int a, int b, float angle, float w) const {
    // sample(a, angle) blended into sample(b, angle) by w, the angle wrapped once for both.
    const Neighbours n = neighbours(angle, resolution_);
    const Packed *row_a = fiber_.data() + size_t(a) * resolution_, *row_b = fiber_.data() + size_t(b) * resolution_;
    return blend(blend(unpack(row_a[n.i0]), unpack(row_a[n.i1]), n.f), blend(unpack(row_b[n.i0]), unpack(row_b[n.i1]), n.f), w);
}

int FiberMaps::variant_of(uint32_t key, int64_t cell) const {
    const uint64_t h = mix64((uint64_t(key) << 32) ^ static_cast<uint64_t>(cell) ^ 0x9e3779b97f4a7c15ULL);
    const uint64_t n = static_cast<uint64_t>(variants_);
    return static_cast<int>((n & (n - 1)) == 0 ? h & (n - 1) : h % n);  // a mask is the same modulo for 2^k
}

FiberSample FiberMaps::lookup(float angle, float cell_position, uint32_t key, uint32_t cells_per_loop) const {
    if (variants_ == 1) return sample(0, angle);
    const float floor_c = std::floor(cell_position);
    int64_t c0 = static_cast<int64_t>(floor_c), c1 = c0 + 1;
    if (cells_per_loop > 0) {
        const int64_t n = cells_per_loop;
        if (c0 >= 0 && c0 < n) {  // the usual case: the same as below, without 64-bit divisions
            c1 = c0 + 1 == n ? 0 : c0 + 1;
        } else {
            c0 = ((c0 % n) + n) % n;
            c1 = ((c1 % n) + n) % n;
        }
    }
    // Smoothstep across the whole cell: C1 along the ply, no visible switch.
    const float f = cell_position - floor_c, w = f * f * (3 - 2 * f);
    const int a = variant_of(key, c0), b = variant_of(key, c1);
    return a == b ? sample(a, angle) : sample_pair(a, b, angle, w);
}

float FiberMaps::ply_shadowing(float azimuth) const {
    const Neighbours n = neighbours(azimuth, resolution_);
    return (ply_[n.i0] * (1 - n.f) + ply_[n.i1] * n.f) * (1.0f / 65535.0f);
}

size_t FiberMaps::memory_bytes() const {
    return sizeof(*this) + fiber_.capacity() * sizeof(Packed) + ply_.capacity() * sizeof(uint16_t);
}

}  // namespace purl
