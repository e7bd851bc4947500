// libFuzzer target: yarn preset files, read as a scene reads them ("preset_file"),
// checked by fuzz_checks.h.
#include <cstdio>

#include "fuzz_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string broken = purl::fuzz::check_preset(data, size);
    if (!broken.empty()) {
        std::fprintf(stderr, "%s\n", broken.c_str());
        std::abort();
    }
    return 0;
}
