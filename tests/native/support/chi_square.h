// One chi-square goodness-of-fit harness for every scattering model: samples are binned on
// a (cos theta, phi) grid of the sphere and compared with the model's pdf integrated over
// each cell by adaptive quadrature. Cells expecting fewer than `min_expected` samples are
// pooled; failed samples form their own cell against the pdf's missing mass.
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "math/vec.h"

namespace purl::test {

struct Chi2Options {
    int cos_theta_bins = 20;   // over cos theta in [-1, 1]
    int phi_bins = 40;         // over phi in [0, 2 pi)
    int64_t samples = 400000;
    double min_expected = 5.0;
    double significance = 0.01;  // family-wise, over `test_count` runs (Sidak)
    int test_count = 1;
    uint64_t seed = 1;
};

struct Chi2Result {
    double statistic = 0, p_value = 0, threshold = 0;
    int dof = 0;
    double pdf_integral = 0;        // integral of the pdf over the sphere
    double success_fraction = 0;    // share of sample calls that returned a direction
    bool passed = false;
    std::string message;            // summary, with the worst cells when it fails
};

// u = (u_lobe, u1, u2) in [0, 1)^3; returns the sampled direction or nothing.
using DirectionSampler = std::function<std::optional<Vec3>(Vec3 u)>;
using DirectionDensity = std::function<double(Vec3 w)>;  // solid-angle density, 1/sr

Chi2Result chi2_test(const DirectionSampler& sample, const DirectionDensity& pdf, const Chi2Options& options);

// chi2_test of a model's sample(wo, u_lobe, {u1, u2}) against its pdf(wo, wi); also counts the
// samples whose record (f, pdf) is not what eval_pdf says at the sampled direction.
template <class Model>
Chi2Result chi2_model(const Model& m, Vec3 wo, const Chi2Options& options, int& record_mismatches) {
    return chi2_test(
        [&](Vec3 u) -> std::optional<Vec3> {
            const auto s = m.sample(wo, u.x, {u.y, u.z});
            if (!s) return std::nullopt;
            const auto ep = m.eval_pdf(wo, s->wi);
            if (std::fabs(ep.pdf - s->pdf) > 1e-5f * s->pdf ||
                std::fabs(average(ep.f) - average(s->f)) > 1e-5f * average(s->f) + 1e-9f)
                ++record_mismatches;
            return s->wi;
        },
        [&](Vec3 wi) { return double(m.pdf(wo, wi)); }, options);
}

// Integral of f over the part of the sphere with cos theta in [z0, z1], phi in [phi0, phi1],
// by adaptive Simpson quadrature in (cos theta, phi), to `tolerance` (absolute).
double integrate_sphere_patch(const DirectionDensity& f, double z0, double z1, double phi0, double phi1,
                              double tolerance);
// Integral of f over the whole sphere, cell by cell on the same grid as chi2_test.
double integrate_sphere(const DirectionDensity& f, int cos_theta_bins, int phi_bins, double tolerance);

// Upper regularised incomplete gamma Q(a, x): the chi-square survival function is Q(k/2, s/2).
double regularized_gamma_q(double a, double x);

}  // namespace purl::test
