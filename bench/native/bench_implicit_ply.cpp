// One implicit yarn query (plies + fiber maps) against tracing explicit plies for the same rays.
//
//   BM_Implicit        trace_yarn_hit: elliptical plies + fiber frame + G_p/G_f (given the tube hit)
//   BM_ImplicitAllRays BM_Implicit over all 512 rays per iteration, 4 iterations (fixed work:
//                      for instruction counts, e.g. valgrind --tool=callgrind)
//   BM_ImplicitPlies   trace_plies only (elliptical)
//   BM_Local           trace_yarn_hit with the local method (yarn straightened at the hit)
//   BM_LocalPlies      trace_plies only (local)
//   BM_Circular        trace_plies with the circular cross-section (the older method)
//   BM_Shared          a lower bound of what any implicit query does besides its ply search: the
//                      centre-line projection of the tube hit and the fiber maps/shading frame of
//                      the exact method's ply hit (prepared); the hit's own frame is left out
//   BM_EmbreeTube      Embree ray against the yarn's round B-spline curve (what precedes BM_Implicit)
//   BM_EmbreePlies     Embree ray against every ply as its own round B-spline curve (ply-based model)
//   BM_ExactPlies      our exact explicit reference (sphere tracing; accuracy first)
//   BM_CurveEvaluation one curve frame plus one ply centre: the unit of work inside a query
//   BM_TubeChord       tube_chord_length from the tube entry along the ray (what the renderer
//                      asks twice per scattering event); second argument: bend radius in R
//                      (0 = straight yarn)
// Arguments: plies, view angle (degrees). Rays (random side, offset, position) are prepared
// outside the timed loop from the explicit yarn tube, as Embree would report them.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "math/rng.h"
#include "reference/explicit_plies.h"
#include "reference/ply_validation.h"
#include "yarn/yarn_shading_point.h"
#include "yarn/yarn_tube.h"

namespace purl {
namespace {

constexpr int kRays = 512;

// A straight yarn of radius 1 and its plies, Embree scenes of both, and prepared rays.
struct Setup {
    YarnDescription description;
    std::vector<Vec4> points = validation_curve(0.0f);
    CurveFrames frames{CurveView::chain(points.data(), static_cast<uint32_t>(points.size()), false)};
    FiberMaps maps;
    ExplicitPlies plies;
    std::vector<YarnTubeHit> hits;
    std::vector<PlyHit> ply_hits;  // the exact method's answer for each of `hits`
    RTCDevice device = nullptr;
    RTCScene tube_scene = nullptr, ply_scene = nullptr;

    Setup(int ply_count, float view_degrees)
        : description(touching_plies(ply_count)), maps(description), plies(frames, description) {
        device = rtcNewDevice(nullptr);
        tube_scene = curve_scene({points.begin(), points.end()});
        // Each ply as a B-spline through samples of its helix every 0.25 R (what a ply-based
        // renderer stores; the small shrinkage of a B-spline through its points does not matter
        // for timing).
        const YarnTwist tw = yarn_twist(frames, description);
        std::vector<std::vector<Vec4>> ply_points(ply_count);
        for (uint32_t s = 0; s < frames.segment_count(); ++s)
            for (int j = 0; j < 4; ++j) {
                const CurvePoint c = frames.evaluate(s, j / 4.0f);
                for (int p = 0; p < ply_count; ++p) {
                    const PlyCentre pc = ply_centre(c, description, tw, p);
                    ply_points[p].emplace_back(pc.position, pc.radius);
                }
            }
        ply_scene = rtcNewScene(device);
        for (const auto& pts : ply_points) add_curve(ply_scene, pts);
        rtcCommitScene(ply_scene);

        Rng rng(11, static_cast<uint64_t>(ply_count * 100 + view_degrees));
        const float psi = view_degrees * kPi / 180;
        while (static_cast<int>(hits.size()) < kRays) {
            const float z = 30 + 18 * rng.next_float(), side = 2 * kPi * rng.next_float();
            const float offset = 2 * rng.next_float() - 1;
            const Vec3 toward(std::cos(side), std::sin(side), 0), across(-std::sin(side), std::cos(side), 0);
            const Vec3 dir = normalize(toward * -std::cos(psi) + Vec3(0, 0, std::sin(psi)));
            const Vec3 origin = Vec3(0, 0, z) + across * offset - dir * 30.0f;
            const ExplicitHit tube = plies.intersect_tube(origin, dir, 0, 60);
            if (tube.hit) hits.push_back({origin, dir, tube.point, tube.segment, tube.t});
        }
        const YarnTwist twist = yarn_twist(frames, description);
        for (const YarnTubeHit& h : hits) ply_hits.push_back(trace_plies({frames, description, twist, h}));
    }
    ~Setup() {
        rtcReleaseScene(tube_scene);
        rtcReleaseScene(ply_scene);
        rtcReleaseDevice(device);
    }
    RTCScene curve_scene(const std::vector<Vec4>& pts) {
        RTCScene scene = rtcNewScene(device);
        add_curve(scene, pts);
        rtcCommitScene(scene);
        return scene;
    }
    void add_curve(RTCScene scene, const std::vector<Vec4>& pts) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE);
        auto* v = static_cast<Vec4*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, sizeof(Vec4), pts.size()));
        std::copy(pts.begin(), pts.end(), v);
        auto* index = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(unsigned), pts.size() - 3));
        for (size_t i = 0; i + 3 < pts.size(); ++i) index[i] = static_cast<unsigned>(i);
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene, g);
        rtcReleaseGeometry(g);
    }
    float embree_hit(RTCScene scene, const YarnTubeHit& h) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh{};
        rh.ray.org_x = h.origin.x, rh.ray.org_y = h.origin.y, rh.ray.org_z = h.origin.z;
        rh.ray.dir_x = h.direction.x, rh.ray.dir_y = h.direction.y, rh.ray.dir_z = h.direction.z;
        rh.ray.tnear = 0;
        rh.ray.tfar = 1e30f;
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &rh);
        return rh.ray.tfar;
    }
};

