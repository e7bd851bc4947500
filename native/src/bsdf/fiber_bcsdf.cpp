#include "bsdf/fiber_bcsdf.h"

#include <algorithm>
#include <cmath>

#include "bsdf/gaussian.h"

namespace purl {
namespace {

constexpr double kHalfPi = 1.57079632679489661923;
constexpr float kMinCos = 1e-6f;  // directions closer than this to a pole or plane carry no energy
constexpr float kDegree = kPi / 180.0f;

Vec3 clamp01(Vec3 c) {
    return {clamp(c.x, 0.0f, 1.0f), clamp(c.y, 0.0f, 1.0f), clamp(c.z, 0.0f, 1.0f)};
}
// Width in degrees -> radians, kept inside the table's range (also for NaN).
double width_rad(float degrees, float hi) {
    const float d = degrees >= 0.5f ? std::min(degrees, hi) : 0.5f;
    return double(d) * kDegree;
}

// Longitudinal angle from the normal plane of the fiber (+x), and the direction's component
// across the fiber (y, z), which carries its azimuth.
struct FiberAngles {
    float sin_theta, cos_theta, theta, y, z;
};
FiberAngles angles(Vec3 w) {
    const float len = length(w);
    if (len > 0 && std::isfinite(len)) w = w / len;
    FiberAngles a;
    a.sin_theta = clamp(w.x, -1.0f, 1.0f);
    a.cos_theta = safe_sqrt(1 - a.sin_theta * a.sin_theta);
    a.theta = std::asin(a.sin_theta);
    a.y = w.y;
    a.z = w.z;
    return a;
}
// phi_i - phi_o - pi in [-pi, pi], from the across-fiber components (one atan2).
float azimuth_difference(const FiberAngles& o, const FiberAngles& i) {
    return std::atan2(-(o.y * i.z - o.z * i.y), -(o.y * i.y + o.z * i.z));
}

// Composite Simpson of N(theta; mean, sigma^2) cos^2 theta over [-pi/2, pi/2], restricted to
// +-10 sigma around the mean (the rest is below 1e-22 of the mass).
double cos2_weighted_mass(double mean, double sigma) {
    const double a = std::max(-kHalfPi, mean - 10 * sigma), b = std::min(kHalfPi, mean + 10 * sigma);
    if (!(b > a)) return 0.0;
    constexpr int kIntervals = 256;  // even
    const double h = (b - a) / kIntervals;
    double sum = 0;
    for (int k = 0; k <= kIntervals; ++k) {
        const double x = a + k * h, c = std::cos(x);
        const double w = (k == 0 || k == kIntervals) ? 1 : (k % 2 ? 4 : 2);
        sum += w * normal_pdf(x, mean, sigma) * c * c;
    }
    return sum * h / 3;
}

}  // namespace

FiberLongitudinalLobe::FiberLongitudinalLobe(float width) {
    sigma_ = std::max(double(width), 1e-4);
    // Fine enough that linear interpolation of G stays within ~1e-3 even where G falls to
    // sigma^2/2 at grazing means.
    step_ = std::min(sigma_ / 32, kHalfPi / 256);
    const int n = static_cast<int>(std::ceil(kHalfPi / step_));
    step_ = kHalfPi / n;
    norm_.resize(n + 1);
    for (int k = 0; k <= n; ++k) norm_[k] = static_cast<float>(cos2_weighted_mass(k * step_, sigma_));
}

double FiberLongitudinalLobe::normalisation(double mean) const {
    const double x = std::min(std::fabs(mean), kHalfPi) / step_;
    const size_t k = std::min(static_cast<size_t>(x), norm_.size() - 2);
    const double f = x - k;
    return norm_[k] * (1 - f) + norm_[k + 1] * f;
}

float FiberLongitudinalLobe::eval(float theta_i, float theta_o) const {
    const double g = normalisation(-theta_o);
    if (!(g > 0)) return 0.0f;
    return static_cast<float>(normal_pdf(theta_i, -theta_o, sigma_) / g);
}

float FiberLongitudinalLobe::sample(float theta_o, float u) const {
    return static_cast<float>(TruncatedNormal{-double(theta_o), sigma_, -kHalfPi, kHalfPi}.sample(u));
}

float FiberLongitudinalLobe::sample_pdf(float theta_i, float theta_o) const {
    return static_cast<float>(TruncatedNormal{-double(theta_o), sigma_, -kHalfPi, kHalfPi}.pdf(theta_i));
}

FiberBcsdf::FiberBcsdf(const FiberBcsdfParams& p)
    : params_(p),
      reflection_color_(clamp01(p.reflection_color)),
      transmission_color_(clamp01(p.transmission_color)),
      r_(static_cast<float>(width_rad(p.reflection_width, 60))),
      tt_(static_cast<float>(width_rad(p.transmission_width, 60))) {
    gamma_ = width_rad(p.transmission_azimuthal_width, 180);
    gamma_mass_ = TruncatedNormal{0, gamma_, -kPi, kPi}.mass();
}

Vec3 FiberBcsdf::fresnel(float cos_theta_o) const {
    const float m = clamp(1 - cos_theta_o, 0.0f, 1.0f), m5 = m * m * m * m * m;
    return reflection_color_ + (Vec3(1.0f) - reflection_color_) * m5;
}

float FiberBcsdf::azimuthal_tt(float phi_d) const {
    return static_cast<float>(normal_pdf(phi_d, 0, gamma_) + (1 - gamma_mass_) / (2 * kPi));
}

float FiberBcsdf::sample_azimuth_tt(float u_choice, float u) const {
    if (u_choice < gamma_mass_) return static_cast<float>(TruncatedNormal{0, gamma_, -kPi, kPi}.sample(u));
    return -kPi + 2 * kPi * u;
}

void FiberBcsdf::lobe_probabilities(Vec3 wo, float prob[2]) const { lobe_probabilities(angles(wo).cos_theta, prob); }

void FiberBcsdf::lobe_probabilities(float cos_theta_o, float prob[2]) const {
    const Vec3 f = fresnel(cos_theta_o);
    prob[kReflection] = average(f);
    prob[kTransmission] = average((Vec3(1.0f) - f) * transmission_color_);
    const float total = prob[0] + prob[1];
    const float scale = total > 0 ? 1 / total : 0.0f;
    prob[0] *= scale;
    prob[1] *= scale;
}

Vec3 FiberBcsdf::scattering(Vec3 wo, Vec3 wi) const {
    const FiberAngles o = angles(wo), i = angles(wi);
    if (!(o.cos_theta > kMinCos && i.cos_theta > kMinCos)) return Vec3(0.0f);  // also NaN
    const Vec3 f = fresnel(o.cos_theta);
    const float phi_d = azimuth_difference(o, i);
    const Vec3 s = f * (r_.eval(i.theta, o.theta) / (2 * kPi)) +
                   (Vec3(1.0f) - f) * transmission_color_ * (tt_.eval(i.theta, o.theta) * azimuthal_tt(phi_d));
    return s * i.cos_theta;
}

Vec3 FiberBcsdf::eval(Vec3 wo, Vec3 wi) const {
    const float cos_n = std::fabs(wi.z) / std::max(length(wi), 1e-30f);
    if (!(cos_n > kMinCos)) return Vec3(0.0f);
    return scattering(wo, wi) / cos_n;
}

float FiberBcsdf::pdf(Vec3 wo, Vec3 wi) const {
    const FiberAngles o = angles(wo), i = angles(wi);
    if (!(o.cos_theta > kMinCos && i.cos_theta > kMinCos)) return 0.0f;
    float prob[2];
    lobe_probabilities(o.cos_theta, prob);
    const float phi_d = azimuth_difference(o, i);
    float p = 0;
    if (prob[kReflection] > 0) p += prob[kReflection] * r_.sample_pdf(i.theta, o.theta) / (2 * kPi);
    if (prob[kTransmission] > 0) p += prob[kTransmission] * tt_.sample_pdf(i.theta, o.theta) * azimuthal_tt(phi_d);
    return p / i.cos_theta;  // d omega = cos theta d theta d phi
}

std::optional<BsdfSample> FiberBcsdf::sample(Vec3 wo, float u_lobe, Vec2 u) const {
    const FiberAngles o = angles(wo);
    if (!(o.cos_theta > kMinCos)) return std::nullopt;
    float prob[2];
    lobe_probabilities(o.cos_theta, prob);
    if (!(prob[0] + prob[1] > 0)) return std::nullopt;
    const float phi_o = std::atan2(o.z, o.y);
    BsdfSample s;
    float theta, phi;
    if (u_lobe < prob[kReflection] || !(prob[kTransmission] > 0)) {
        s.lobe = kReflection;
        s.flags = kBsdfReflection | kBsdfSpecular;
        theta = r_.sample(o.theta, u.x);
        phi = 2 * kPi * u.y;
    } else {
        s.lobe = kTransmission;
        s.flags = kBsdfTransmission | kBsdfSpecular;
        // Reuse what is left of u_lobe to choose the Gaussian or the uniform part of N_TT.
        const float u_choice = std::min((u_lobe - prob[kReflection]) / prob[kTransmission], 0.99999994f);
        theta = tt_.sample(o.theta, u.x);
        phi = phi_o + kPi + sample_azimuth_tt(u_choice, u.y);
    }
    const float cos_theta = std::cos(theta);
    if (!(cos_theta > kMinCos)) return std::nullopt;
    s.wi = Vec3(std::sin(theta), cos_theta * std::cos(phi), cos_theta * std::sin(phi));
    s.pdf = pdf(wo, s.wi);
    if (!(s.pdf > 0)) return std::nullopt;
    s.f = eval(wo, s.wi);
    return s;
}

}  // namespace purl
