#include "render/far_field.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <utility>

#include "math/rng.h"
#include "render/multiscale.h"
#include "yarn/straight_yarn.h"

namespace purl {
namespace {

constexpr float kMinCos = 1e-6f;  // as the BYSDF: the reference plane carries nothing
constexpr float kCellSolidAngle = 4 * kPi / FarFieldTable::kCells;
constexpr size_t kCachedTables = 4;
std::atomic<int> g_nodes_done{0}, g_nodes_total{0};  // far_field_build_progress()

// One build's share of g_nodes_*, taken back when the build ends (also by an exception).
class BuildProgressScope {
public:
    explicit BuildProgressScope(const std::atomic<int>& done) : done_(done) { g_nodes_total += FarFieldTable::kThetaO; }
    ~BuildProgressScope() {
        g_nodes_done -= done_.load();
        g_nodes_total -= FarFieldTable::kThetaO;
    }

private:
    const std::atomic<int>& done_;
};

Vec3 clamp01(Vec3 c) { return {clamp(c.x, 0.0f, 1.0f), clamp(c.y, 0.0f, 1.0f), clamp(c.z, 0.0f, 1.0f)}; }

int color_classes(const BysdfParams& p) {
    return static_cast<int>(clamp(p.ply_color_count, 1.0f, float(kMaxPlyColors)));
}

// The material with its colours replaced by lobe markers: the lobe at the hit is linear in them,
// so one evaluation gives the specular lobes in x and the body lobes in y (the plies crossed
// come apart, from the material's own colours: MultiscaleYarn::crossing_colors).
BysdfParams marker_params(const BysdfParams& material) {
    BysdfParams p = material;
    p.specular_reflection_albedo = p.specular_transmission_albedo = Vec3(1, 0, 0);
    p.body_reflection_albedo = p.body_transmission_albedo = Vec3(0, 1, 0);
    for (Vec3& c : p.ply_colors) c = Vec3(1.0f);
    // The table keeps the plies crossed apart (a product along one direction), which the spread
    // crossing's average over directions is not: it tabulates the traced crossing instead.
    p.ply_crossing = std::min(p.ply_crossing, 1.0f);
    return p;
}

// Local direction from sin theta (along +x) and phi (from +z toward +y).
Vec3 direction(float sin_theta, float phi) {
    const float cos_theta = safe_sqrt(1 - sin_theta * sin_theta);
    return {sin_theta, cos_theta * std::sin(phi), cos_theta * std::cos(phi)};
}

float azimuth(Vec3 w) { return std::atan2(w.y, w.z); }

}  // namespace

void FarFieldTable::node_weights(float sin_o, int& j0, int& j1, float& t) {
    const float pos = (clamp(sin_o, -1.0f, 1.0f) + 1) * 0.5f * kThetaO - 0.5f;
    j0 = clamp(static_cast<int>(std::floor(pos)), 0, kThetaO - 1);
    j1 = std::min(j0 + 1, kThetaO - 1);
    t = j1 > j0 ? clamp(pos - float(j0), 0.0f, 1.0f) : 0.0f;
}

int FarFieldTable::cell_of(Vec3 wi, float phi_o) {
    const int row = clamp(static_cast<int>((clamp(wi.x, -1.0f, 1.0f) + 1) * 0.5f * kThetaI), 0, kThetaI - 1);
    float phi = (azimuth(wi) - phi_o) * (0.5f * kInvPi);
    phi -= std::floor(phi);
    const int col = clamp(static_cast<int>(phi * kPhi), 0, kPhi - 1);
    return row * kPhi + col;
}

FarFieldTable::FarFieldTable(const YarnDescription& d, const BysdfParams& material, const MultiscaleSettings& s,
                             int queries, int cell_stride) {
    const auto start = std::chrono::steady_clock::now();
    const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    classes_ = color_classes(material);
    const int g_count = groups();
    values_.assign(size_t(kThetaO) * kCells * g_count * 3, 0.0f);
    pass_.assign(kThetaO, 1.0f);
    albedo_.assign(size_t(kThetaO) * g_count, 0.0f);
    distributions_.resize(kThetaO * 2);

    // A straight yarn of radius 1 along +z; queries land in its middle third.
    const std::vector<Vec4> points = straight_yarn_points();
    const CurveFrames frames(CurveView::chain(points.data(), static_cast<uint32_t>(points.size()), false));
    const FiberMaps maps(d);
    const BysdfParams markers = marker_params(material);
    MultiscaleSettings settings = s;
    settings.aggregation = MultiscaleAggregation::Mixture;
    // The table is a long average: its models take every h sample a full footprint allows,
    // whatever a render's own per-hit limit (not part of the cache key).
    settings.max_h_samples = float(kMaxHSamples);
    settings.sample_spacing = 1.0f;
    const Vec3 axis(0, 0, 1);

    std::atomic<int> done{0};
    const BuildProgressScope progress(done);
    const auto build_node = [&](int j) {
        const float sin_o = -1 + (j + 0.5f) * 2.0f / kThetaO, cos_o = safe_sqrt(1 - sin_o * sin_o);
        std::vector<double> sum(size_t(kCells) * g_count * 3, 0.0);
        std::vector<double> hit_share(cell_stride, 0.0);  // per residue of the query index
        double pass_sum = 0;
        Rng rng(0x66617266u + uint64_t(j));
        for (int qi = 0; qi < queries; ++qi) {
            // Stratified offset h0 and view azimuth (stands in for the ply phase; its strata
            // permuted so the two do not move together), jitter; position along the yarn and
            // the curve key (per-curve fiber maps) vary too.
            const float alpha = 2 * kPi * ((qi * 37 + 11) % queries + rng.next_float()) / queries;
            const float h0 = clamp(-1 + 2 * (qi + rng.next_float()) / queries, -0.999f, 0.999f);
            const float z0 = 30 + 20 * rng.next_float();
            const Vec3 out(std::cos(alpha), std::sin(alpha), 0.0f);  // toward the viewer, across the axis
            const Vec3 wo = out * cos_o + axis * sin_o, d_ray = -wo;
            const Vec3 across = cross(axis, -out);

            MultiscaleQuery q;
            q.tube.direction = d_ray;
            q.tube.point = Vec3(0, 0, z0) + across * h0 + out * safe_sqrt(1 - h0 * h0);
            q.tube.origin = q.tube.point - d_ray * 5.0f;
            q.axis = project_to_centreline(frames, q.tube.point, static_cast<uint32_t>(z0) - 1, 0.5f);
            q.tube.segment = q.axis.segment;
            q.tube.t = q.axis.t;
            Ray ray;
            ray.origin = q.tube.origin;
            ray.direction = d_ray;
            ray.has_differentials = true;
            ray.rx_origin = ray.origin + across * 4.0f;  // wider than the yarn
            ray.rx_direction = d_ray;
            ray.ry_origin = ray.origin + normalize(cross(d_ray, across)) * 0.37f;
            ray.ry_direction = d_ray;
            q.footprint = yarn_footprint(ray, q.tube.point, q.axis.point, 1.0f);
            q.mode = MultiscaleMode::Far;
            q.u_strata = rng.next_float();
            const MultiscaleYarn yarn{&frames, &d, &maps, &markers, uint32_t(qi), Vec3(1.0f), {}, &material};
            const MultiscaleBysdf m(yarn, settings, q);
            pass_sum += m.empty() ? 1.0 : m.pass_fraction();
            if (m.empty()) continue;
            const float share = 1 - m.pass_fraction();
            hit_share[qi % cell_stride] += share;

            // One jittered direction in every cell_stride-th cell, every component: more
            // queries (h0, phase) for the same cost.
            const Frame far = Frame::from_normal_tangent(out, axis);
            const Vec3 wo_m = m.frame().to_local(wo);
            for (int cell = qi % cell_stride; cell < kCells; cell += cell_stride) {
                const int row = cell / kPhi, col = cell % kPhi;
                const float sin_i = -1 + 2 * (row + rng.next_float()) / kThetaI;
                const float phi = 2 * kPi * (col + rng.next_float()) / kPhi;
                const Vec3 wi_m = m.frame().to_local(far.to_world(direction(sin_i, phi)));
                double* acc = &sum[size_t(cell) * g_count * 3];
                const auto add = [&](int g, float lobe, Vec3 crossed) {
                    for (int ch = 0; ch < 3; ++ch) acc[g * 3 + ch] += double(lobe) * crossed[ch];
                };
                for (int k = 0; k < m.components(); ++k) {
                    const MultiscaleBysdf::Component& c = m.component(k);
                    Vec3 crossed;
                    const Vec3 f = m.component_integrand(k, wo_m, wi_m, nullptr, &crossed) * share;
                    const int through = c.frame.to_local(wo_m).z * c.frame.to_local(wi_m).z < 0 ? 1 : 0;
                    const int cls = c.ply >= 0 ? c.ply % classes_ : 0;
                    add(through, f.x, crossed);
                    add(2 + 2 * cls + through, f.y, crossed);
                }
            }
        }
        pass_[j] = float(pass_sum / queries);
        std::vector<float> spec(kCells, 0.0f), body(kCells, 0.0f);
        for (int cell = 0; cell < kCells; ++cell) {
            const double norm = hit_share[cell % cell_stride];
            if (norm > 0)
                for (int g = 0; g < g_count; ++g) {
                    float mean = 0;
                    for (int ch = 0; ch < 3; ++ch) {
                        const size_t i = (size_t(cell) * g_count + g) * 3 + ch;
                        const float v = float(sum[i] / norm);
                        values_[size_t(j) * kCells * g_count * 3 + i] = v;
                        mean += v / 3;
                    }
                    albedo_[size_t(j) * g_count + g] += mean * kCellSolidAngle;
                    (g < 2 ? spec : body)[cell] += mean;
                }
        }
        distributions_[j * 2] = Distribution2D(spec.data(), kPhi, kThetaI);
        distributions_[j * 2 + 1] = Distribution2D(body.data(), kPhi, kThetaI);
        const int n = ++done;
        ++g_nodes_done;
        if ((n == kThetaO / 2 || n == kThetaO) && elapsed() > 1.0)
            std::fprintf(stderr, "purl: tabulating the far field: %d/%d view angles, %.1f s\n", n, kThetaO, elapsed());
    };
    // Isolated: a render thread waiting here must not pick up another pixel that waits for this table.
    tbb::this_task_arena::isolate([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, kThetaO, 1), [&](const tbb::blocked_range<int>& r) {
            for (int j = r.begin(); j != r.end(); ++j) build_node(j);
        });
    });
    build_seconds_ = elapsed();
}

