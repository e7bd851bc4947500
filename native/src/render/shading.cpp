#include "render/shading.h"

namespace purl {

ShadingPoint make_shading_point(const SceneDesc& scene, const SurfaceHit& hit, Vec3 wo) {
    ShadingPoint sp;
    // Both yarn tubes and meshes are shaded two-sided: the normal faces the viewer.
    const Vec3 n = dot(hit.geometric_normal, wo) >= 0 ? hit.geometric_normal : -hit.geometric_normal;
    if (hit.kind == SurfaceKind::Yarn) {
        const MaterialDesc& m = scene.yarns[hit.object].material;
        sp.frame = Frame::from_normal_tangent(n, hit.tangent);
        sp.bsdf = PlaceholderYarnBsdf{m.placeholder.color, m.placeholder.roughness, m.placeholder.specular};
    } else {
        const MeshDesc& mesh = scene.meshes[hit.object];
        sp.frame = Frame::from_normal(n);
        sp.bsdf = DiffuseBsdf{mesh.color};
        sp.holdout = mesh.holdout;
    }
    return sp;
}

}  // namespace purl
