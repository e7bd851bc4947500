#include "support/chi_square.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <vector>

#include "math/rng.h"

namespace purl::test {
namespace {

constexpr double kTwoPi = 6.283185307179586;

Vec3 direction(double z, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    return Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(z));
}

// 3x3 Simpson rule on a rectangle from its nine corner/edge/centre values.
double simpson9(const double v[9], double area) {
    static const double w[9] = {1, 4, 1, 4, 16, 4, 1, 4, 1};
    double s = 0;
    for (int i = 0; i < 9; ++i) s += w[i] * v[i];
    return s * area / 36.0;
}

constexpr int kMaxDepth = 9;

// f of (cos theta, phi).
using PatchFunction = std::function<double(double, double)>;

double adaptive(const PatchFunction& f, double z0, double z1, double p0, double p1, const double v[9],
                double whole, double tolerance, int depth) {
    // Values on the 5x5 lattice of the four children, reusing the parent's nine.
    double g[5][5];
    const double zs[5] = {z0, 0.75 * z0 + 0.25 * z1, 0.5 * (z0 + z1), 0.25 * z0 + 0.75 * z1, z1};
    const double ps[5] = {p0, 0.75 * p0 + 0.25 * p1, 0.5 * (p0 + p1), 0.25 * p0 + 0.75 * p1, p1};
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j) {
            if (i % 2 == 0 && j % 2 == 0) g[i][j] = v[(i / 2) * 3 + j / 2];
            else g[i][j] = f(zs[i], ps[j]);
        }
    double child_v[4][9], child_sum[4], total = 0;
    for (int c = 0; c < 4; ++c) {
        const int oi = (c / 2) * 2, oj = (c % 2) * 2;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) child_v[c][i * 3 + j] = g[oi + i][oj + j];
        child_sum[c] = simpson9(child_v[c], 0.25 * (z1 - z0) * (p1 - p0));
        total += child_sum[c];
    }
    // Never accept the first level: a coarse 3x3 rule can agree with its children by chance.
    const bool converged = std::fabs(total - whole) <= 15.0 * tolerance && depth < kMaxDepth;
    if (depth <= 0 || converged) return total + (total - whole) / 15.0;
    double result = 0;
    for (int c = 0; c < 4; ++c) {
        const int oi = (c / 2) * 2, oj = (c % 2) * 2;
        result += adaptive(f, zs[oi], zs[oi + 2], ps[oj], ps[oj + 2], child_v[c], child_sum[c], 0.25 * tolerance,
                           depth - 1);
    }
    return result;
}

// Adaptive Simpson over one cell. Nodes on the cell's cos theta edges move inward by 1e-4
// of its height, so a model that is discontinuous at the horizon (or returns 0 in a thin
// grazing band) is integrated by its one-sided limit instead of forcing endless refinement.
double integrate_cell(const DirectionDensity& f, double z0, double z1, double phi0, double phi1,
                      double absolute_tolerance, double relative_tolerance) {
    const double inset = 1e-4 * (z1 - z0);
    const PatchFunction g = [&](double z, double phi) {
        return f(direction(std::clamp(z, z0 + inset, z1 - inset), phi));
    };
    double v[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) v[i * 3 + j] = g(z0 + 0.5 * i * (z1 - z0), phi0 + 0.5 * j * (phi1 - phi0));
    const double whole = simpson9(v, (z1 - z0) * (phi1 - phi0));
    const double tolerance = std::max(absolute_tolerance, relative_tolerance * std::fabs(whole));
    return adaptive(g, z0, z1, phi0, phi1, v, whole, tolerance, kMaxDepth);
}

// Continued fraction for Q(a, x) (modified Lentz), valid for x > a + 1.
double gamma_q_continued_fraction(double a, double x) {
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::fabs(delta - 1.0) < 1e-15) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

// Series for P(a, x), valid for x < a + 1.
double gamma_p_series(double a, double x) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 10000; ++n) {
        term *= x / (a + n);
        sum += term;
        if (std::fabs(term) < std::fabs(sum) * 1e-16) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

}  // namespace

double regularized_gamma_q(double a, double x) {
    if (x <= 0) return 1.0;
    if (x < a + 1.0) return 1.0 - gamma_p_series(a, x);
    return gamma_q_continued_fraction(a, x);
}

double integrate_sphere_patch(const DirectionDensity& f, double z0, double z1, double phi0, double phi1,
                              double tolerance) {
    return integrate_cell(f, z0, z1, phi0, phi1, tolerance, 0.0);
}


double integrate_sphere(const DirectionDensity& f, int cos_theta_bins, int phi_bins, double tolerance) {
    double total = 0;
    for (int i = 0; i < cos_theta_bins; ++i)
        for (int j = 0; j < phi_bins; ++j)
            total += integrate_sphere_patch(f, -1.0 + 2.0 * i / cos_theta_bins, -1.0 + 2.0 * (i + 1) / cos_theta_bins,
                                            kTwoPi * j / phi_bins, kTwoPi * (j + 1) / phi_bins, tolerance);
    return total;
}

