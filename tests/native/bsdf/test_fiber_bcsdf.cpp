// The fiber BCSDF of Khungurn et al. 2015 (fiber-based reference): the normal-distribution
// helpers against the two bugs of the public Mitsuba port, the cos^2 normalisation, chi-square
// of sample against pdf, white furnace (quadrature and importance sampling), frame
// independence and a fuzz for NaN/negative values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "base/input_error.h"
#include "bsdf/fiber_bcsdf.h"
#include "bsdf/gaussian.h"
#include "math/rng.h"
#include "support/chi_square.h"

namespace purl::test {
namespace {

constexpr double kHalfPi = 1.5707963267948966;

float uniform(Rng& rng, float lo, float hi) { return lo + (hi - lo) * rng.next_float(); }

// A direction with longitudinal angle theta (from the normal plane of the fiber axis +x) and
// azimuth phi around it.
Vec3 fiber_direction(double theta, double phi) {
    return Vec3(float(std::sin(theta)), float(std::cos(theta) * std::cos(phi)), float(std::cos(theta) * std::sin(phi)));
}

// Largest gap between the empirical CDF of `xs` and `cdf` (Kolmogorov-Smirnov statistic).
template <class Cdf>
double ks_statistic(std::vector<double> xs, const Cdf& cdf) {
    std::sort(xs.begin(), xs.end());
    double d = 0;
    const double n = double(xs.size());
    for (size_t i = 0; i < xs.size(); ++i) {
        const double c = cdf(xs[i]);
        d = std::max(d, std::max(std::fabs(c - i / n), std::fabs(c - (i + 1) / n)));
    }
    return d;
}

TEST(Gaussian, InverseCdfIsTheInverseToDoublePrecision) {
    for (double p : {1e-12, 1e-6, 0.001, 0.02, 0.0243, 0.1, 0.5, 0.77, 0.975, 0.999, 1 - 1e-9}) {
        const double x = inverse_standard_normal_cdf(p);
        EXPECT_NEAR(standard_normal_cdf(x), p, 1e-14 + 1e-12 * p) << p;
    }
    EXPECT_NEAR(inverse_standard_normal_cdf(0.975), 1.959963984540054, 1e-12);
}

TEST(Gaussian, TruncatedNormalSamplesFollowTheirCdfAndThePortsBugsWouldNot) {
    // KS at 1 %: reject when D > 1.63 / sqrt(n).
    const int n = 20000;
    const double reject = 1.63 / std::sqrt(double(n));
    const TruncatedNormal t{-1.2, 0.4, -kHalfPi, kHalfPi};
    auto cdf = [&](double x) { return (standard_normal_cdf((x - t.mean) / t.sigma) - t.cdf_lo()) / t.mass(); };
    std::vector<double> ours, erf_bug, cdf_bug;
    Rng rng(3);
    for (int i = 0; i < n; ++i) {
        const double u = rng.next_float();
        ours.push_back(t.sample(u));
        // Port bug 1: erf where erfinv belongs (then rejected into a uniform when outside).
        const double g = t.mean + t.sigma * kSqrt2 * std::erf(2 * u - 1);
        erf_bug.push_back(g > t.lo && g < t.hi ? g : t.lo + (t.hi - t.lo) * rng.next_float());
        // Port bug 2: a CDF that ignores mean and sigma, used to place u in [cdf(lo), cdf(hi)].
        const double a = standard_normal_cdf(t.lo), b = standard_normal_cdf(t.hi);
        cdf_bug.push_back(std::clamp(t.mean + t.sigma * inverse_standard_normal_cdf(a + u * (b - a)), t.lo, t.hi));
    }
    EXPECT_LT(ks_statistic(ours, cdf), reject);
    EXPECT_GT(ks_statistic(erf_bug, cdf), reject);
    EXPECT_GT(ks_statistic(cdf_bug, cdf), reject);
    // The density integrates to 1 on its interval.
    double sum = 0;
    const int m = 20000;
    for (int i = 0; i < m; ++i) sum += t.pdf(t.lo + (t.hi - t.lo) * (i + 0.5) / m) * (t.hi - t.lo) / m;
    EXPECT_NEAR(sum, 1.0, 1e-6);
}

TEST(FiberBcsdf, LongitudinalLobeIsCosSquaredNormalised) {
    // Integral of M(theta_i | theta_o) cos^2 theta_i over [-pi/2, pi/2] is 1 for every viewer,
    // including grazing ones where half the Gaussian is cut off.
    for (float width_deg : {0.5f, 1.0f, 7.238f, 27.197f, 60.0f}) {
        const FiberLongitudinalLobe lobe(width_deg * kPi / 180);
        for (float theta_o_deg : {0.0f, 30.0f, -60.0f, 85.0f, 89.5f, -89.9f}) {
            const float theta_o = theta_o_deg * kPi / 180;
            const int n = 100000;
            double sum = 0;
            for (int i = 0; i < n; ++i) {
                const double x = -kHalfPi + kPi * (i + 0.5) / n, c = std::cos(x);
                sum += lobe.eval(float(x), theta_o) * c * c;
            }
            sum *= kPi / n;
            EXPECT_NEAR(sum, 1.0, 2e-3) << "width " << width_deg << " theta_o " << theta_o_deg;
        }
    }
}

// Random parameters inside the table's ranges, widths where a 20 x 40 grid resolves the lobes.
FiberBcsdfParams random_fiber_params(Rng& rng) {
    FiberBcsdfParams p;
    p.reflection_color = {rng.next_float(), rng.next_float(), rng.next_float()};
    p.transmission_color = {rng.next_float(), rng.next_float(), rng.next_float()};
    p.reflection_width = uniform(rng, 3, 40);
    p.transmission_width = uniform(rng, 3, 40);
    p.transmission_azimuthal_width = uniform(rng, 8, 150);
    return p;
}

// The chi-square harness bins (cos theta, phi) about its z axis and integrates the pdf over
// d omega = d cos theta d phi. Hand it (z = 2 theta / pi, phi) of the fiber's own angles instead,
// with the density carried over (pdf cos theta pi / 2): a change of variables, so the test is
// the same, but the solid-angle pdf's integrable 1/cos theta peak at the fiber poles (where a
// truncated lobe keeps a finite density per radian) becomes a bounded density.
Vec3 to_harness(Vec3 w) {
    const double z = 2 * std::asin(std::clamp(double(w.x), -1.0, 1.0)) / kPi, s = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = std::atan2(double(w.z), double(w.y));
    return Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z));
}
double harness_density(const FiberBcsdf& m, Vec3 wo, Vec3 h) {
    const double theta = double(h.z) * kHalfPi;
    const Vec3 wi = fiber_direction(theta, std::atan2(double(h.y), double(h.x)));
    return double(m.pdf(wo, wi)) * std::cos(theta) * kHalfPi;
}

