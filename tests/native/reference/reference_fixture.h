// Yarn curves shared by the explicit-reference tests: a straight yarn, a wavy open yarn, a
// closed loop, and the first curves of the glove (real knit data, C1 Catmull-Rom segments).
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "scene/bcc.h"
#include "scene/scene.h"

#include "support/shared_data.h"

namespace purl::test {

inline YarnCurves straight_yarn(float radius, float length) {
    std::vector<Vec4> p;
    const int n = 12;
    for (int i = 0; i < n; ++i) p.emplace_back(0.0f, 0.0f, length * (float(i) / (n - 1) - 0.5f), radius);
    YarnCurves c;
    c.add_curve(p.data(), p.size(), false);
    return c;
}

// An open yarn that bends both ways (radius of curvature down to ~3 yarn radii).
inline YarnCurves wavy_yarn(float radius) {
    std::vector<Vec4> p;
    for (int i = 0; i < 24; ++i) {
        const float x = 0.4f * i;
        p.emplace_back(x * radius * 4, radius * 3 * std::sin(0.9f * x), radius * 1.5f * std::cos(0.5f * x), radius);
    }
    YarnCurves c;
    c.add_curve(p.data(), p.size(), false);
    return c;
}

// A closed circular loop of the given radius (in yarn radii), in the xy plane.
inline YarnCurves loop_yarn(float radius, float loop_radius) {
    std::vector<Vec4> p;
    const int n = 16;
    for (int i = 0; i < n; ++i) {
        const float a = 2 * kPi * i / n;
        p.emplace_back(loop_radius * radius * std::cos(a), loop_radius * radius * std::sin(a), 0.0f, radius);
    }
    YarnCurves c;
    c.add_curve(p.data(), p.size(), true);
    return c;
}

// The first `count` loops of glove.bcc at yarn radius 0.1 (file units).
inline YarnCurves glove_yarns(size_t count) {
    const YarnCurves all = load_bcc(shared_data_path("glove.bcc"), 0.1f);
    YarnCurves c;
    for (size_t k = 0; k < count && k < all.curve_count(); ++k) {
        const uint32_t s0 = all.segment_offsets[k], s1 = all.segment_offsets[k + 1];
        std::vector<Vec4> pts;
        for (uint32_t s = s0; s < s1; ++s)
            for (int i = 0; i < 4; ++i) pts.push_back(all.control_points[all.segment_first[s] + i]);
        c.add_curve_segments(pts.data(), s1 - s0, all.closed[k] != 0, all.curve_ids[k]);
    }
    return c;
}

inline YarnSetDesc bysdf_set(YarnCurves curves, const YarnDescription& d, const std::string& name = "yarn") {
    YarnSetDesc s;
    s.name = name;
    s.curves = std::move(curves);
    s.material.model = MaterialModel::Bysdf;
    s.material.yarn = d;
    return s;
}

}  // namespace purl::test
