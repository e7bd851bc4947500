// Reference geometry for validating the implicit plies: the same plies as explicit helix
// tubes (ply_helix.h) around the same centre-line, intersected exactly. Favours accuracy over
// speed: a sphere trace with a guaranteed lower bound of the distance to every tube (a dense
// polyline of each centre-line, minus the polyline's measured deviation from the curve),
// then Newton steps and bisection on the exact distance to the helix (closest point by Newton
// on the curve parameter). It cannot skip a tube, so it also finds grazing hits.
#pragma once
#include <cstdint>
#include <vector>

#include "yarn/curve_frames.h"
#include "yarn/ply_helix.h"
#include "yarn/yarn_description.h"

namespace purl {

struct ExplicitHit {
    bool hit = false;
    bool resolved = true;  // false when the step budget ran out (counted, never guessed)
    int ply = -1;          // -1 for the yarn tube
    float distance = 0;    // ray parameter of the hit, m
    Vec3 point, normal, tangent;  // normal away from the centre-line; tangent unit along increasing t
    uint32_t segment = 0;  // centre-line parameter of the closest centre-line point
    float t = 0;
    int steps = 0;
};

class ExplicitPlies {
public:
    // spacing: polyline sample spacing in yarn radii (accuracy does not depend on it, speed does).
    ExplicitPlies(const CurveFrames& frames, const YarnDescription& d, float spacing = 0.1f);

    // First hit of the ray o + d * lambda, lambda in [tmin, tmax], with any ply tube.
    ExplicitHit intersect_plies(Vec3 origin, Vec3 direction, float tmin, float tmax) const;
    // First hit with one ply's tube only (for counting the plies a ray crosses).
    ExplicitHit intersect_ply(int ply, Vec3 origin, Vec3 direction, float tmin, float tmax) const;
    // First hit with the yarn tube itself (what Embree's round curve reports).
    ExplicitHit intersect_tube(Vec3 origin, Vec3 direction, float tmin, float tmax) const;
    // Ray parameter where a ray inside the tube at `inside` leaves it (first exit).
    float tube_exit(Vec3 origin, Vec3 direction, float inside, float tmax, uint32_t segment, float t) const;

    size_t memory_bytes() const;

private:
    struct Sample {
        Vec3 position;
        float radius;  // tube radius at the sample, m
        float g;       // curve parameter: segment index + t
    };
    struct Chunk {
        Vec3 centre;
        float extent;      // bounding-sphere radius of the chunk's polyline, m
        float max_radius;  // largest tube radius in the chunk, m
        uint32_t begin, end;  // samples [begin, end] (end inclusive: pieces begin..end-1)
    };
    struct Strand {
        std::vector<Sample> samples;
        std::vector<Chunk> chunks;
        float deviation = 0;  // bound on the curve's distance from its polyline, m
    };
    struct Nearest {
        float bound;  // lower bound of the distance to the tube surface, m
        float g;      // curve parameter near the closest polyline point
    };

    Vec3 strand_point(int strand, double g, float* radius) const;
    Nearest lower_bound(int strand, Vec3 x, float cutoff, const std::vector<uint32_t>& active_chunks) const;
    // Exact distance to the tube surface (negative inside) from Newton on the curve parameter.
    float exact_distance(int strand, Vec3 x, double& g) const;
    ExplicitHit trace(int first_strand, int last_strand, Vec3 origin, Vec3 direction, float tmin, float tmax) const;
    double wrap(double g) const;

    const CurveFrames& frames_;
    YarnDescription description_;
    YarnTwist twist_;
    std::vector<Strand> strands_;  // 0: yarn centre-line, 1 + i: ply i
    float unit_ = 1;               // reference yarn radius, m
};

}  // namespace purl
