#include "scene/embree_scene.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "math/bspline.h"
#include "math/ray_spawn.h"

namespace purl {

namespace {

// Embree reports every allocation here; the running total is the structure's size.
bool count_memory(void* user, ssize_t bytes, bool /*post*/) {
    static_cast<std::atomic<long long>*>(user)->fetch_add(bytes);
    return true;
}

[[noreturn]] void embree_failed(RTCDevice device, const char* what) {
    throw std::runtime_error(std::string("Embree: ") + what + " failed (error " +
                             std::to_string(static_cast<int>(rtcGetDeviceError(device))) + ")");
}

// The hit on a round curve segment put back on Embree's surface: the centre-line point at u
// plus the radius there, along the hit's offset from it without its tangential part (Embree
// solves (hit - P(u)) . T(u) = 0, |hit - P(u)| = r(u)). Its iteration stops within a
// tolerance, and origin + t dir adds the rounding of t times the ray's length.
Vec3 onto_curve(const Vec3* p, float u, float radius, Vec3 raw) {
    const Vec3 centre = bspline_point(p, u), tangent = bspline_tangent(p, u);
    const float tl2 = dot(tangent, tangent);
    Vec3 radial = raw - centre;
    if (tl2 > 0) radial -= tangent * (dot(radial, tangent) / tl2);
    const float len = length(radial);
    if (!(len > 0) || !std::isfinite(len)) return raw;  // on the axis (a degenerate ray): keep it
    return centre + radial * (radius / len);
}

}  // namespace

const char* EmbreeScene::requested_isa() {
    const char* isa = std::getenv("PURL_EMBREE_ISA");
    if (!isa || !*isa) return nullptr;
    // Embree takes any other word for SSE2 without a warning: refuse it here.
    for (const char* known : {"sse2", "sse4.2", "avx", "avx2", "avx512"})
        if (std::string(isa) == known) return isa;
    throw std::runtime_error(std::string("PURL_EMBREE_ISA=") + isa +
                             ": not an instruction set Embree knows (sse2, sse4.2, avx, avx2, avx512)");
}

EmbreeScene::EmbreeScene(const SceneDesc& scene) : scene_(scene) {
    // Build with TBB's threads, like the render.
    std::string config = "threads=0";
    if (const char* isa = requested_isa()) config += std::string(",isa=") + isa;
    device_ = rtcNewDevice(config.c_str());
    if (!device_)
        throw std::runtime_error("Embree: cannot create a device (config \"" + config +
                                 "\"; PURL_EMBREE_ISA must name an instruction set this CPU and Embree build have)");
    std::atomic<long long> bytes{0};
    rtcSetDeviceMemoryMonitorFunction(device_, count_memory, &bytes);
    rtc_scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(rtc_scene_, RTC_BUILD_QUALITY_HIGH);

    Vec3 lo(1e30f), hi(-1e30f);
    for (uint32_t y = 0; y < scene.yarns.size(); ++y) {
        const YarnCurves& curves = scene.yarns[y].curves;
        const std::vector<uint32_t>& index = curves.segment_first;
        for (const Vec4& p : curves.control_points) {
            lo = min(lo, p.xyz() - Vec3(p.w));
            hi = max(hi, p.xyz() + Vec3(p.w));
        }
        if (index.empty()) continue;
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE);
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                   curves.control_points.data(), 0, sizeof(Vec4),
                                   curves.control_points.size());
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, curves.segment_first.data(), 0,
                                   sizeof(uint32_t), index.size());
        rtcCommitGeometry(g);
        const uint32_t id = rtcAttachGeometry(rtc_scene_, g);
        rtcReleaseGeometry(g);
        if (geometries_.size() <= id) geometries_.resize(id + 1);
        geometries_[id] = {SurfaceKind::Yarn, y};
    }
    for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
        const MeshDesc& mesh = scene.meshes[m];
        if (mesh.indices.empty()) continue;
        for (const Vec3& p : mesh.vertices) {
            lo = min(lo, p);
            hi = max(hi, p);
        }
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree reads vertices with 16-byte loads: copy into a padded buffer it owns.
        float* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
        for (size_t i = 0; i < mesh.vertices.size(); ++i) {
            vertices[3 * i] = mesh.vertices[i].x;
            vertices[3 * i + 1] = mesh.vertices[i].y;
            vertices[3 * i + 2] = mesh.vertices[i].z;
        }
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                                   3 * sizeof(uint32_t), mesh.indices.size() / 3);
        rtcCommitGeometry(g);
        const uint32_t id = rtcAttachGeometry(rtc_scene_, g);
        rtcReleaseGeometry(g);
        if (geometries_.size() <= id) geometries_.resize(id + 1);
        geometries_[id] = {SurfaceKind::Mesh, m};
    }
    rtcCommitScene(rtc_scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) embree_failed(device_, "scene build");
    rtcSetDeviceMemoryMonitorFunction(device_, nullptr, nullptr);
    acceleration_bytes_ = static_cast<size_t>(std::max(0LL, bytes.load()));
    extent_ = hi.x >= lo.x ? std::max(length(hi - lo), 1e-6f) : 1.0f;
}

