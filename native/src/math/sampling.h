// Sampling routines as Sample / Pdf pairs (solid-angle or area measure as named).
#pragma once
#include <vector>

#include "math/vec.h"

namespace purl {

inline Vec2 sample_uniform_disk_concentric(Vec2 u) {
    const float a = 2 * u.x - 1, b = 2 * u.y - 1;
    if (a == 0 && b == 0) return {0, 0};
    float r, phi;
    if (std::fabs(a) > std::fabs(b)) {
        r = a;
        phi = (kPi / 4) * (b / a);
    } else {
        r = b;
        phi = kPi / 2 - (kPi / 4) * (a / b);
    }
    return {r * std::cos(phi), r * std::sin(phi)};
}

inline Vec3 sample_cosine_hemisphere(Vec2 u) {
    const Vec2 d = sample_uniform_disk_concentric(u);
    return {d.x, d.y, safe_sqrt(1 - d.x * d.x - d.y * d.y)};
}
inline float cosine_hemisphere_pdf(float cos_theta) { return std::max(0.0f, cos_theta) * kInvPi; }

inline Vec3 sample_uniform_sphere(Vec2 u) {
    const float z = 1 - 2 * u.x;
    const float r = safe_sqrt(1 - z * z), phi = 2 * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniform_sphere_pdf() { return kInv4Pi; }

// Directions within angle acos(cos_max) of +z, uniform in solid angle.
inline Vec3 sample_uniform_cone(Vec2 u, float cos_max) {
    const float cos_t = (1 - u.x) + u.x * cos_max;
    const float sin_t = safe_sqrt(1 - cos_t * cos_t), phi = 2 * kPi * u.y;
    return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
}
inline float uniform_cone_pdf(float cos_max) { return 1.0f / (2 * kPi * (1 - cos_max)); }

inline float power_heuristic(float pdf_a, float pdf_b) {
    const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
    return a + b > 0 ? a / (a + b) : 0.0f;
}

// Piecewise-constant 1D distribution over [0, 1) (for importance-sampling images).
class Distribution1D {
public:
    Distribution1D() = default;
    explicit Distribution1D(const float* weights, size_t n) : func_(weights, weights + n), cdf_(n + 1, 0.0f) {
        double total = 0;
        for (size_t i = 0; i < n; ++i) {
            total += std::max(0.0f, func_[i]);
            cdf_[i + 1] = static_cast<float>(total);
        }
        integral_ = static_cast<float>(total / n);
        if (total > 0)
            for (float& c : cdf_) c = static_cast<float>(c / total);
        else
            for (size_t i = 0; i <= n; ++i) cdf_[i] = static_cast<float>(i) / n;
    }
    size_t size() const { return func_.size(); }
    float integral() const { return integral_; }
    // Returns x in [0, 1); `pdf` is the density in x, `index` the bin.
    float sample(float u, float& pdf, size_t& index) const {
        size_t lo = 0, hi = func_.size();
        while (lo + 1 < hi) {  // last bin whose cdf <= u
            const size_t mid = (lo + hi) / 2;
            if (cdf_[mid] <= u) lo = mid; else hi = mid;
        }
        index = lo;
        const float width = cdf_[lo + 1] - cdf_[lo];
        const float du = width > 0 ? (u - cdf_[lo]) / width : 0.5f;
        pdf = pdf_of_bin(lo);
        return std::min((lo + clamp(du, 0.0f, 1.0f)) / func_.size(), 0.99999994f);
    }
    float pdf_of_bin(size_t i) const {
        return integral_ > 0 ? std::max(0.0f, func_[i]) / integral_ : 1.0f;
    }

private:
    std::vector<float> func_, cdf_;
    float integral_ = 0;
};

// Piecewise-constant 2D distribution over [0,1)^2: rows (v) by marginal, then column (u).
class Distribution2D {
public:
    Distribution2D() = default;
    Distribution2D(const float* weights, size_t width, size_t height) {
        std::vector<float> row_integrals(height);
        rows_.reserve(height);
        for (size_t y = 0; y < height; ++y) {
            rows_.emplace_back(weights + y * width, width);
            row_integrals[y] = rows_.back().integral();
        }
        marginal_ = Distribution1D(row_integrals.data(), height);
    }
    Vec2 sample(Vec2 u, float& pdf) const {
        float pdf_v, pdf_u;
        size_t row, col;
        const float v = marginal_.sample(u.y, pdf_v, row);
        const float x = rows_[row].sample(u.x, pdf_u, col);
        pdf = pdf_u * pdf_v;
        return {x, v};
    }
    float pdf(Vec2 p) const {
        const size_t row = std::min(static_cast<size_t>(p.y * rows_.size()), rows_.size() - 1);
        const Distribution1D& r = rows_[row];
        const size_t col = std::min(static_cast<size_t>(p.x * r.size()), r.size() - 1);
        return marginal_.integral() > 0 ? std::max(0.0f, r.pdf_of_bin(col) * r.integral()) / marginal_.integral()
                                        : 1.0f;
    }

private:
    std::vector<Distribution1D> rows_;
    Distribution1D marginal_;
};

}  // namespace purl