FarFieldBuildProgress far_field_build_progress() {
    FarFieldBuildProgress p;
    p.total = g_nodes_total.load();
    p.done = std::min(g_nodes_done.load(), p.total);
    return p;
}

size_t FarFieldTable::memory_bytes() const {
    // Each Distribution2D row keeps its values and its CDF, plus the marginal.
    const size_t per_distribution = (size_t(kThetaI) * (2 * kPhi + 1) + 2 * kThetaI + 1) * sizeof(float);
    return (values_.size() + pass_.size() + albedo_.size()) * sizeof(float) + distributions_.size() * per_distribution;
}

std::shared_ptr<const FarFieldTable> far_field_table(const YarnDescription& d, const BysdfParams& material,
                                                     const MultiscaleSettings& s) {
    // Key: every number that shapes the table (the colours too: A_k of the plies crossed).
    std::vector<float> key;
    for (const ParamInfo& info : yarn_description_params())
        for (int c = 0; c < info.components; ++c) key.push_back(param_field(d, info)[c]);
    for (const ParamInfo& info : bysdf_param_table())
        for (int c = 0; c < info.components; ++c) key.push_back(param_field(material, info)[c]);
    key.push_back(s.roughness_c);

    static std::mutex mutex;
    static std::vector<std::pair<std::vector<float>, std::shared_ptr<const FarFieldTable>>> cache;  // oldest first
    const std::lock_guard<std::mutex> lock(mutex);
    for (size_t i = 0; i < cache.size(); ++i)
        if (cache[i].first == key) {
            std::rotate(cache.begin() + i, cache.begin() + i + 1, cache.end());
            return cache.back().second;
        }
    auto table = std::make_shared<const FarFieldTable>(d, material, s);
    if (cache.size() == kCachedTables) cache.erase(cache.begin());
    cache.emplace_back(std::move(key), table);
    return table;
}

