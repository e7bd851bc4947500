#include "render/multiscale.h"

#include <cmath>
#include <cstddef>
#include <cstdio>

#include "math/ray_cylinder.h"
#include "base/input_error.h"
#include "yarn/ply_crossings.h"
#include "yarn/yarn_shading_point.h"

namespace purl {
namespace {

constexpr float kMinCos = 1e-6f;       // as the BYSDF: directions in the reference plane carry nothing
constexpr float kMaxChord = 200.0f;    // yarn radii; tube_exit's cap for rays running along the yarn
constexpr float kGolden = 0.61803398875f;

// Entry of the line o + s d (d unit) into the straight cylinder (c, axis, radius); false when
// it misses or runs along the axis. A line that only grazes enters at its closest point.
bool cylinder_entry(Vec3 o, Vec3 d, Vec3 c, Vec3 axis, float radius, float max_offset, Vec3& entry) {
    const RayCylinder r = ray_cylinder(o, d, c, axis, radius);
    if (r.along_axis()) return false;
    if (r.discriminant() < -r.a * sqr(max_offset * radius)) return false;  // misses by more than max_offset radii
    entry = o + d * r.entry();
    return is_finite(entry);
}

// Distance (yarn radii) from `offset` (inside, relative to the axis, in radii) along unit d to
// the straight tube's wall.
float chord_in_radii(Vec3 offset, Vec3 axis, Vec3 d) {
    const RayCylinder r = ray_cylinder(offset, d, Vec3(0.0f), axis, 1.0f);
    return r.along_axis() ? kMaxChord : clamp(r.chord(), 0.0f, kMaxChord);
}

// The line parallel to the camera ray at `dh` yarn radii across the yarn, entering the
// straight tube of the camera ray's cross-section (the camera ray itself if it misses).
YarnTubeHit virtual_entry(const MultiscaleQuery& q, float dh) {
    const CurvePoint& c = q.axis.point;
    YarnTubeHit h = q.tube;
    h.origin = q.tube.origin + q.footprint.across * (dh * c.radius);
    if (!cylinder_entry(h.origin, h.direction, c.position, c.tangent, c.radius, 1e-3f, h.point)) return q.tube;
    return h;
}

// The same followed along the centre-line to the entry's own cross-section (on a bend,
// re-entering the tube there), for the methods that project the hit themselves.
YarnTubeHit virtual_hit(const CurveFrames& frames, const MultiscaleQuery& q, float dh) {
    YarnTubeHit h = virtual_entry(q, dh);
    const CurvePoint& c = q.axis.point;
    uint32_t segment = q.axis.segment;
    float t = q.axis.t;
    const float along = dot(h.point - c.position, c.tangent);
    frames.advance(segment, t, along / std::max(c.speed, 1e-30f));
    if (std::fabs(along) > 0.25f * c.radius) {
        const CurvePoint c2 = frames.evaluate_centreline(segment, t);
        Vec3 entry2;
        if (cylinder_entry(h.origin, h.direction, c2.position, c2.tangent, c2.radius, 0.05f, entry2)) {
            frames.advance(segment, t, dot(entry2 - c2.position, c2.tangent) / std::max(c2.speed, 1e-30f));
            h.point = entry2;
        }
    }
    h.segment = segment;
    h.t = t;
    return h;
}

Vec3 ply_tint(const BysdfParams& p, int ply) {
    const int colors = static_cast<int>(clamp(p.ply_color_count, 1.0f, float(kMaxPlyColors)));
    return p.ply_colors[ply >= 0 ? ply % colors : 0];
}

}  // namespace

float fiber_feature_width(const YarnDescription& d) {
    return std::max(2.0f * d.fiber_radius * d.ply_radius, 1e-4f);
}

int h_sample_count(float width, const YarnDescription& d, const MultiscaleSettings& s) {
    // Odd, so that a cell centred on h0 tiles an unclamped footprint exactly.
    int most = static_cast<int>(clamp(s.max_h_samples, 1.0f, float(kMaxHSamples - 1)));
    if (most % 2 == 0) --most;
    const float per_sample = std::max(s.sample_spacing, 1e-3f) * fiber_feature_width(d);
    const float k = std::ceil(std::max(width, 0.0f) / per_sample);
    if (!(k < float(most))) return most;  // also NaN
    const int n = std::max(1, static_cast<int>(k));
    return n % 2 ? n : n + 1;
}

MultiscaleSelector::MultiscaleSelector(const MultiscaleSettings& settings, WarningSink sink, size_t yarn_sets)
    : settings_(settings), sink_(std::move(sink)), tables_(new TableSlot[yarn_sets]), table_count_(yarn_sets) {
    if (!sink_) sink_ = [](const std::string& m) { std::fprintf(stderr, "purl: warning: %s\n", m.c_str()); };
}

const FarFieldTable* MultiscaleSelector::far_table(size_t set, const YarnDescription& d,
                                                   const BysdfParams& material) const {
    if (set >= table_count_) return nullptr;
    TableSlot& slot = tables_[set];
    tbb::collaborative_call_once(slot.once, [&] { slot.table = far_field_table(d, material, settings_); });
    return slot.table.get();
}

MultiscaleMode MultiscaleSelector::choose(const AzimuthalFootprint& f, const YarnDescription& d) const {
    switch (settings_.mode) {
        case MultiscaleMode::Near:
        case MultiscaleMode::Multi:
            return settings_.mode;
        case MultiscaleMode::Far: {
            // One pixel narrower than the yarn: far-field averages detail the pixel could resolve.
            const float pixel_width = settings_.footprint_scale > 0 ? f.raw_width / settings_.footprint_scale : 0.0f;
            if (f.valid && pixel_width < 2.0f && !warned_.exchange(true, std::memory_order_relaxed)) {
                char message[256];
                std::snprintf(message, sizeof message,
                              "multiscale mode 'far' on yarns wider than a pixel (this one spans %.1f pixels): "
                              "far field averages the whole yarn width and will not match near or multi "
                              "(Khattar et al. 2024, Fig. 8); use 'auto'",
                              pixel_width > 0 ? 2.0f / pixel_width : 0.0f);
                sink_(message);
            }
            return MultiscaleMode::Far;
        }
        case MultiscaleMode::Auto:
            break;
    }
    if (!f.valid) return MultiscaleMode::Near;
    // A pixel as wide as the yarn: its footprint may end inside the yarn, but the neighbour
    // covers the rest, so the whole-yarn average only blurs below a pixel.
    const float pixel_width = settings_.footprint_scale > 0 ? f.raw_width / settings_.footprint_scale : 0.0f;
    if (f.covers_yarn() || pixel_width >= 2 * settings_.far_limit) return MultiscaleMode::Far;
    if (f.width() < settings_.near_limit * fiber_feature_width(d)) return MultiscaleMode::Near;
    // A yarn many pixels wide: its pixel samples land on different fibers anyway, and cost
    // less than multi's traced h samples (docs/multiscale.md, production tier).
    if (settings_.near_pixels > 0 && pixel_width * settings_.near_pixels <= 2.0f) return MultiscaleMode::Near;
    return MultiscaleMode::Multi;
}

MultiscaleBysdf::MultiscaleBysdf(const MultiscaleYarn& yarn, const MultiscaleSettings& settings,
                                 const MultiscaleQuery& q) {
    const CurveFrames& frames = *yarn.frames;
    const YarnDescription& desc = *yarn.description;
    const AzimuthalFootprint& fp = q.footprint;
    const CurvePoint& axis = q.axis.point;
    const float radius = std::max(axis.radius, 1e-30f);

    // Without an azimuthal plane (ray along the yarn), or a footprint for multi, only h0 exists.
    mode_ = q.mode == MultiscaleMode::Auto ? MultiscaleMode::Multi : q.mode;
    if (fp.along_yarn || !(length(fp.across) > 0.5f) || (mode_ == MultiscaleMode::Multi && !fp.valid))
        mode_ = MultiscaleMode::Near;
    h1_ = mode_ == MultiscaleMode::Far ? -1.0f : (mode_ == MultiscaleMode::Near ? fp.h0 : fp.h1);
    h2_ = mode_ == MultiscaleMode::Far ? 1.0f : (mode_ == MultiscaleMode::Near ? fp.h0 : fp.h2);
    const float width = h2_ - h1_;
    const int k_count = mode_ == MultiscaleMode::Near ? 1 : h_sample_count(width, desc, settings);
    samples_ = 0;
    roughness_increase_ = mode_ == MultiscaleMode::Near ? 0.0f : width / std::max(settings.roughness_c, 1e-6f);

    BysdfParams params = *yarn.params;
    params.specular_roughness_along += roughness_increase_;
    params.specular_roughness_across += roughness_increase_;
    params.transmission_roughness += roughness_increase_;

    // The h samples: cells of width/K on a grid centred on h0, clipped to [h1, h2] (K odd:
    // K cells, one more when the footprint is clamped at a silhouette), each weighted by its
    // length. h0's own cell takes the camera ray itself: h0 is uniform over the pixel, so that
    // sample is as random as a jittered one, costs no virtual ray, keeps the footprint's
    // filter symmetric, and rays leave from where the near field would leave. The other
    // cells are jittered by the per-hit random number.
    const float h_main = dot(q.tube.origin - axis.position, fp.across) / radius;
    const float cell = width > 0 ? width / float(k_count) : 1.0f;
    const int j_lo = width > 0 ? static_cast<int>(std::floor((h1_ - fp.h0) / cell + 0.5f)) : 0;
    const int j_hi = width > 0 ? static_cast<int>(std::ceil((h2_ - fp.h0) / cell - 0.5f)) : 0;
    // The virtual rays only feed an average: they take the local method around the camera
    // ray's own cross-section (q.axis), exact on straight yarns and with no curve evaluation
    // (docs/multiscale.md).
    const bool local = yarn.trace.cross_section != PlyCrossSection::circular;
    PlyTraceOptions around = yarn.trace;
    around.cross_section = PlyCrossSection::local;
    const YarnTwist twist = yarn_twist(frames, desc);
    YarnShadingPoint hits[kMaxHSamples];
    float hit_h[kMaxHSamples], hit_len[kMaxHSamples];
    int hit_count = 0, nearest = -1;
    bool own_hit = false;
    float hit_length = 0, total_length = 0;
    float u = q.u_strata - std::floor(q.u_strata);
    for (int j = j_lo; j <= j_hi && samples_ < kMaxHSamples; ++j) {
        const float lo = std::max(h1_, fp.h0 + (j - 0.5f) * cell), hi = std::min(h2_, fp.h0 + (j + 0.5f) * cell);
        const float len = width > 0 ? hi - lo : 1.0f;
        if (!(len > 1e-6f * std::max(width, 1e-6f))) continue;
        float h = fp.h0;
        if (j != 0) {
            h = lo + (u - std::floor(u)) * len;
            u += kGolden;  // each cell's jitter is uniform on its own
        }
        ++samples_;
        total_length += len;
        const PlyHit ply = j == 0  ? trace_plies({frames, desc, twist, q.tube}, yarn.trace)
                           : local ? trace_plies({frames, desc, twist, virtual_entry(q, h - h_main), &q.axis}, around)
                                   : trace_plies({frames, desc, twist, virtual_hit(frames, q, h - h_main)}, yarn.trace);
        const YarnShadingPoint y = shade_ply_hit(ply, frames, desc, twist, *yarn.maps, yarn.curve_key);
        if (!y.hit) continue;
        if (j == 0) own_hit = true;
        if (j == 0 || (!own_hit && (nearest < 0 || std::fabs(h - fp.h0) < std::fabs(hit_h[nearest] - fp.h0))))
            nearest = hit_count;
        hit_h[hit_count] = h;
        hit_len[hit_count] = len;
        hit_length += len;
        hits[hit_count++] = y;
    }
    pass_fraction_ = total_length > 0 ? clamp(1.0f - hit_length / total_length, 0.0f, 1.0f) : 1.0f;
    frames_ = &frames;
    entry_ = q.tube;
    axis_segment_ = q.axis.segment;
    axis_t_ = q.axis.t;
    if (hit_count == 0) return;

    const YarnShadingPoint& rep = hits[nearest];
    position_ = rep.position;
    segment_ = rep.segment;
    t_ = rep.t;
    ply_ = rep.ply_index;
    u_ply_ = rep.u_ply;
    v_ply_ = rep.v_ply;

    // Aggregated frame and shading values (eqs. 9-11). The BYSDF is two-sided and symmetric
    // in its tangent's sign, so normals face the viewer and tangents follow the yarn first.
    const Vec3 view = -q.tube.direction;
    Vec3 n_sum(0.0f), t_sum(0.0f), tint_sum(0.0f);
    float gf = 0, gp = 0, crossed = 0;
    for (int k = 0; k < hit_count; ++k) {
        const YarnShadingPoint& y = hits[k];
        const float w = hit_len[k] / hit_length;
        n_sum += (dot(y.fiber_normal, view) >= 0 ? y.fiber_normal : -y.fiber_normal) * w;
        t_sum += (dot(y.fiber_tangent, axis.tangent) >= 0 ? y.fiber_tangent : -y.fiber_tangent) * w;
        gf += y.fiber_shadowing * w;
        gp += y.ply_shadowing * w;
        crossed += float(std::max(1, y.plies_crossed)) * w;
        tint_sum += ply_tint(params, y.ply_index) * w;
    }
    g_multi_ = gf;
    const bool single = hit_count == 1 && settings.aggregation == MultiscaleAggregation::Mixture;
    if (single) {
        frame_ = Frame::from_normal_tangent(rep.fiber_normal, rep.fiber_tangent);  // exactly the near field's
    } else {
        const float n_len = length(n_sum);
        const Vec3 n = n_len > 1e-3f ? n_sum / n_len : rep.fiber_normal;
        frame_ = Frame::from_normal_tangent(n, t_sum);
    }
    axis_tangent_ = frame_.to_local(axis.tangent);

    if (params.ply_crossing >= 0.5f) crossing_ = &desc;
    // A hit's section in the straight yarn of the camera ray's cross-section, local axes.
    auto local_section = [&](const YarnShadingPoint& y) {
        CurvePoint c = axis;
        const float along = dot(y.position - axis.position, axis.tangent);
        c.position += axis.tangent * along;
        c.arc_length += along;
        PlySection ps = ply_section(c, desc, twist, y.ply_index, y.position);
        ps.tangent = frame_.to_local(ps.tangent);
        ps.hit_outward = frame_.to_local(ps.hit_outward);
        ps.offset = frame_.to_local(ps.offset);
        return ps;
    };

    if (settings.aggregation == MultiscaleAggregation::Aggregate) {
        BysdfParams p = params;
        p.ply_color_count = 1;
        p.ply_colors[0] = tint_sum;
        BysdfShadingPoint bp{gp, gf, std::max(1, static_cast<int>(std::lround(crossed))), 0, yarn.yarn_color,
                             yarn.maps->mean_fiber_shadowing()};
        Component& c = components_[0];
        c.bsdf.emplace(p, bp);
        c.frame = Frame();
        c.offset = frame_.to_local(rep.position - axis.position) / radius;
        c.h = hit_h[nearest];
        c.weight = 1;
        c.ply = rep.ply_index;
        if (crossing_) c.section = local_section(rep);
        c.crossing_colors = c.bsdf->pass_on();
        count_ = 1;
        same_frame_ = true;
        return;
    }
    for (int k = 0; k < hit_count; ++k) {
        const YarnShadingPoint& y = hits[k];
        Component& c = components_[k];
        const BysdfShadingPoint point{y.ply_shadowing, y.fiber_shadowing, std::max(1, y.plies_crossed),
                                      y.ply_index, yarn.yarn_color, yarn.maps->mean_fiber_shadowing()};
        c.bsdf.emplace(params, point);
        const Frame f = Frame::from_normal_tangent(y.fiber_normal, y.fiber_tangent);
        c.frame.s = frame_.to_local(f.s);
        c.frame.t = frame_.to_local(f.t);
        c.frame.n = frame_.to_local(f.n);
        c.offset = frame_.to_local(y.position - axis.position) / radius;
        c.h = hit_h[k];
        c.weight = hit_len[k] / hit_length;
        c.ply = y.ply_index;
        if (crossing_) c.section = local_section(y);
        c.crossing_colors = yarn.crossing_colors ? Bysdf(*yarn.crossing_colors, point).pass_on() : c.bsdf->pass_on();
    }
    count_ = hit_count;
    same_frame_ = single;
}

float MultiscaleBysdf::pass_distance() const {
    if (!frames_) return 0.0f;
    return tube_chord_length(*frames_, axis_segment_, axis_t_, entry_.point, entry_.direction);
}

BsdfEvalPdf MultiscaleBysdf::component_eval(const Component& c, Vec3 wo_k, Vec3 wi_k, Vec3 wi, Vec3* crossed) const {
    if (crossing_) {  // every leaving ray may cross other plies
        const float chord = chord_in_radii(c.offset, axis_tangent_, wi);
        PlyCrossings plies = cross_plies(c.section, *crossing_, c.ply, wi, chord);
        if (crossed) {  // A_k apart: the BYSDF then attenuates by the hit ply's own path only
            *crossed = c.crossing_colors.product(plies);
            plies.others = 0;
        }
        return c.bsdf->eval_pdf(wo_k, wi_k, {chord, &plies});
    }
    const float chord = wo_k.z * wi_k.z < 0 ? chord_in_radii(c.offset, axis_tangent_, wi) : 0.0f;
    return c.bsdf->eval_pdf(wo_k, wi_k, {chord});
}

Vec3 MultiscaleBysdf::component_integrand(int k, Vec3 wo, Vec3 wi, float* pdf, Vec3* crossed) const {
    const Component& c = components_[k];
    const Vec3 wo_k = c.frame.to_local(wo), wi_k = c.frame.to_local(wi);
    if (crossed) *crossed = Vec3(1.0f);
    const BsdfEvalPdf e = component_eval(c, wo_k, wi_k, wi, crossed);
    if (pdf) *pdf += c.weight * e.pdf;
    return e.f * (c.weight * std::fabs(wi_k.z));
}

BsdfEvalPdf MultiscaleBysdf::evaluate(Vec3 wo, Vec3 wi) const {
    BsdfEvalPdf out;
    if (same_frame_) return component_eval(components_[0], wo, wi, wi);
    const float cos_ref = std::fabs(wi.z);
    for (int k = 0; k < count_; ++k) out.f += component_integrand(k, wo, wi, &out.pdf);
    // f~ |cos_ref| is the integrand; the reference plane itself carries nothing.
    out.f = cos_ref > kMinCos ? out.f / cos_ref : Vec3(0.0f);
    return out;
}

std::optional<BsdfSample> MultiscaleBysdf::sample(Vec3 wo, float u_lobe, Vec2 u, ExitQuery*) const {
    if (count_ == 0) return std::nullopt;
    // Pick h_k by its weight and stretch u_lobe back to [0, 1) for the BYSDF's own lobe choice.
    int k = 0;
    float below = 0;
    while (k + 1 < count_ && u_lobe >= below + components_[k].weight) below += components_[k++].weight;
    const Component& c = components_[k];
    const float u_k = clamp((u_lobe - below) / c.weight, 0.0f, 0x1.fffffep-1f);
    const std::optional<BsdfSample> s = c.bsdf->sample(c.frame.to_local(wo), u_k, u);
    if (!s) return std::nullopt;
    BsdfSample out = *s;
    out.wi = c.frame.to_world(s->wi);
    const BsdfEvalPdf e = evaluate(wo, out.wi);
    out.f = e.f;
    out.pdf = e.pdf;
    if (!(out.pdf > 0)) return std::nullopt;
    return out;
}

}  // namespace purl
