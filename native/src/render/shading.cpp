#include "render/shading.h"

#include <array>
#include <cmath>
#include <limits>
#include <map>

#include "base/input_error.h"
#include "bsdf/ply_bsdf.h"
#include "math/bspline.h"
#include "math/ray_spawn.h"
#include "scene/yarn_set_frames.h"
#include "yarn/yarn_shading_point.h"
#include "yarn/yarn_tube.h"

namespace purl {

namespace {

// Bounce hits whose ray cone is at least this many ply radii wide take the circular method.
constexpr float kCoarseConePlies = 1.0f;

// The origin of a ray leaving a tube at `exit`, a point on its wall found by a search along
// the ray, whose centre-line parameter is (segment, t): the point is put back on the wall
// (the search stops within a tolerance of it) and moved off by the wall's float error.
Vec3 spawn_from_tube(const CurveFrames& tube, uint32_t segment, float t, Vec3 exit, Vec3 w) {
    const CurvePoint c = tube.evaluate_centreline(segment, t);
    Vec3 radial = exit - c.position;
    radial -= c.tangent * dot(radial, c.tangent);
    const float len = length(radial);
    SpawnPoint p;
    p.position = exit;
    p.normal = w;  // on the centre-line (a degenerate tube): straight on
    if (len > 0 && std::isfinite(len)) {
        p.normal = radial / len;
        p.position = c.position + p.normal * c.radius;
    }
    p.error = curve_point_error(tube.view().segment_points(segment));
    return spawn_origin(p, w);
}

}  // namespace

ShadingPoint::Exit ShadingPoint::leave(Vec3 wi) const {
    Exit exit;
    if (cylinder_radius > 0) {
        // Where the ray leaves the cylinder it starts in (0 when it heads outward); rays nearly
        // along the axis are cut at 20 radii, where the fiber has bent away anyway.
        const Vec3 q = position - cylinder_point;
        const Vec3 qp = q - cylinder_axis * dot(q, cylinder_axis), vp = wi - cylinder_axis * dot(wi, cylinder_axis);
        const float a = dot(vp, vp), b = dot(qp, vp), c = dot(qp, qp) - cylinder_radius * cylinder_radius;
        float chord = a > 1e-12f ? (-b + std::sqrt(std::max(0.0f, b * b - a * c))) / a : 0.0f;
        chord = clamp(chord, 0.0f, 20 * cylinder_radius);
        const Vec3 exit_q = qp + vp * chord;  // across the axis at the exit
        const float across = length(exit_q), along = dot(q + wi * chord, cylinder_axis);
        SpawnPoint p;
        p.position = position + wi * chord;
        p.normal = across > 0 ? exit_q / across : surface_normal;
        p.error = error + 0.5f * cylinder_curvature * along * along;
        exit.origin = spawn_origin(p, wi);
        return exit;
    }
    if (tube) {
        const TubeExit e = tube_exit(*tube, segment, t, position, wi);
        exit.origin = spawn_from_tube(*tube, e.segment, e.t, position + wi * e.distance, wi);
        exit.chord = e.distance / yarn_radius;
        if (yarn) {
            exit.crossed = true;
            exit.plies = cross_plies(section, *yarn, ply, wi, exit.chord);
        }
        return exit;
    }
    exit.origin = spawn_origin({position, surface_normal, error}, wi);
    return exit;
}

void SurfaceShader::pass_through(const SurfaceHit& hit, const Ray& ray, const CurveFrames& frames, float distance,
                                 SurfaceInteraction& out) {
    out.pass_through = true;
    const Vec3 exit = hit.position + ray.direction * distance;
    // The exit's centre-line parameter, by Newton from the entry's; a long way along the yarn
    // (a ray nearly along it) the search for the exit gives it.
    const CentrelineProjection at = project_to_centreline(frames, exit, hit.segment, hit.u);
    if (at.converged) {
        out.continue_origin = spawn_from_tube(frames, at.segment, at.t, exit, ray.direction);
        return;
    }
    const TubeExit e = tube_exit(frames, hit.segment, hit.u, hit.position, ray.direction);
    out.continue_origin = spawn_from_tube(frames, e.segment, e.t, hit.position + ray.direction * e.distance,
                                          ray.direction);
}

BsdfEvalPdf ShadingPoint::eval_pdf(Vec3 wo_world, Vec3 wi_world, const Exit& exit) const {
    return bsdf.eval_pdf(frame.to_local(wo_world), frame.to_local(wi_world), exit.context());
}

namespace {

// The exit of a sampled direction, asked by the model before it evaluates the sample; kept for
// the path's next ray.
class SampleExit final : public ExitQuery {
public:
    SampleExit(const ShadingPoint& sp, ShadingPoint::Exit& exit) : sp_(sp), exit_(exit) {}
    ScatterExit toward(Vec3 wi_local) override {
        exit_ = sp_.leave(sp_.frame.to_world(wi_local));
        asked_ = true;
        return exit_.context();
    }
    bool asked() const { return asked_; }

private:
    const ShadingPoint& sp_;
    ShadingPoint::Exit& exit_;
    bool asked_ = false;
};

}  // namespace

std::optional<BsdfSample> ShadingPoint::sample(Vec3 wo_world, float u_lobe, Vec2 u, Exit& exit) const {
    SampleExit query(*this, exit);
    std::optional<BsdfSample> s = bsdf.sample(frame.to_local(wo_world), u_lobe, u, &query);
    if (!s) return s;
    s->wi = frame.to_world(s->wi);
    if (!query.asked()) exit = leave(s->wi);  // models that do not attenuate: only the origin
    return s;
}

// One recoloured copy of the material per distinct curve colour (knits use a handful).
void SurfaceShader::recolor_bysdf(const BysdfParams& material, const std::vector<Vec3>& colors, YarnSetData& data) {
    std::map<std::array<float, 3>, uint32_t> index_of;
    data.colored_of_curve.reserve(colors.size());
    for (const Vec3& c : colors) {
        const auto [it, added] = index_of.try_emplace({c.x, c.y, c.z}, uint32_t(data.colored_bysdf.size()));
        if (added) data.colored_bysdf.push_back(with_body_color(material, c));
        data.colored_of_curve.push_back(it->second);
    }
}

SurfaceShader::SurfaceShader(const SceneDesc& scene) : scene_(scene) {
    ply_trace_.cross_section = scene.render.ply_method;
    coarse_trace_ = ply_trace_;
    coarse_trace_.cross_section = PlyCrossSection::circular;
    uint32_t key = 0;
    for (const YarnSetDesc& set : scene.yarns) {
        curve_key_base_.push_back(key);
        key += static_cast<uint32_t>(set.curves.curve_count());
        YarnSetData data;
        const MaterialDesc& m = set.material;
        switch (m.model) {
            case MaterialModel::Bysdf:
                data.frames = yarn_set_frames(set.curves);
                for (const CurveFrames& f : data.frames) data.yarn_twist.push_back(yarn_twist(f, m.yarn));
                data.maps = std::make_unique<FiberMaps>(m.yarn);
                // Yarn colours: the set's own curves.
                if (set.curves.has_colors()) recolor_bysdf(m.bysdf, set.curves.colors, data);
                break;
            case MaterialModel::Ply: {
                // The ply curves' own frames (for exits through the ply tube), and the yarns they
                // came from with the same frames, arc lengths and twist as the BYSDF scene.
                data.frames = yarn_set_frames(set.curves);
                data.maps = std::make_unique<FiberMaps>(m.yarn);
                const PlyOrigins& o = m.ply;
                if (!o.yarns || o.curves.size() != set.curves.curve_count())
                    throw InputError(scene.source, set.name, "a \"ply\" material needs the origins make_explicit_scene fills in");
                data.yarn_frames = yarn_set_frames(*o.yarns);
                data.yarn_arc.reserve(data.yarn_frames.size());
                for (const CurveFrames& f : data.yarn_frames) {
                    data.yarn_arc.emplace_back(f);
                    data.yarn_twist.push_back(yarn_twist(f, m.yarn));
                }
                // Yarn colours: the origin yarns'.
                if (o.yarns->has_colors()) recolor_bysdf(m.bysdf, o.yarns->colors, data);
                break;
            }
            case MaterialModel::Fiber:
                data.fiber = std::make_unique<FiberBcsdf>(m.fiber);
                break;
            case MaterialModel::Placeholder:
                break;
        }
        yarn_sets_.push_back(std::move(data));
    }
}

SurfaceShader::~SurfaceShader() = default;

size_t SurfaceShader::memory_bytes() const {
    size_t bytes = 0;
    for (const YarnSetData& d : yarn_sets_) {
        for (const CurveFrames& f : d.frames) bytes += f.memory_bytes();
        for (const CurveFrames& f : d.yarn_frames) bytes += f.memory_bytes();
        for (const ArcLengthIndex& a : d.yarn_arc) bytes += a.memory_bytes();
        bytes += d.yarn_twist.size() * sizeof(YarnTwist);
        if (d.maps) bytes += d.maps->memory_bytes();
        if (d.fiber) bytes += sizeof(FiberBcsdf);
        bytes += d.colored_bysdf.size() * sizeof(BysdfParams) + d.colored_of_curve.size() * sizeof(uint32_t);
    }
    return bytes;
}

SurfaceInteraction SurfaceShader::shade(const SurfaceHit& hit, const Ray& ray, const MultiscaleHitContext* multiscale,
                                        float cone_width) const {
    SurfaceInteraction out;
    ShadingPoint& sp = out.point;
    const Vec3 wo = -ray.direction;
    // Surfaces are shaded two-sided: the normal faces the viewer.
    const Vec3 n = dot(hit.geometric_normal, wo) >= 0 ? hit.geometric_normal : -hit.geometric_normal;
    sp.position = hit.position;
    sp.surface_normal = n;
    sp.error = hit.error;
    if (hit.kind == SurfaceKind::Mesh) {
        const MeshDesc& mesh = scene_.meshes[hit.object];
        sp.frame = Frame::from_normal(n);
        sp.bsdf = DiffuseBsdf{mesh.color};
        sp.holdout = mesh.holdout;
        return out;
    }
    const MaterialDesc& m = scene_.yarns[hit.object].material;
    switch (m.model) {
        case MaterialModel::Placeholder: shade_placeholder(hit, n, m, sp); return out;
        case MaterialModel::Ply: shade_ply(hit, ray, yarn_sets_[hit.object], m, out); return out;
        case MaterialModel::Fiber: shade_fiber(hit, wo, n, yarn_sets_[hit.object], sp); return out;
        case MaterialModel::Bysdf: break;
    }
    // BYSDF: find the ply and fiber under the tube hit.
    const YarnSetData& data = yarn_sets_[hit.object];
    const CurveFrames& frames = data.frames[hit.curve];
    YarnTubeHit tube_hit{ray.origin, ray.direction, hit.position, hit.segment, hit.u};
    if (multiscale && multiscale->selector) {
        out.multiscale_hit = true;
        out.h_samples = 1;  // near unless the selector says otherwise
        if (shade_multiscale(hit, ray, *multiscale, tube_hit, out)) return out;
    }
    // A bounce ray whose cone spans a ply averages the plies' exact shapes away: the cheap
    // circular cross-section finds its ply (docs/implicit-geometry.md measures what it changes).
    const bool coarse = !multiscale && cone_width >= kCoarseConePlies * m.yarn.ply_radius * hit.radius;
    const YarnShadingPoint y = trace_yarn_hit(frames, m.yarn, data.yarn_twist[hit.curve], *data.maps, tube_hit,
                                              curve_key_base_[hit.object] + hit.curve, coarse ? coarse_trace_ : ply_trace_);
    if (!y.hit) {
        pass_through(hit, ray, frames, y.exit_distance, out);
        return out;
    }
    sp.position = y.position;
    sp.frame = Frame::from_normal_tangent(y.fiber_normal, y.fiber_tangent);
    sp.tube = &frames;
    sp.segment = y.segment;  // the ply point's own cross-section: chords start there
    sp.t = y.t;
    sp.yarn_radius = hit.radius;
    BysdfShadingPoint bp;
    bp.ply_shadow = y.ply_shadowing;
    bp.fiber_shadow = y.fiber_shadowing;
    bp.plies_crossed = std::max(1, y.plies_crossed);
    bp.ply_index = y.ply_index;
    bp.mean_fiber_shadow = data.maps->mean_fiber_shadowing();
    const Bysdf bysdf(data.bysdf(m, hit.curve), bp);
    sp.bsdf = bysdf;
    if (bysdf.traces_plies()) {
        sp.yarn = &m.yarn;
        sp.ply = y.ply_index;
        sp.section = ply_section(frames.evaluate(y.segment, y.t), m.yarn, data.yarn_twist[hit.curve], y.ply_index,
                                 y.position);
    }
    out.ply_index = y.ply_index;
    out.u_ply = y.u_ply;
    out.v_ply = y.v_ply;
    return out;
}

bool SurfaceShader::shade_multiscale(const SurfaceHit& hit, const Ray& ray, const MultiscaleHitContext& context,
                                     const YarnTubeHit& tube_hit, SurfaceInteraction& out) const {
    const MultiscaleSettings& ms = context.selector->settings();
    if (ms.mode == MultiscaleMode::Near || !ray.has_differentials) return false;
    const MaterialDesc& m = scene_.yarns[hit.object].material;
    const YarnSetData& data = yarn_sets_[hit.object];
    const CurveFrames& frames = data.frames[hit.curve];
    MultiscaleQuery q;
    q.tube = tube_hit;
    q.axis = project_to_centreline(frames, hit.position, hit.segment, hit.u);
    q.footprint = yarn_footprint(ray, hit.position, q.axis.point, ms.footprint_scale);
    q.mode = context.selector->choose(q.footprint, m.yarn);
    q.u_strata = context.u_strata;
    if (q.mode == MultiscaleMode::Near) return false;
    if (q.mode == MultiscaleMode::Far && !q.footprint.along_yarn) {
        if (const FarFieldTable* table = context.selector->far_table(hit.object, m.yarn, m.bysdf)) {
            shade_far(hit, ray, context, *table, q.axis, out);
            return true;
        }
    }
    const MultiscaleYarn yarn{&frames, &m.yarn, data.maps.get(), &data.bysdf(m, hit.curve),
                              curve_key_base_[hit.object] + hit.curve, Vec3(1.0f), ply_trace_};
    MultiscaleBysdf model(yarn, ms, q);
    out.multiscale_mode = model.mode();  // near when the footprint turned out empty
    out.h_samples = model.samples();
    if (model.empty() || context.u_pass < model.pass_fraction()) {
        // This share of the footprint lies between the plies: go on as a near-field miss does.
        pass_through(hit, ray, frames, model.pass_distance(), out);
        return true;
    }
    ShadingPoint& sp = out.point;
    sp.position = model.position();
    sp.frame = model.frame();
    sp.tube = &frames;
    sp.segment = model.segment();
    sp.t = model.t();
    sp.yarn_radius = hit.radius;
    out.ply_index = model.ply();
    out.u_ply = model.u_ply();
    out.v_ply = model.v_ply();
    sp.bsdf = std::move(model);
    return true;
}

void SurfaceShader::shade_far(const SurfaceHit& hit, const Ray& ray, const MultiscaleHitContext& context,
                              const FarFieldTable& table, const CentrelineProjection& axis,
                              SurfaceInteraction& out) const {
    const YarnSetData& data = yarn_sets_[hit.object];
    const CurveFrames& frames = data.frames[hit.curve];
    const Vec3 wo = -ray.direction, tangent = axis.point.tangent;
    out.multiscale_mode = MultiscaleMode::Far;
    out.h_samples = 0;
    ShadingPoint& sp = out.point;
    // +z: the view direction across the yarn (not along_yarn, so it has length), +x: the yarn.
    sp.frame = Frame::from_normal_tangent(normalize(wo - tangent * dot(wo, tangent)), tangent);
    const FarFieldBsdf far(table, data.bysdf(scene_.yarns[hit.object].material, hit.curve));
    if (context.u_pass < far.pass_fraction(sp.frame.to_local(wo))) {
        pass_through(hit, ray, frames, tube_chord_length(frames, axis.segment, axis.t, hit.position, ray.direction),
                     out);
        return;
    }
    // Light scatters at the tube entry: a sub-pixel yarn's depth does not show.
    sp.position = hit.position;
    sp.tube = &frames;
    sp.segment = axis.segment;
    sp.t = axis.t;
    sp.yarn_radius = hit.radius;
    sp.bsdf = far;
}

void SurfaceShader::shade_ply(const SurfaceHit& hit, const Ray& ray, const YarnSetData& data, const MaterialDesc& m,
                              SurfaceInteraction& out) const {
    // The ply centre-line point under the hit and the ply normal there.
    const CurveFrames& ply = data.frames[hit.curve];
    const CentrelineProjection c = project_to_centreline(ply, hit.position, hit.segment, hit.u);
    const Vec3 tangent = c.point.tangent;
    Vec3 radial = hit.position - c.point.position;
    radial -= tangent * dot(radial, tangent);
    const float len = length(radial);
    Vec3 normal = len > 1e-12f * c.point.radius ? radial / len : -ray.direction - tangent * dot(-ray.direction, tangent);
    normal = normalize(normal);
    if (!is_finite(normal)) normal = hit.geometric_normal;

    // Back to the yarn cross-section this point of the ply came from: the ply's knots sit at
    // even steps of yarn arc length, so its curve parameter maps linearly onto v_yarn.
    const PlyCurveOrigin& o = m.ply.curves[hit.curve];
    const CurveFrames& yarn_frames = data.yarn_frames[o.yarn_curve];
    float s = o.arc_start + (float(c.segment) + c.t) * o.arc_step;
    const float loop = yarn_frames.total_length();
    if (yarn_frames.closed() && loop > 0) s -= loop * std::floor(s / loop);
    CurveParam yarn_param;
    const CurvePoint yarn = data.yarn_arc[o.yarn_curve].point_at(s, &yarn_param);
    const YarnTwist& twist = data.yarn_twist[o.yarn_curve];
    const PlyCentre centre = ply_centre(yarn, m.yarn, twist, o.ply);

    // The same ply hit the implicit model would report, so the fiber maps are read alike.
    PlyHit h;
    h.hit = true;
    h.ply = o.ply;
    h.plies_crossed = 1;
    h.point = hit.position;
    h.normal = normal;
    h.tangent = tangent;
    h.outward = normalize(centre.outward - tangent * dot(centre.outward, tangent));
    const Vec3 side = cross(tangent, h.outward);
    const float u_ply = std::atan2(dot(normal, side), dot(normal, h.outward));
    h.u_ply = u_ply < 0 ? u_ply + 2 * kPi : u_ply;
    h.v_ply = yarn.arc_length * twist.ply_stretch;
    h.u_yarn = CurveFrames::azimuth(yarn, hit.position);
    h.v_yarn = yarn.arc_length;
    h.segment = yarn_param.segment;
    h.t = yarn_param.t;
    const YarnShadingPoint y = shade_ply_hit(h, yarn_frames, m.yarn, twist, *data.maps, m.ply.key_base + o.yarn_curve);
    out.ply_index = o.ply;
    out.u_ply = h.u_ply;
    out.v_ply = h.v_ply;

    ShadingPoint& sp = out.point;
    sp.position = hit.position;
    sp.frame = Frame::from_normal_tangent(y.fiber_normal, y.fiber_tangent);
    sp.tube = &ply;  // rays leave through this ply's tube; other plies are traced
    sp.segment = c.segment;
    sp.t = c.t;
    sp.yarn_radius = c.point.radius / std::max(m.yarn.ply_radius, 1e-6f);  // chords stay per yarn radius
    sp.bsdf = make_ply_bsdf(data.bysdf(m, o.yarn_curve), y.fiber_shadowing, o.ply);
}

void SurfaceShader::shade_placeholder(const SurfaceHit& hit, Vec3 normal, const MaterialDesc& m, ShadingPoint& sp) const {
    sp.frame = Frame::from_normal_tangent(normal, hit.tangent);
    PlaceholderYarnBsdf placeholder = make_placeholder_bsdf(m.placeholder);
    const YarnCurves& curves = scene_.yarns[hit.object].curves;
    if (curves.has_colors())  // same rule as the BYSDF body albedos (docs/bysdf.md)
        placeholder.color = recolored_albedo(m.placeholder.color, curves.colors[hit.curve]);
    sp.bsdf = placeholder;
}

void SurfaceShader::shade_fiber(const SurfaceHit& hit, Vec3 wo, Vec3 normal, const YarnSetData& data,
                                ShadingPoint& sp) const {
    // Any normal around the fiber gives the same light (fiber_bcsdf.h); face the viewer.
    const Vec3 t = hit.tangent;
    const Vec3 across = wo - t * dot(wo, t);
    const float len = length(across);
    sp.frame = Frame::from_normal_tangent(len > 1e-6f ? across / len : normal, t);
    sp.bsdf = FiberBcsdfRef{data.fiber.get()};
    const Vec4* cp = &scene_.yarns[hit.object].curves.control_points[hit.primitive];
    const Vec3 p[4] = {cp[0].xyz(), cp[1].xyz(), cp[2].xyz(), cp[3].xyz()};
    sp.cylinder_point = bspline_point(p, hit.u);
    sp.cylinder_axis = t;
    sp.cylinder_radius = hit.radius;
    const Vec3 d1 = bspline_tangent(p, hit.u), d2 = bspline_combine(p, bspline_basis_second_derivative(hit.u));
    const float speed = length(d1);
    sp.cylinder_curvature = speed > 0 ? length(cross(d1, d2)) / (speed * speed * speed) : 0.0f;
}

}  // namespace purl