FarFieldBsdf::FarFieldBsdf(const FarFieldTable& table, const BysdfParams& p) : table_(&table) {
    coef_[0] = clamp01(p.specular_reflection_albedo);
    coef_[1] = clamp01(p.specular_transmission_albedo);
    for (int c = 0; c < table.classes(); ++c) {
        const Vec3 tint = clamp01(p.ply_colors[c]);
        coef_[2 + 2 * c] = clamp01(p.body_reflection_albedo * tint);
        coef_[3 + 2 * c] = clamp01(p.body_transmission_albedo * tint);
    }
}

float FarFieldBsdf::pass_fraction(Vec3 wo) const {
    int j0, j1;
    float t;
    FarFieldTable::node_weights(wo.x, j0, j1, t);
    return (1 - t) * table_->pass_fraction(j0) + t * table_->pass_fraction(j1);
}

Vec3 FarFieldBsdf::value(int node, int cell) const {
    Vec3 f(0.0f);
    for (int g = 0; g < table_->groups(); ++g) f += coef_[g] * table_->value(node, cell, g);
    return f;
}

float FarFieldBsdf::specular_share(int node) const {
    float spec = 0, body = 0;
    for (int g = 0; g < table_->groups(); ++g) (g < 2 ? spec : body) += average(coef_[g]) * table_->albedo(node, g);
    return spec + body > 0 ? spec / (spec + body) : 0.5f;
}