Chi2Result chi2_test(const DirectionSampler& sample, const DirectionDensity& pdf, const Chi2Options& o) {
    const int nz = o.cos_theta_bins, np = o.phi_bins, cells = nz * np;
    const double n = double(o.samples);

    // Histogram of sampled directions; the extra last cell counts failed samples.
    std::vector<double> observed(cells + 1, 0.0);
    Rng rng(o.seed, 0x5eed);
    for (int64_t k = 0; k < o.samples; ++k) {
        const Vec3 u(rng.next_float(), rng.next_float(), rng.next_float());
        const std::optional<Vec3> w = sample(u);
        if (!w || !is_finite(*w)) {
            observed[cells] += 1;
            continue;
        }
        const double z = std::clamp(double(w->z), -1.0, 1.0);
        double phi = std::atan2(double(w->y), double(w->x));
        if (phi < 0) phi += kTwoPi;
        const int iz = std::min(nz - 1, int((z + 1.0) * 0.5 * nz));
        const int ip = std::min(np - 1, int(phi / kTwoPi * np));
        observed[iz * np + ip] += 1;
    }

    // Expected counts: the pdf integrated per cell, accurate to ~0.02 samples per cell.
    std::vector<double> expected(cells + 1, 0.0);
    double integral = 0;
    for (int iz = 0; iz < nz; ++iz)
        for (int ip = 0; ip < np; ++ip) {
            // Error budget: 0.05 samples or 2e-4 of the cell's mass, well below the Poisson
            // noise sqrt(expected) of any cell the test keeps.
            const double cell = integrate_cell(pdf, -1.0 + 2.0 * iz / nz, -1.0 + 2.0 * (iz + 1) / nz,
                                               kTwoPi * ip / np, kTwoPi * (ip + 1) / np, 0.05 / n, 2e-4);
            expected[iz * np + ip] = cell * n;
            integral += cell;
        }
    expected[cells] = std::max(0.0, 1.0 - integral) * n;

    Chi2Result r;
    r.pdf_integral = integral;
    r.success_fraction = 1.0 - observed[cells] / n;
    r.threshold = 1.0 - std::pow(1.0 - o.significance, 1.0 / std::max(1, o.test_count));
    if (integral > 1.0 + 1e-3) {
        r.message = "pdf integrates to " + std::to_string(integral) + " > 1";
        return r;
    }

    // Pool the sparse cells, worst first for the report.
    std::vector<int> order(cells + 1);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
    double pooled_obs = 0, pooled_exp = 0, stat = 0;
    int bins = 0;
    struct Offender { double term, obs, exp; int cell; };
    std::vector<Offender> offenders;
    for (int c : order) {
        if (expected[c] < o.min_expected) {
            pooled_obs += observed[c];
            pooled_exp += expected[c];
            continue;
        }
        const double diff = observed[c] - expected[c];
        const double term = diff * diff / expected[c];
        stat += term;
        offenders.push_back({term, observed[c], expected[c], c});
        ++bins;
    }
    if (pooled_exp > 0 || pooled_obs > 0) {
        if (pooled_exp < o.min_expected && bins > 0) {
            // Too little mass to stand alone: fold into the smallest kept cell.
            Offender& smallest = offenders.front();
            stat -= smallest.term;
            smallest.obs += pooled_obs;
            smallest.exp += pooled_exp;
            smallest.term = sqr(float(smallest.obs - smallest.exp)) / smallest.exp;
            stat += smallest.term;
        } else {
            const double diff = pooled_obs - pooled_exp;
            const double term = pooled_exp > 0 ? diff * diff / pooled_exp : (pooled_obs > 0 ? 1e30 : 0.0);
            stat += term;
            offenders.push_back({term, pooled_obs, pooled_exp, -1});
            ++bins;
        }
    }
    r.statistic = stat;
    r.dof = std::max(1, bins - 1);
    r.p_value = regularized_gamma_q(0.5 * r.dof, 0.5 * stat);
    r.passed = r.p_value >= r.threshold;

    char buf[256];
    std::snprintf(buf, sizeof buf, "chi2 = %.1f, dof = %d, p = %.3g (threshold %.3g), pdf integral %.5f, success %.5f",
                  stat, r.dof, r.p_value, r.threshold, integral, r.success_fraction);
    r.message = buf;
    if (!r.passed) {
        std::sort(offenders.begin(), offenders.end(), [](const Offender& a, const Offender& b) { return a.term > b.term; });
        for (size_t i = 0; i < std::min<size_t>(5, offenders.size()); ++i) {
            const Offender& w = offenders[i];
            if (w.cell == cells) std::snprintf(buf, sizeof buf, "\n  failed samples: observed %.0f expected %.1f", w.obs, w.exp);
            else if (w.cell < 0) std::snprintf(buf, sizeof buf, "\n  pooled cells: observed %.0f expected %.1f", w.obs, w.exp);
            else
                std::snprintf(buf, sizeof buf, "\n  cell cos_theta #%d phi #%d: observed %.0f expected %.1f", w.cell / np,
                              w.cell % np, w.obs, w.exp);
            r.message += buf;
        }
    }
    return r;
}

}  // namespace purl::test