Chi2Result fiber_chi2(const FiberBcsdf& m, Vec3 wo, int runs, uint64_t seed, int* record_mismatches) {
    Chi2Options o;
    o.test_count = runs;
    o.seed = seed;
    o.samples = 100000;
    return chi2_test(
        [&](Vec3 u) -> std::optional<Vec3> {
            const auto s = m.sample(wo, u.x, {u.y, u.z});
            if (!s) return std::nullopt;
            const float pdf = m.pdf(wo, s->wi);
            const Vec3 f = m.eval(wo, s->wi);
            if (std::fabs(pdf - s->pdf) > 1e-5f * s->pdf || std::fabs(average(f) - average(s->f)) > 1e-5f * average(f))
                ++*record_mismatches;
            return to_harness(s->wi);
        },
        [&](Vec3 h) { return harness_density(m, wo, h); }, o);
}

TEST(FiberBcsdf, ChiSquareOverRandomConfigurationsAndPresets) {
    const std::vector<std::string> presets = fiber_bcsdf_preset_names();
    constexpr int kRandom = 6;
    const int runs = kRandom + int(presets.size());
    Rng rng(2015);
    int failures = 0, run = 0;
    auto check = [&](const FiberBcsdfParams& p, Vec3 wo, const std::string& label) {
        const FiberBcsdf m(p);
        int mismatches = 0;
        const Chi2Result r = fiber_chi2(m, wo, runs, 100 + run, &mismatches);
        ++run;
        EXPECT_EQ(mismatches, 0) << label;
        if (!r.passed) ++failures;
        EXPECT_TRUE(r.passed) << label << " wo " << wo.x << " " << wo.y << " " << wo.z << "\n" << r.message;
    };
    for (int k = 0; k < kRandom; ++k) {
        const float theta = k < 3 ? std::vector<float>{0.0f, 1.55f, -1.5f}[k] : uniform(rng, -1.5f, 1.5f);
        check(random_fiber_params(rng), fiber_direction(theta, uniform(rng, 0, 2 * kPi)), "random " + std::to_string(k));
    }
    // The published fits, sharp lobes included (1 degree: 40 slices of cos theta still see them
    // through the adaptive quadrature of each cell).
    for (size_t k = 0; k < presets.size(); ++k)
        check(fiber_bcsdf_preset(presets[k]), fiber_direction(k % 2 ? -1.2 : 0.3, 0.7), presets[k]);
    std::printf("fiber BCSDF chi-square: %d of %d runs rejected at Sidak-corrected 1%%\n", failures, runs);
}

