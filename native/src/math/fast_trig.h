// cos and sin without libm: the local ply search evaluates dozens of phases per query, and
// libm's sincosf was a quarter of its time. The angle less q quarter turns (q: a rounded to
// whole quarter turns, the reduction by pi/2 in two parts) goes through Taylor polynomials on
// [-pi/4, pi/4], and the result is turned back by q. Good to ~5e-7 within a few turns; beyond,
// the float product of q and pi/2's leading part rounds, by ~5e-8 of the angle (3e-5 at
// 1,000 rad, 5e-4 at 10,000; tests/native/math/test_ray_cylinder.cpp), so it is no use far
// beyond that (at 3e7 rad c^2 + s^2 is 0.98). The quadrant turn is written with
// selects, not a switch, so a loop over many angles vectorises.
#pragma once
#include <cmath>

namespace purl {

// a rounded to whole quarter turns, without a library call: adding and removing 1.5 * 2^23
// rounds to the nearest whole number (ties to even, as nearbyint in the default rounding mode)
// for |a| / (pi/2) < 2^22 (fits_quarter_turns).
inline float quarter_turns(float a) { return (a * 0.636619772f + 12582912.0f) - 12582912.0f; }
inline bool fits_quarter_turns(float a) { return std::fabs(a * 0.636619772f) < 4194304.0f; }

// cos and sin of a, given q = a in whole quarter turns (quarter_turns(a), or nearbyint beyond).
inline void quadrant_sincos(float a, float q, float& c, float& s) {
    const float r = (a - q * 1.57079625f) - q * 7.54978995e-8f;
    const float r2 = r * r;
    const float sr = r * (1 + r2 * (-1.0f / 6 + r2 * (1.0f / 120 + r2 * (-1.0f / 5040))));
    const float cr = 1 + r2 * (-0.5f + r2 * (1.0f / 24 + r2 * (-1.0f / 720 + r2 * (1.0f / 40320))));
    const int quadrant = static_cast<int>(q);
    const float cs = (quadrant & 1) ? sr : cr, sn = (quadrant & 1) ? cr : sr;
    c = ((quadrant + 1) & 2) ? -cs : cs;
    s = (quadrant & 2) ? -sn : sn;
}

inline void fast_sincos(float a, float& c, float& s) {
    quadrant_sincos(a, fits_quarter_turns(a) ? quarter_turns(a) : std::nearbyint(a * 0.636619772f), c, s);
}

}  // namespace purl