EmbreeScene::~EmbreeScene() {
    if (rtc_scene_) rtcReleaseScene(rtc_scene_);
    if (device_) rtcReleaseDevice(device_);
}

bool EmbreeScene::intersect(const Ray& ray, SurfaceHit& hit) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = ray.origin.x;
    rh.ray.org_y = ray.origin.y;
    rh.ray.org_z = ray.origin.z;
    rh.ray.dir_x = ray.direction.x;
    rh.ray.dir_y = ray.direction.y;
    rh.ray.dir_z = ray.direction.z;
    rh.ray.tnear = ray.tmin;
    rh.ray.tfar = ray.tmax;
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rtc_scene_, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;

    const GeometryRef& ref = geometries_[rh.hit.geomID];
    hit.t = rh.ray.tfar;
    hit.kind = ref.kind;
    hit.object = ref.object;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    Vec3 ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    const float len = length(ng);
    hit.geometric_normal = len > 0 ? ng / len : -ray.direction;
    if (ref.kind == SurfaceKind::Yarn) {
        const uint32_t first = scene_.yarns[ref.object].curves.segment_first[rh.hit.primID];
        hit.primitive = first;
        // The curve owning the segment, by binary search: no per-segment table in memory.
        const std::vector<uint32_t>& offsets = scene_.yarns[ref.object].curves.segment_offsets;
        hit.curve = static_cast<uint32_t>(
            std::upper_bound(offsets.begin(), offsets.end(), rh.hit.primID) - offsets.begin() - 1);
        hit.segment = rh.hit.primID - offsets[hit.curve];
        const Vec4* cp = scene_.yarns[ref.object].curves.control_points.data() + first;
        const Vec3 p[4] = {cp[0].xyz(), cp[1].xyz(), cp[2].xyz(), cp[3].xyz()};
        const Vec3 tangent = bspline_tangent(p, hit.u);
        const float tl = length(tangent);
        hit.tangent = tl > 0 ? tangent / tl : Vec3(0, 0, 1);
        const BSplineWeights w = bspline_basis(hit.u);
        hit.radius = cp[0].w * w.w[0] + cp[1].w * w.w[1] + cp[2].w * w.w[2] + cp[3].w * w.w[3];
        hit.position = onto_curve(p, hit.u, hit.radius, ray.at(hit.t));
        hit.error = curve_point_error(cp);
    } else {
        hit.primitive = rh.hit.primID;
        hit.curve = 0;
        hit.radius = 0.0f;
        const MeshDesc& mesh = scene_.meshes[ref.object];
        const uint32_t* tri = mesh.indices.data() + 3 * size_t(rh.hit.primID);
        const Vec3 a = mesh.vertices[tri[0]], b = mesh.vertices[tri[1]], c = mesh.vertices[tri[2]];
        hit.position = a * (1 - hit.u - hit.v) + b * hit.u + c * hit.v;
        hit.error = triangle_point_error(a, b, c);
    }
    return true;
}

bool EmbreeScene::occluded(Vec3 origin, Vec3 direction, float tmin, float tmax) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    r.org_x = origin.x;
    r.org_y = origin.y;
    r.org_z = origin.z;
    r.dir_x = direction.x;
    r.dir_y = direction.y;
    r.dir_z = direction.z;
    r.tnear = tmin;
    r.tfar = tmax;
    r.time = 0.0f;
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(rtc_scene_, &context, &r);
    return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

}  // namespace purl