// Directional albedo: integral of S cos theta_i over the sphere, by Simpson in the fiber's own
// (theta, phi) so that narrow lobes are resolved (no sample or pdf involved).
double albedo_quadrature(const FiberBcsdf& m, Vec3 wo) {
    const int nt = 3000, np = 90;  // even: 0.06 degree and 4 degree steps
    double sum = 0;
    for (int i = 0; i <= nt; ++i) {
        const double theta = -kHalfPi + kPi * i / nt;
        const double wt = (i == 0 || i == nt) ? 1 : (i % 2 ? 4 : 2);
        double row = 0;
        for (int j = 0; j <= np; ++j) {
            const double phi = 2 * kPi * j / np;
            const double wp = (j == 0 || j == np) ? 1 : (j % 2 ? 4 : 2);
            row += wp * average(m.scattering(wo, fiber_direction(theta, phi)));
        }
        sum += wt * row * std::cos(theta);
    }
    return sum * (kPi / nt / 3) * (2 * kPi / np / 3);
}

double albedo_sampled(const FiberBcsdf& m, Vec3 wo, int n, uint64_t seed, double* standard_error) {
    Rng u(seed);
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        const auto s = m.sample(wo, u.next_float(), {u.next_float(), u.next_float()});
        const double w = s ? double(average(s->weight())) : 0.0;
        sum += w;
        sum2 += w * w;
    }
    const double mean = sum / n;
    *standard_error = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
    return mean;
}

TEST(FiberBcsdf, WhiteFurnaceAndAlbedoMatchTheModel) {
    // With A_TT = 1 every viewer gets all its light back (R takes F, TT the rest); in general
    // the albedo is mean(F + (1 - F) A_TT), whatever the widths.
    std::printf(" preset      theta_o   expected  quadrature  sampled (+-)\n");
    for (const std::string& name : fiber_bcsdf_preset_names()) {
        FiberBcsdfParams p = fiber_bcsdf_preset(name);
        for (int white = 0; white < 2; ++white) {
            if (white) p.transmission_color = Vec3(1.0f);
            const FiberBcsdf m(p);
            for (float deg : {0.0f, 45.0f, 80.0f, 89.0f}) {
                if (!white && (deg == 0.0f || deg == 89.0f)) continue;
                const Vec3 wo = fiber_direction(deg * kPi / 180, 1.1);
                const float cos_o = std::cos(deg * kPi / 180), x = 1 - cos_o, x5 = x * x * x * x * x;
                const Vec3 f = p.reflection_color + (Vec3(1.0f) - p.reflection_color) * x5;
                const double expected = average(f + (Vec3(1.0f) - f) * p.transmission_color);
                const double q = albedo_quadrature(m, wo);
                double se;
                const double s = albedo_sampled(m, wo, 30000, 7 + int(deg), &se);
                if (white) std::printf(" %-10s  %5.1f    %.4f    %.4f     %.4f (%.4f)\n", name.c_str(), deg, expected, q, s, se);
                EXPECT_NEAR(q, expected, 3e-3) << name << " theta_o " << deg;
                EXPECT_NEAR(s, q, 4 * se + 1e-3) << name << " theta_o " << deg;
                if (white) {
                    EXPECT_NEAR(q, 1.0, 3e-3);
                }
            }
        }
    }
}

TEST(FiberBcsdf, LightDoesNotDependOnTheFrameAroundTheFiber) {
    // eval |wi.z| must be the same whichever normal the shading frame picks around the fiber.
    const FiberBcsdf m(fiber_bcsdf_preset("polyester"));
    Rng rng(9);
    for (int k = 0; k < 1000; ++k) {
        const Vec3 wo = fiber_direction(uniform(rng, -1.4f, 1.4f), uniform(rng, 0, 2 * kPi));
        const Vec3 wi = fiber_direction(uniform(rng, -1.4f, 1.4f), uniform(rng, 0, 2 * kPi));
        const float turn = uniform(rng, 0, 2 * kPi), c = std::cos(turn), s = std::sin(turn);
        auto rotate = [&](Vec3 w) { return Vec3(w.x, c * w.y - s * w.z, s * w.y + c * w.z); };
        const Vec3 a = m.eval(wo, wi) * std::fabs(wi.z);
        const Vec3 b = m.eval(rotate(wo), rotate(wi)) * std::fabs(rotate(wi).z);
        if (std::fabs(wi.z) < 1e-3f || std::fabs(rotate(wi).z) < 1e-3f) continue;
        EXPECT_NEAR(average(a), average(b), 1e-4f * average(a) + 1e-7f) << k;
        EXPECT_NEAR(m.pdf(wo, wi), m.pdf(rotate(wo), rotate(wi)), 1e-4f * m.pdf(wo, wi));
    }
}