Setup& setup(int plies, int view) {
    static std::map<std::pair<int, int>, std::unique_ptr<Setup>> cache;
    auto& s = cache[{plies, view}];
    if (!s) s = std::make_unique<Setup>(plies, static_cast<float>(view));
    return *s;
}

void query(benchmark::State& state, PlyCrossSection method) {
    Setup& s = setup(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    PlyTraceOptions o;
    o.cross_section = method;
    size_t i = 0;
    for (auto _ : state) {
        const YarnShadingPoint sp = trace_yarn_hit(s.frames, s.description, s.maps, s.hits[i++ % kRays], 3, o);
        benchmark::DoNotOptimize(sp);
    }
}
void BM_Implicit(benchmark::State& state) { query(state, PlyCrossSection::elliptical); }
void BM_Local(benchmark::State& state) { query(state, PlyCrossSection::local); }

// Every prepared ray once per iteration, a fixed number of iterations: the same work in every
// run, for instruction counts under callgrind (time per ray = reported time / 512).
void BM_ImplicitAllRays(benchmark::State& state) {
    Setup& s = setup(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    for (auto _ : state)
        for (const YarnTubeHit& h : s.hits) benchmark::DoNotOptimize(trace_yarn_hit(s.frames, s.description, s.maps, h, 3));
}


void plies_only(benchmark::State& state, PlyCrossSection method) {
    Setup& s = setup(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    PlyTraceOptions o;
    o.cross_section = method;
    size_t i = 0;
    for (auto _ : state) {
        const YarnTwist twist = yarn_twist(s.frames, s.description);  // per query, as before PlyQuery
        benchmark::DoNotOptimize(trace_plies({s.frames, s.description, twist, s.hits[i++ % kRays]}, o));
    }
}
void BM_ImplicitPlies(benchmark::State& state) { plies_only(state, PlyCrossSection::elliptical); }
void BM_LocalPlies(benchmark::State& state) { plies_only(state, PlyCrossSection::local); }
void BM_Circular(benchmark::State& state) { plies_only(state, PlyCrossSection::circular); }

void BM_Shared(benchmark::State& state) {
    Setup& s = setup(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    size_t i = 0;
    for (auto _ : state) {
        const size_t k = i++ % kRays;
        const YarnTubeHit& h = s.hits[k];
        benchmark::DoNotOptimize(project_to_centreline(s.frames, h.point, h.segment, h.t));
        benchmark::DoNotOptimize(shade_ply_hit(s.ply_hits[k], s.frames, s.description, s.maps, 3));
    }
}

void BM_EmbreeTube(benchmark::State& state) {
    Setup& s = setup(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    size_t i = 0;
    for (auto _ : state) benchmark::DoNotOptimize(s.embree_hit(s.tube_scene, s.hits[i++ % kRays]));
}

void BM_EmbreePlies(benchmark::State& state) {
    Setup& s = setup(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    size_t i = 0;
    for (auto _ : state) benchmark::DoNotOptimize(s.embree_hit(s.ply_scene, s.hits[i++ % kRays]));
}

void BM_ExactPlies(benchmark::State& state) {
    Setup& s = setup(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
    size_t i = 0;
    for (auto _ : state) {
        const YarnTubeHit& h = s.hits[i++ % kRays];
        benchmark::DoNotOptimize(s.plies.intersect_plies(h.origin, h.direction, 0, 60));
    }
}

// The unit of work inside a query: the yarn's centre-line and frame at one parameter plus one
// ply centre there (what every scan point, Newton step and entry correction evaluates).
void BM_CurveEvaluation(benchmark::State& state) {
    Setup& s = setup(3, 0);
    const YarnTwist tw = yarn_twist(s.frames, s.description);
    size_t i = 0;
    for (auto _ : state) {
        const YarnTubeHit& h = s.hits[i++ % kRays];
        const CurvePoint c = s.frames.evaluate(h.segment, h.t);
        benchmark::DoNotOptimize(ply_centre(c, s.description, tw, static_cast<int>(i % 3)));
    }
}

// Chords through a straight yarn or a closed loop of the given bend radius (yarn radius 1),
// from random tube entries in random inward directions.
struct ChordSetup {
    std::vector<Vec4> points;
    CurveFrames frames;
    struct Query {
        Vec3 point, direction;
        uint32_t segment;
        float t;
    };
    std::vector<Query> queries;
    explicit ChordSetup(float bend)
        : points(validation_curve(bend)),
          frames(CurveView::chain(points.data(), static_cast<uint32_t>(points.size()), bend > 0)) {
        const ExplicitPlies tube(frames, touching_plies(3));
        Rng rng(5, static_cast<uint64_t>(bend * 10));
        auto random_direction = [&] {
            return normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
        };
        while (static_cast<int>(queries.size()) < kRays) {
            const uint32_t segment = std::min(static_cast<uint32_t>(rng.next_float() * frames.segment_count()),
                                              frames.segment_count() - 1);
            const CurvePoint c = frames.evaluate(segment, rng.next_float());
            const Vec3 dir = random_direction();
            const ExplicitHit h = tube.intersect_tube(c.position - dir * 5.0f, dir, 0, 10);
            if (!h.hit) continue;
            Vec3 inward = random_direction();
            if (dot(inward, h.point - c.position) > 0) inward = -inward;
            queries.push_back({h.point, inward, h.segment, h.t});
        }
    }
};

void BM_TubeChord(benchmark::State& state) {
    static std::map<int, std::unique_ptr<ChordSetup>> cache;
    auto& s = cache[static_cast<int>(state.range(1))];
    if (!s) s = std::make_unique<ChordSetup>(static_cast<float>(state.range(1)));
    size_t i = 0;
    for (auto _ : state) {
        const ChordSetup::Query& q = s->queries[i++ % kRays];
        benchmark::DoNotOptimize(tube_chord_length(s->frames, q.segment, q.t, q.point, q.direction));
    }
}

void arguments(benchmark::internal::Benchmark* b) {
    for (int plies : {2, 3, 5, 12})
        for (int view : {0, 30, 60, 85}) b->Args({plies, view});
}

BENCHMARK(BM_Implicit)->Apply(arguments);
BENCHMARK(BM_ImplicitAllRays)->Apply(arguments)->Iterations(4);
BENCHMARK(BM_ImplicitPlies)->Apply(arguments);
BENCHMARK(BM_Local)->Apply(arguments);
BENCHMARK(BM_LocalPlies)->Apply(arguments);
BENCHMARK(BM_Circular)->Apply(arguments);
BENCHMARK(BM_Shared)->Apply(arguments);
BENCHMARK(BM_EmbreeTube)->Apply(arguments);
BENCHMARK(BM_EmbreePlies)->Apply(arguments);
BENCHMARK(BM_ExactPlies)->Apply(arguments);
BENCHMARK(BM_CurveEvaluation);
BENCHMARK(BM_TubeChord)->Args({3, 0})->Args({3, 4})->Args({3, 2});

}  // namespace
}  // namespace purl

BENCHMARK_MAIN();
