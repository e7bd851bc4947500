// The normal distribution as the fiber BCSDF needs it: density, CDF, inverse CDF and a
// truncated normal with exact inverse-CDF sampling. Double precision throughout: the
// fiber lobes are as narrow as 1 degree and their tails are cut at +-90 degrees.
//
// (The public Mitsuba port of Khungurn et al. 2015 has a CDF that ignores mean and sigma and
// samples with erf where the inverse is needed; these functions are tested against both.)
#pragma once
#include <cmath>

namespace purl {

constexpr double kSqrt2 = 1.41421356237309504880;
constexpr double kSqrt2Pi = 2.50662827463100050242;

// Density of N(mean, sigma^2) at x.
inline double normal_pdf(double x, double mean, double sigma) {
    const double z = (x - mean) / sigma;
    return std::exp(-0.5 * z * z) / (sigma * kSqrt2Pi);
}

// Phi(z): the standard normal CDF (erfc keeps the lower tail accurate).
inline double standard_normal_cdf(double z) { return 0.5 * std::erfc(-z / kSqrt2); }

// Phi^-1(p) for p in (0, 1): Acklam's rational approximation (relative error 1.2e-9)
// polished by one Halley step on Phi, which brings it to double precision.
inline double inverse_standard_normal_cdf(double p) {
    if (!(p > 0)) return -INFINITY;
    if (!(p < 1)) return INFINITY;
    static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                               1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                               6.680131188771972e+01,  -1.328068155288572e+01};
    static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                               -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
    static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                               3.754408661907416e+00};
    constexpr double kLow = 0.02425;
    double x;
    if (p < kLow || p > 1 - kLow) {
        const double q = std::sqrt(-2 * std::log(p < kLow ? p : 1 - p));
        x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
        if (p > kLow) x = -x;
    } else {
        const double q = p - 0.5, r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
    }
    const double e = standard_normal_cdf(x) - p;
    const double u = e * kSqrt2Pi * std::exp(0.5 * x * x);
    return x - u / (1 + 0.5 * x * u);
}

// N(mean, sigma^2) restricted to [lo, hi] and renormalised; the mean must lie in [lo, hi]
// (true for every lobe of the fiber BCSDF), so neither CDF end is deep in a tail.
struct TruncatedNormal {
    double mean = 0, sigma = 1, lo = -1, hi = 1;

    double cdf_lo() const { return standard_normal_cdf((lo - mean) / sigma); }
    double cdf_hi() const { return standard_normal_cdf((hi - mean) / sigma); }
    // Probability mass of the untruncated normal inside [lo, hi], as 1 minus both tails (a
    // tail beyond 9 sigma is below 1e-18 and skipped: most narrow lobes need no erfc at all).
    double mass() const {
        const double a = (lo - mean) / sigma, b = (hi - mean) / sigma;
        const double below = a < -9 ? 0.0 : standard_normal_cdf(a), above = b > 9 ? 0.0 : standard_normal_cdf(-b);
        return 1 - below - above;
    }
    double pdf(double x) const {
        if (x < lo || x > hi) return 0.0;
        const double m = mass();
        return m > 0 ? normal_pdf(x, mean, sigma) / m : 0.0;
    }
    // Inverse-CDF sample for u in [0, 1).
    double sample(double u) const {
        const double a = cdf_lo(), b = cdf_hi();
        const double x = mean + sigma * inverse_standard_normal_cdf(a + u * (b - a));
        return std::fmin(hi, std::fmax(lo, x));
    }
};

}  // namespace purl