TEST(FiberBcsdf, TransmissionGoesForwardAndReflectionAllAround) {
    // TT concentrates opposite the viewer's azimuth; R is uniform in azimuth.
    const FiberBcsdf m(fiber_bcsdf_preset("fleece"));
    const Vec3 wo = fiber_direction(0.2, 0.0);
    const Vec3 forward = fiber_direction(-0.2, kPi), side = fiber_direction(-0.2, kPi / 2), back = fiber_direction(-0.2, 0.1);
    EXPECT_GT(average(m.scattering(wo, forward)), 5 * average(m.scattering(wo, side)));
    // Fleece reflects little: away from the forward lobe only R (uniform azimuth) remains.
    const FiberBcsdfParams only_r = [] {
        FiberBcsdfParams p = fiber_bcsdf_preset("fleece");
        p.transmission_color = Vec3(0.0f);
        return p;
    }();
    const FiberBcsdf r(only_r);
    EXPECT_NEAR(average(r.scattering(wo, side)), average(r.scattering(wo, back)), 1e-6f);
    EXPECT_NEAR(average(r.scattering(wo, side)), average(r.scattering(wo, forward)), 1e-6f);
    Rng rng(4);
    int transmitted = 0, forward_half = 0;
    for (int i = 0; i < 10000; ++i) {
        const auto s = m.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
        ASSERT_TRUE(s.has_value());
        if (s->lobe != FiberBcsdf::kTransmission) continue;
        ++transmitted;
        EXPECT_TRUE(s->is_transmission());
        if (s->wi.y < 0) ++forward_half;  // wo sits at phi = 0 (+y)
    }
    EXPECT_GT(forward_half, 0.95 * transmitted);
}

TEST(FiberBcsdf, FuzzNeverGivesNanInfOrNegative) {
    Rng rng(123);
    const FiberBcsdf models[] = {FiberBcsdf(fiber_bcsdf_preset("silk")), FiberBcsdf(fiber_bcsdf_preset("cotton")),
                                 FiberBcsdf(random_fiber_params(rng))};
    auto odd_direction = [&](int k) -> Vec3 {
        switch (k % 6) {
            case 0: return {1, 0, 0};                      // along the fiber
            case 1: return {-1, 0, 0};
            case 2: return {0, 1, 0};                      // in the frame's tangent plane
            case 3: return Vec3(rng.next_float() * 5 - 2.5f, rng.next_float() - 0.5f, rng.next_float() * 1e-7f);  // not unit
            case 4: return {0.9999999f, 1e-4f, 1e-4f};
            default: return fiber_direction(uniform(rng, -kHalfPi, kHalfPi), uniform(rng, -10, 10));
        }
    };
    int bad = 0;
    for (int i = 0; i < 300000; ++i) {
        const FiberBcsdf& m = models[i % 3];
        const Vec3 wo = odd_direction(i), wi = odd_direction(i / 7);
        const Vec3 f = m.eval(wo, wi);
        const float pdf = m.pdf(wo, wi);
        if (!is_finite(f) || f.x < 0 || f.y < 0 || f.z < 0 || !std::isfinite(pdf) || pdf < 0) ++bad;
        const auto s = m.sample(wo, rng.next_float(), {rng.next_float(), rng.next_float()});
        if (s && (!is_finite(s->f) || !is_finite(s->wi) || !(s->pdf > 0) || !std::isfinite(s->pdf))) ++bad;
    }
    EXPECT_EQ(bad, 0);
}

TEST(FiberBcsdfParams, PresetsAreInRangeAndUnknownNamesAreRejected) {
    for (const std::string& name : fiber_bcsdf_preset_names())
        EXPECT_NO_THROW(check_fiber_bcsdf_params(fiber_bcsdf_preset(name), "f", "fiber")) << name;
    EXPECT_THROW(fiber_bcsdf_preset("denim"), InputError);
    FiberBcsdfParams p = default_fiber_bcsdf_params();
    p.reflection_width = 0.1f;
    EXPECT_THROW(check_fiber_bcsdf_params(p, "f", "fiber"), InputError);
    p = default_fiber_bcsdf_params();
    p.transmission_color.y = std::nanf("");
    EXPECT_THROW(check_fiber_bcsdf_params(p, "f", "fiber"), InputError);
}

}  // namespace
}  // namespace purl::test
