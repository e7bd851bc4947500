#include "reference/explicit_plies.h"

#include <algorithm>
#include <cmath>

namespace purl {
namespace {

constexpr uint32_t kChunkPieces = 16;
constexpr int kMaxSteps = 20000;
constexpr double kDerivativeStep = 1e-2;  // curve parameter step of the central differences

float distance_to_piece(Vec3 x, Vec3 a, Vec3 b, float& fraction) {
    const Vec3 ab = b - a;
    const float len2 = dot(ab, ab);
    fraction = len2 > 0 ? clamp(dot(x - a, ab) / len2, 0.0f, 1.0f) : 0.0f;
    return length(x - (a + ab * fraction));
}

}  // namespace

ExplicitPlies::ExplicitPlies(const CurveFrames& frames, const YarnDescription& d, float spacing)
    : frames_(frames), description_(d), twist_(yarn_twist(frames, d)), unit_(frames.reference_radius()) {
    const uint32_t segments = frames.segment_count();
    strands_.resize(1 + d.plies());
    for (size_t k = 0; k < strands_.size(); ++k) {
        Strand& strand = strands_[k];
        const float stretch = k == 0 ? 1.0f : twist_.ply_stretch;
        for (uint32_t seg = 0; seg < segments; ++seg) {
            const float len = frames.evaluate(seg, 1).arc_length - frames.evaluate(seg, 0).arc_length;
            const int pieces = std::max(2, static_cast<int>(std::ceil(len * stretch / (spacing * unit_))));
            for (int j = 0; j < pieces; ++j) {
                const double g = seg + double(j) / pieces;
                Sample s;
                s.position = strand_point(static_cast<int>(k), g, &s.radius);
                s.g = static_cast<float>(g);
                strand.samples.push_back(s);
            }
        }
        Sample last;
        last.position = strand_point(static_cast<int>(k), segments, &last.radius);
        last.g = static_cast<float>(segments);
        strand.samples.push_back(last);

        // How far the curve strays from its polyline, measured at every piece's middle.
        float deviation = 0;
        for (size_t i = 0; i + 1 < strand.samples.size(); ++i) {
            const Sample &a = strand.samples[i], &b = strand.samples[i + 1];
            float r;
            const Vec3 mid = strand_point(static_cast<int>(k), 0.5 * (double(a.g) + double(b.g)), &r);
            deviation = std::max(deviation, length(mid - (a.position + b.position) * 0.5f));
        }
        strand.deviation = 1.5f * deviation + 1e-5f * unit_;

        for (uint32_t begin = 0; begin + 1 < strand.samples.size(); begin += kChunkPieces) {
            Chunk c;
            c.begin = begin;
            c.end = std::min<uint32_t>(begin + kChunkPieces, static_cast<uint32_t>(strand.samples.size()) - 1);
            Vec3 centre(0.0f);
            c.max_radius = 0;
            for (uint32_t i = c.begin; i <= c.end; ++i) {
                centre += strand.samples[i].position;
                c.max_radius = std::max(c.max_radius, strand.samples[i].radius);
            }
            c.centre = centre / float(c.end - c.begin + 1);
            c.extent = 0;
            for (uint32_t i = c.begin; i <= c.end; ++i)
                c.extent = std::max(c.extent, length(strand.samples[i].position - c.centre));
            strand.chunks.push_back(c);
        }
    }
}

double ExplicitPlies::wrap(double g) const {
    const double n = frames_.segment_count();
    if (frames_.closed()) {
        g = std::fmod(g, n);
        return g < 0 ? g + n : g;
    }
    return std::min(std::max(g, 0.0), n);
}

Vec3 ExplicitPlies::strand_point(int strand, double g, float* radius) const {
    g = wrap(g);
    const uint32_t segment = std::min(static_cast<uint32_t>(g), frames_.segment_count() - 1);
    const CurvePoint c = frames_.evaluate(segment, static_cast<float>(g - segment));
    if (strand == 0) {
        *radius = c.radius;
        return c.position;
    }
    const PlyCentre p = ply_centre(c, description_, twist_, strand - 1);
    *radius = p.radius;
    return p.position;
}

ExplicitPlies::Nearest ExplicitPlies::lower_bound(int strand_index, Vec3 x, float cutoff,
                                                  const std::vector<uint32_t>& active) const {
    const Strand& strand = strands_[strand_index];
    Nearest best{cutoff, 0};
    for (uint32_t index : active) {
        const Chunk& c = strand.chunks[index];
        if (length(x - c.centre) - c.extent - strand.deviation - c.max_radius >= best.bound) continue;
        for (uint32_t i = c.begin; i < c.end; ++i) {
            const Sample &a = strand.samples[i], &b = strand.samples[i + 1];
            float fraction;
            const float bound = distance_to_piece(x, a.position, b.position, fraction) - strand.deviation -
                                std::max(a.radius, b.radius);
            if (bound < best.bound) best = {bound, a.g + (b.g - a.g) * fraction};
        }
    }
    return best;
}

float ExplicitPlies::exact_distance(int strand, Vec3 x, double& g) const {
    // Newton on |x - P(g)|^2 with central differences of the exact centre-line.
    const double h = kDerivativeStep;
    float radius = 0;
    for (int it = 0; it < 30; ++it) {
        float r0, rp, rm;
        const Vec3 p0 = strand_point(strand, g, &r0), pp = strand_point(strand, g + h, &rp),
                   pm = strand_point(strand, g - h, &rm);
        const Vec3 d1 = (pp - pm) / float(2 * h), d2 = (pp - p0 * 2.0f + pm) / float(h * h);
        const Vec3 w = p0 - x;
        const double f = dot(w, d1);
        double fp = dot(d1, d1) + dot(w, d2);
        if (fp <= 0.1 * dot(d1, d1)) fp = dot(d1, d1);  // away from a minimum: gradient step
        const double step = std::max(-0.25, std::min(0.25, -f / std::max(fp, 1e-30)));
        g = wrap(g + step);
        if (std::fabs(step) < 1e-5) break;  // 1e-5 of a segment: float noise is near 1e-6
    }
    const Vec3 p = strand_point(strand, g, &radius);
    return length(x - p) - radius;
}

ExplicitHit ExplicitPlies::trace(int first, int last, Vec3 origin, Vec3 direction, float tmin,
                                 float tmax) const {
    ExplicitHit result;
    const float near = 0.02f * unit_, tolerance = 1e-5f * unit_;
    const int count = last - first + 1;
    std::vector<double> hint(count, -1.0);
    std::vector<float> bound(count);
    // Only chunks near the ray's span can matter: list them once per ray. Farther ones are
    // still bounded by the distance to the span, so the far bound stays valid.
    std::vector<std::vector<uint32_t>> active(count);
    const float span = std::max(tmax - tmin, 0.0f);
    const Vec3 a = origin + direction * tmin;
    for (int k = 0; k < count; ++k) {
        const Strand& strand = strands_[first + k];
        for (uint32_t i = 0; i < strand.chunks.size(); ++i) {
            const Chunk& c = strand.chunks[i];
            const float along = clamp(dot(c.centre - a, direction), 0.0f, span);
            if (length(a + direction * along - c.centre) - c.extent - strand.deviation - c.max_radius < 0.5f * unit_)
                active[k].push_back(i);
        }
    }
    float lambda = tmin, previous = tmin;
    for (int step = 0; step < kMaxSteps; ++step) {
        result.steps = step + 1;
        if (lambda > tmax) return result;
        const Vec3 x = origin + direction * lambda;
        float step_length = 1e30f;
        int closest = -1;
        float closest_distance = 1e30f;
        Vec3 closest_normal;
        for (int k = 0; k < count; ++k) {
            // Chunks off the ray's span are at least half a radius away from it.
            Nearest nb = lower_bound(first + k, x, 1e30f, active[k]);
            nb.bound = std::min(nb.bound, 0.5f * unit_);
            bound[k] = nb.bound;
            if (nb.bound >= near) {
                step_length = std::min(step_length, nb.bound);
                continue;
            }
            // Close to this tube: the exact distance, from the polyline's guess or the last one.
            double g = hint[k] >= 0 ? hint[k] : nb.g;
            float dist = exact_distance(first + k, x, g);
            const double g_poly = nb.g;
            if (hint[k] >= 0 && std::fabs(g - g_poly) > 0.5) {  // a stale hint found another minimum
                double g2 = g_poly;
                const float dist2 = exact_distance(first + k, x, g2);
                if (dist2 < dist) dist = dist2, g = g2;
            }
            hint[k] = g;
            step_length = std::min(step_length, std::max(dist, 0.0f));
            if (dist < closest_distance) {
                float r;
                closest_distance = dist;
                closest = k;
                closest_normal = normalize(x - strand_point(first + k, g, &r));
            }
        }
        if (closest >= 0 && closest_distance < tolerance) {
            // Inside or on the surface: if inside, bisect back to the surface.
            if (closest_distance < -tolerance) {
                float lo = previous, hi = lambda;
                for (int it = 0; it < 40; ++it) {
                    const float mid = 0.5f * (lo + hi);
                    double g = hint[closest];
                    if (exact_distance(first + closest, origin + direction * mid, g) > 0) lo = mid;
                    else hi = mid;
                }
                lambda = hi;
            }
            const Vec3 p = origin + direction * lambda;
            double g = hint[closest];
            exact_distance(first + closest, p, g);
            float r;
            const Vec3 c = strand_point(first + closest, g, &r);
            const Vec3 cp = strand_point(first + closest, g + kDerivativeStep, &r);
            const Vec3 cm = strand_point(first + closest, g - kDerivativeStep, &r);
            result.hit = true;
            result.ply = first + closest - 1;
            result.distance = lambda;
            result.point = p;
            result.normal = normalize(p - c);
            result.tangent = normalize(cp - cm);
            const double gw = wrap(g);
            result.segment = std::min(static_cast<uint32_t>(gw), frames_.segment_count() - 1);
            result.t = static_cast<float>(gw - result.segment);
            return result;
        }
        // Newton toward the closest tube, never past what the bounds allow for the others.
        float advance = step_length;
        if (closest >= 0) {
            const float approach = -dot(direction, closest_normal);
            float others = 1e30f;
            for (int k = 0; k < count; ++k)
                if (k != closest) others = std::min(others, bound[k] >= near ? bound[k] : std::max(bound[k], 0.0f));
            if (approach > 0.05f) {
                float jump = std::min(closest_distance / approach, others);
                // Never step into the tube: check, and take the safe sphere step if it would.
                double g = hint[closest];
                if (exact_distance(first + closest, origin + direction * (lambda + jump), g) < -tolerance)
                    jump = closest_distance;
                advance = std::max(advance, jump);
            }
        }
        previous = lambda;
        lambda += std::max(advance, 0.1f * tolerance);
    }
    result.resolved = false;
    return result;
}

ExplicitHit ExplicitPlies::intersect_plies(Vec3 origin, Vec3 direction, float tmin, float tmax) const {
    return trace(1, static_cast<int>(strands_.size()) - 1, origin, direction, tmin, tmax);
}

ExplicitHit ExplicitPlies::intersect_ply(int ply, Vec3 origin, Vec3 direction, float tmin, float tmax) const {
    return trace(1 + ply, 1 + ply, origin, direction, tmin, tmax);
}

ExplicitHit ExplicitPlies::intersect_tube(Vec3 origin, Vec3 direction, float tmin, float tmax) const {
    return trace(0, 0, origin, direction, tmin, tmax);
}

float ExplicitPlies::tube_exit(Vec3 origin, Vec3 direction, float inside, float tmax, uint32_t segment,
                               float t) const {
    // March inside: r - |x - C| is a safe step (the ball around x stays inside the tube).
    const float tolerance = 1e-5f * unit_;
    double g = segment + double(t);
    float lambda = inside, previous = inside;
    for (int step = 0; step < kMaxSteps && lambda < tmax; ++step) {
        const float dist = exact_distance(0, origin + direction * lambda, g);
        float r;
        const Vec3 n = normalize(origin + direction * lambda - strand_point(0, g, &r));
        const float leaving = dot(direction, n);
        if (dist > -tolerance && (leaving > 0 || dist > tolerance)) {
            if (dist <= tolerance) return lambda;
            // Stepped out (only through the Newton jump below): bisect back.
            float lo = previous, hi = lambda;
            for (int it = 0; it < 40; ++it) {
                const float mid = 0.5f * (lo + hi);
                double gm = g;
                if (exact_distance(0, origin + direction * mid, gm) < 0) lo = mid;
                else hi = mid;
            }
            return hi;
        }
        float advance = std::max(-dist, 1e-3f * unit_);
        if (leaving > 0.05f) advance = std::min(std::max(advance, -dist / leaving), -dist + 0.05f * unit_);
        previous = lambda;
        lambda += std::max(advance, 0.1f * tolerance);
    }
    return std::min(lambda, tmax);
}

size_t ExplicitPlies::memory_bytes() const {
    size_t bytes = sizeof(*this);
    for (const Strand& s : strands_) bytes += s.samples.capacity() * sizeof(Sample) + s.chunks.capacity() * sizeof(Chunk);
    return bytes;
}

}  // namespace purl
