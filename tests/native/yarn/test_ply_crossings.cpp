// cross_plies against brute force on a straight yarn: a fine march along the ray, each point
// tested against every ply's true helix tube (closest approach to the helix centre-line).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "math/rng.h"
#include "yarn/ply_crossings.h"
#include "yarn/yarn_tube.h"

namespace purl {
namespace {

struct StraightYarn {
    std::vector<Vec4> points;
    CurveFrames frames;
    StraightYarn() : points(make()), frames(CurveView::chain(points.data(), 40, false)) {}
    static std::vector<Vec4> make() {
        std::vector<Vec4> p;
        for (int i = 0; i < 40; ++i) p.emplace_back(0.0f, 0.0f, float(i), 1.0f);
        return p;
    }
    CentrelineProjection section(float z) const {
        return project_to_centreline(frames, Vec3(0, 0, z), uint32_t(z), 0.5f);
    }
    // The frame is the same all along a straight yarn: shift one evaluated point.
    CurvePoint at(float z) const {
        static const CurvePoint base = section(20.0f).point;
        CurvePoint c = base;
        c.position.z = z;
        c.arc_length = base.arc_length + (z - base.position.z);
        return c;
    }
};

YarnDescription layout(int plies) {
    YarnDescription d = yarn_preset("prototype");
    d.ply_count = float(plies);
    const float s = std::sin(kPi / plies);
    d.ply_radius = s / (1 + s);
    d.ply_distance = 1 - d.ply_radius;
    return d;
}

// Distance from p to ply k's centre-line: the closest of many helix points around p's height.
float helix_distance(const StraightYarn& y, const YarnDescription& d, const YarnTwist& tw, int ply, Vec3 p) {
    float best = 1e30f;
    for (int i = -60; i <= 60; ++i) {
        const float z = p.z + i * (0.6f / 60);
        best = std::min(best, length(p - ply_centre(y.at(z), d, tw, ply).position));
    }
    return best;
}

TEST(PlyCrossings, MatchTheHelixTubesOnAStraightYarn) {
    const StraightYarn y;
    Rng rng(5);
    int rays = 0, count_mismatch = 0;
    double length_error = 0, length_total = 0;
    for (int plies : {2, 3, 6}) {
        const YarnDescription d = layout(plies);
        const YarnTwist tw = yarn_twist(y.frames, d);
        for (int n = 0; n < 40; ++n) {
            // A point on ply `hit`'s surface facing outward-ish, a direction into the yarn.
            const int hit = int(rng.next_float() * plies) % plies;
            const CentrelineProjection cs = y.section(15 + 10 * rng.next_float());
            const CurvePoint& c = cs.point;
            const PlyCentre pc = ply_centre(c, d, tw, hit);
            const float a = (rng.next_float() - 0.5f) * 2.0f;
            const Vec3 around = cross(c.tangent, pc.outward);
            const Vec3 x = pc.position + (pc.outward * std::cos(a) + around * std::sin(a)) * pc.radius;
            Vec3 dir = normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
            const float chord = tube_chord_length(y.frames, cs.segment, cs.t, x, dir);
            const PlyCrossings got = cross_plies(ply_section(c, d, tw, hit, x), d, hit, dir, chord);
            // The same from a cross-section a little along the yarn (the hit need not lie in it).
            const PlyCrossings shifted =
                cross_plies(ply_section(y.at(c.position.z + 0.3f), d, tw, hit, x), d, hit, dir, chord);
            EXPECT_EQ(shifted.others, got.others);
            EXPECT_NEAR(shifted.own, got.own, 1e-3f);
            // Brute force: 600 steps, every ply's true tube.
            std::vector<float> inside(plies, 0.0f);
            const int steps = 600;
            for (int j = 0; j < steps; ++j) {
                const Vec3 p = x + dir * ((j + 0.5f) * chord / steps);
                for (int k = 0; k < plies; ++k)
                    if (helix_distance(y, d, tw, k, p) < pc.radius) inside[k] += chord / steps;
            }
            std::vector<float> others;
            for (int k = 0; k < plies; ++k)
                if (k != hit && inside[k] > 0.02f) others.push_back(inside[k]);
            ++rays;
            if (int(others.size()) != got.others) ++count_mismatch;
            float sum_true = inside[hit], sum_got = got.own;
            for (float v : others) sum_true += v;
            for (int k = 0; k < got.others; ++k) sum_got += got.other[k];
            length_error += std::fabs(sum_true - sum_got);
            length_total += sum_true;
        }
    }
    std::printf(" %d rays: %d with another count of plies crossed, length inside plies off by %.1f %%\n", rays,
                count_mismatch, 100 * length_error / length_total);
    EXPECT_LE(count_mismatch, rays / 20);
    EXPECT_LT(length_error, 0.04 * length_total);
}

TEST(PlyCrossings, NothingToCrossWithoutAChord) {
    const YarnDescription d = layout(3);
    PlySection s;
    s.tangent = Vec3(0, 0, 1);
    s.hit_outward = Vec3(1, 0, 0);
    s.offset = Vec3(d.ply_distance + d.ply_radius, 0, 0);
    const PlyCrossings none = cross_plies(s, d, 0, Vec3(1, 0, 0), 0.0f);
    EXPECT_EQ(none.others, 0);
    EXPECT_EQ(none.own, 0.0f);
    const PlyCrossings nan = cross_plies(s, d, 0, Vec3(-1, 0, 0), std::nanf(""));
    EXPECT_EQ(nan.others, 0);
    // Straight through the centre: the hit ply's diameter, the opposite plies' too.
    const PlyCrossings through = cross_plies(s, d, 0, Vec3(-1, 0, 0), 2.0f);
    EXPECT_NEAR(through.own, 2 * d.ply_radius, 0.1f);
}

}  // namespace
}  // namespace purl
