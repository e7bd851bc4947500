// libFuzzer target: the JSON scene reader (parse_scene_text), checked by fuzz_checks.h.
// Scenes may name files in tests/fuzz/data (small.bcc, small.obj).
#include <cstdio>

#include "fuzz_checks.h"

#ifndef PURL_FUZZ_DATA_DIR
#error "PURL_FUZZ_DATA_DIR must name tests/fuzz/data"
#endif

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::string broken = purl::fuzz::check_scene_json(text, PURL_FUZZ_DATA_DIR);
    if (!broken.empty()) {
        std::fprintf(stderr, "%s\n", broken.c_str());
        std::abort();
    }
    return 0;
}
