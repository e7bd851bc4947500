// The real cloth models in ../shared/data (beside the repository, not in it). A test that
// needs one skips with the reason when it is missing (GTEST_SKIP_WITHOUT_SHARED_DATA), so a
// fresh clone elsewhere reports what it did not run instead of passing silently or failing.
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace purl {

inline std::string shared_data_path(const std::string& name) { return std::string(PURL_SHARED_DATA_DIR) + "/" + name; }
inline bool have_shared_data(const std::string& name) { return std::filesystem::exists(shared_data_path(name)); }

}  // namespace purl

// In a test body (it returns): skips the rest when `name` is not in ../shared/data.
#define GTEST_SKIP_WITHOUT_SHARED_DATA(name)                                                         \
    if (!::purl::have_shared_data(name))                                                             \
    GTEST_SKIP() << "needs " << ::purl::shared_data_path(name)                                       \
                 << ", which is missing (the shared cloth models live beside the repository, not in it)"
