// Counter-based random numbers: every value is a pure function of
// (seed, pixel, sample, dimension), so images do not depend on thread count.
#pragma once
#include <cstdint>

namespace purl {

inline uint64_t mix64(uint64_t x) {  // SplitMix64 finaliser
    x ^= x >> 30; x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27; x *= 0x94d049bb133111ebULL;
    x ^= x >> 31;
    return x;
}

// PCG32 stream; seeded from a hash of the sample's coordinates.
class Rng {
public:
    Rng() = default;
    explicit Rng(uint64_t seed, uint64_t stream = 0) { reseed(seed, stream); }
    void reseed(uint64_t seed, uint64_t stream = 0) {
        state_ = 0;
        inc_ = (mix64(stream) << 1u) | 1u;
        next_u32();
        state_ += mix64(seed);
        next_u32();
    }
    uint32_t next_u32() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
    }
    // Uniform in [0, 1), never exactly 1.
    float next_float() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }

private:
    uint64_t state_ = 0x853c49e6748fea9bULL, inc_ = 0xda3e39cb94b95bdbULL;
};

// The generator for one camera sample of one pixel.
inline Rng pixel_sample_rng(uint64_t seed, uint32_t px, uint32_t py, uint32_t sample) {
    const uint64_t pixel = (static_cast<uint64_t>(py) << 32) | px;
    return Rng(mix64(seed ^ mix64(pixel)), sample);
}

}  // namespace purl
