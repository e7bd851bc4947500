// Numbers in messages as a person would write them: the shortest text that reads back as the
// same float (0, 0.5, 100000, 1e-09, 3.4028235e+38), not std::to_string's six fixed decimals
// ("0.000000" for both 0 and 1e-9).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace purl {

inline std::string number_text(float value) {
    char text[48];
    int digits = 1;
    for (; digits < 9; ++digits) {
        std::snprintf(text, sizeof(text), "%.*g", digits, double(value));
        if (std::strtof(text, nullptr) == value) break;
    }
    // Whole digits in full below 1e15 (100000, not 1e+05).
    const double magnitude = std::fabs(double(value));
    if (magnitude >= 1 && magnitude < 1e15) digits = std::max(digits, int(std::floor(std::log10(magnitude))) + 1);
    std::snprintf(text, sizeof(text), "%.*g", digits, double(value));
    return text;
}

}  // namespace purl
