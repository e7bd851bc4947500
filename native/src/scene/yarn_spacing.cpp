#include "scene/yarn_spacing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include "math/bspline.h"

namespace purl {
namespace {

constexpr int kSamplesPerSegment = 4;
constexpr int kMaxDoublings = 12;
constexpr size_t kMaxQueries = 50000;  // samples whose neighbour is searched (all are searched among)
constexpr float kTurnBack = 3.14159265f;  // same curve counts when arc length > this x distance

struct Sample {
    Vec3 position;
    uint32_t curve;
    float arc;  // arc length from the curve's start (chord sum of the samples)
};

std::vector<Sample> sample_curves(const YarnCurves& curves, std::vector<float>& curve_length) {
    std::vector<Sample> samples;
    samples.reserve(curves.segment_count() * kSamplesPerSegment);
    curve_length.assign(curves.curve_count(), 0.0f);
    for (uint32_t c = 0; c < curves.curve_count(); ++c) {
        float arc = 0;
        bool first = true;
        Vec3 previous;
        for (uint32_t s = curves.segment_offsets[c]; s < curves.segment_offsets[c + 1]; ++s) {
            Vec3 cp[4];
            for (int k = 0; k < 4; ++k) cp[k] = curves.control_points[curves.segment_first[s] + k].xyz();
            for (int k = 0; k < kSamplesPerSegment; ++k) {
                const Vec3 p = bspline_point(cp, float(k) / kSamplesPerSegment);
                if (!first) arc += length(p - previous);
                samples.push_back({p, c, arc});
                previous = p;
                first = false;
            }
        }
        curve_length[c] = arc;
    }
    return samples;
}

float median_step(const std::vector<Sample>& samples) {
    std::vector<float> steps;
    for (size_t i = 1; i < samples.size(); ++i)
        if (samples[i].curve == samples[i - 1].curve) steps.push_back(samples[i].arc - samples[i - 1].arc);
    if (steps.empty()) return 0;
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    return steps[steps.size() / 2];
}

// Nearest distance from every sample to another yarn, infinity when none lies within `cell`.
std::vector<float> nearest_other_yarn(const std::vector<Sample>& samples, const std::vector<float>& curve_length,
                                      const std::vector<uint8_t>& closed, float cell) {
    const auto key = [](int64_t x, int64_t y, int64_t z) {
        return uint64_t(x & 0x1fffff) | (uint64_t(y & 0x1fffff) << 21) | (uint64_t(z & 0x1fffff) << 42);
    };
    const auto cell_of = [cell](float v) { return static_cast<int64_t>(std::floor(v / cell)); };
    std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
    grid.reserve(samples.size() / 4);
    for (uint32_t i = 0; i < samples.size(); ++i) {
        const Vec3& p = samples[i].position;
        grid[key(cell_of(p.x), cell_of(p.y), cell_of(p.z))].push_back(i);
    }
    // A median over a regular subset of kMaxQueries samples is as good and keeps large files fast.
    const size_t stride = std::max<size_t>(1, samples.size() / kMaxQueries);
    std::vector<float> nearest((samples.size() + stride - 1) / stride, std::numeric_limits<float>::infinity());
    for (size_t q = 0; q < nearest.size(); ++q) {
        const Sample& a = samples[q * stride];
        const int64_t cx = cell_of(a.position.x), cy = cell_of(a.position.y), cz = cell_of(a.position.z);
        float best = cell;  // anything farther may sit in a cell not searched
        for (int64_t dz = -1; dz <= 1; ++dz)
            for (int64_t dy = -1; dy <= 1; ++dy)
                for (int64_t dx = -1; dx <= 1; ++dx) {
                    const auto it = grid.find(key(cx + dx, cy + dy, cz + dz));
                    if (it == grid.end()) continue;
                    for (uint32_t j : it->second) {
                        const Sample& b = samples[j];
                        const float d = length(b.position - a.position);
                        if (!(d < best)) continue;
                        if (b.curve == a.curve) {
                            float along = std::fabs(b.arc - a.arc);
                            if (closed[a.curve]) along = std::min(along, curve_length[a.curve] - along);
                            if (along <= kTurnBack * d) continue;  // the same stretch of yarn
                        }
                        best = d;
                    }
                }
        if (best < cell) nearest[q] = best;
    }
    return nearest;
}

}  // namespace

YarnSpacing estimate_yarn_spacing(const YarnCurves& curves) {
    YarnSpacing result;
    std::vector<float> curve_length;
    const std::vector<Sample> samples = sample_curves(curves, curve_length);
    result.samples = samples.size();
    float cell = 4 * median_step(samples);
    if (samples.size() < 2 || !(cell > 0) || !std::isfinite(cell)) return result;
    for (int round = 0; round <= kMaxDoublings; ++round, cell *= 2) {
        std::vector<float> nearest = nearest_other_yarn(samples, curve_length, curves.closed, cell);
        const size_t found = std::count_if(nearest.begin(), nearest.end(), [](float d) { return std::isfinite(d); });
        result.found_share = float(found) / float(nearest.size());
        // The median is exact once more than half the samples found their neighbour.
        if (2 * found > nearest.size()) {
            std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
            result.radius = 0.5f * nearest[nearest.size() / 2];
            return result;
        }
    }
    return result;
}

}  // namespace purl