BsdfEvalPdf FarFieldBsdf::evaluate(Vec3 wo, Vec3 wi) const {
    BsdfEvalPdf out;
    int j[2];
    float t;
    FarFieldTable::node_weights(wo.x, j[0], j[1], t);
    const int cell = FarFieldTable::cell_of(wi, azimuth(wo));
    const Vec2 uv((float(cell % FarFieldTable::kPhi) + 0.5f) / FarFieldTable::kPhi,
                  (float(cell / FarFieldTable::kPhi) + 0.5f) / FarFieldTable::kThetaI);
    const float lambda[2] = {1 - t, t};
    Vec3 integrand(0.0f);
    for (int n = 0; n < 2; ++n) {
        if (lambda[n] == 0) continue;
        integrand += value(j[n], cell) * lambda[n];
        const float share = specular_share(j[n]);
        out.pdf += lambda[n] * (share * table_->distribution(j[n], 0).pdf(uv) +
                                (1 - share) * table_->distribution(j[n], 1).pdf(uv));
    }
    out.pdf /= 4 * kPi;  // (phi, sin theta) in [0, 1)^2 covers the sphere with dw = 4 pi du dv
    const float cos_ref = std::fabs(wi.z);
    out.f = cos_ref > kMinCos ? integrand / cos_ref : Vec3(0.0f);
    return out;
}

std::optional<BsdfSample> FarFieldBsdf::sample(Vec3 wo, float u_lobe, Vec2 u) const {
    int j0, j1;
    float t;
    FarFieldTable::node_weights(wo.x, j0, j1, t);
    // Node j1 with probability t, then the specular or body distribution by its share.
    int node = j0;
    if (u_lobe < 1 - t) {
        u_lobe /= 1 - t;
    } else {
        node = j1;
        u_lobe = (u_lobe - (1 - t)) / t;
    }
    const float share = specular_share(node);
    const int kind = u_lobe < share ? 0 : 1;
    float pdf_uv;
    const Vec2 x = table_->distribution(node, kind).sample(u, pdf_uv);
    BsdfSample s;
    s.wi = direction(2 * x.y - 1, azimuth(wo) + 2 * kPi * x.x);
    const BsdfEvalPdf e = evaluate(wo, s.wi);
    if (!(e.pdf > 0)) return std::nullopt;
    s.f = e.f;
    s.pdf = e.pdf;
    s.lobe = kind;
    s.flags = (s.wi.z * wo.z >= 0 ? kBsdfReflection : kBsdfTransmission) | (kind == 0 ? kBsdfSpecular : kBsdfBody);
    return s;
}

}  // namespace purl
