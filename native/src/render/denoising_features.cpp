#include "render/denoising_features.h"

#include <cmath>

namespace purl {
namespace {

Vec3 clamp01(Vec3 c) { return {clamp(c.x, 0.0f, 1.0f), clamp(c.y, 0.0f, 1.0f), clamp(c.z, 0.0f, 1.0f)}; }

// The transmission lobes lose light on the way through the yarn, by a chord the hit does not know
// yet; they count with the transmittance along the mean chord of a circle, pi/2 yarn radii (at
// the default extinction the specular transmission is then all but gone, as in the image).
constexpr float kMeanChord = 0.5f * kPi;

DenoisingAlbedo bysdf_albedo(const Bysdf& b, Vec3 wo) {
    Vec3 lobes[4];
    b.lobe_albedos(wo, lobes);
    lobes[Bysdf::kSpecularTransmission] *= b.transmittance(0, kMeanChord);
    lobes[Bysdf::kBodyTransmission] *= b.transmittance(1, kMeanChord);
    DenoisingAlbedo a;
    for (int i = 0; i < 4; ++i) {
        a.total += lobes[i];
        if (b.lobe_roughness(i) < kSharpAlpha) a.sharp += lobes[i];
    }
    return a;
}

// Models without a closed form (tabulated far field, fiber BCSDF): the mean sample weight
// f |cos| / pdf over a fixed stratified set, so the estimate is the same for every sample at the
// same wo and adds no noise of its own. Four samples: the pass averages over the pixel's samples.
template <class Model>
DenoisingAlbedo sampled_albedo(const Model& model, Vec3 wo) {
    constexpr int kSide = 2;
    Vec3 sum(0.0f);
    for (int i = 0; i < kSide; ++i)
        for (int j = 0; j < kSide; ++j) {
            const int k = i * kSide + j;
            const float u_lobe = (k + 0.5f) / (kSide * kSide);
            const std::optional<BsdfSample> s = model.sample(wo, u_lobe, Vec2((i + 0.5f) / kSide, (j + 0.5f) / kSide));
            if (s) sum += s->weight();
        }
    return {clamp01(sum / float(kSide * kSide)), Vec3(0.0f)};
}

struct AlbedoOf {
    Vec3 wo;
    DenoisingAlbedo operator()(const DiffuseBsdf& d) const { return {d.albedo, Vec3(0.0f)}; }
    DenoisingAlbedo operator()(const PlaceholderYarnBsdf& p) const {
        // The glossy lobe's Fresnel weight W (white) over the diffuse colour; masking losses aside.
        const float w = wo.z > 0 ? p.glossy_weight(wo) : 0.0f;
        return {Vec3(w) + p.color * (1.0f - w), Vec3(0.0f)};
    }
    DenoisingAlbedo operator()(const Bysdf& b) const { return bysdf_albedo(b, wo); }
    DenoisingAlbedo operator()(const MultiscaleBysdf& m) const {
        // The footprint's components, each in its own fiber frame, by their weights.
        DenoisingAlbedo a;
        for (int k = 0; k < m.components(); ++k) {
            const MultiscaleBysdf::Component& c = m.component(k);
            if (!c.bsdf) continue;
            const DenoisingAlbedo ak = bysdf_albedo(*c.bsdf, c.frame.to_local(wo));
            a.total += ak.total * c.weight;
            a.sharp += ak.sharp * c.weight;
        }
        return a;
    }
    template <class Model>
    DenoisingAlbedo operator()(const Model& model) const { return sampled_albedo(model, wo); }
};

}  // namespace

DenoisingAlbedo denoising_albedo(const ShadingPoint& sp, Vec3 wo_world) {
    DenoisingAlbedo a = sp.bsdf.visit(AlbedoOf{sp.frame.to_local(wo_world)});
    a.total = clamp01(a.total);
    a.sharp = clamp01(a.sharp);
    return a;
}

void DenoisingPath::record(const ShadingPoint& sp, Vec3 wo_world, const Camera& camera) {
    if (done_) return;
    if (sp.holdout) {  // nothing to denoise behind a cut-out
        done_ = true;
        return;
    }
    const DenoisingAlbedo a = denoising_albedo(sp, wo_world);
    if (average(a.sharp) > 0.75f * average(a.total)) {  // a mirror: look through it
        throughput_ *= a.sharp;
        return;
    }
    done_ = true;
    albedo_ = throughput_ * a.total;
    const Vec3 n = dot(sp.frame.n, wo_world) < 0 ? -sp.frame.n : sp.frame.n;  // two-sided: face the viewer
    normal_ = camera.to_camera(n);
}

}  // namespace purl
