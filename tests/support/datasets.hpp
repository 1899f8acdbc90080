#pragma once
// The public datasets beside the project (../shared/datasets, or $EST_SHARED_DIR/datasets) for the tests that read
// real data. When they are absent the case says so and exits 77, which ctest reports as SKIP (est_add_test sets
// SKIP_RETURN_CODE 77; ctest runs each case in a process of its own). A user's clone has no ../shared: its tests
// skip, they do not pass.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace test_support {

inline std::string datasets_dir() {
  if (const char* env = std::getenv("EST_SHARED_DIR")) {
    const std::string d = std::string(env) + "/datasets";
    if (std::filesystem::is_directory(d)) return d;
  }
  if (std::filesystem::is_directory("../shared/datasets")) return "../shared/datasets";
  return {};
}

// The dataset's folder (datasets_dir() + "/" + sub), or the case skips.
inline std::string dataset_or_skip(const std::string& sub) {
  const std::string root = datasets_dir();
  const std::string path = root.empty() ? std::string() : root + "/" + sub;
  if (root.empty() || !std::filesystem::exists(path)) {
    std::fprintf(stderr, "SKIP: dataset %s not found ($EST_SHARED_DIR/datasets or ../shared/datasets)\n", sub.c_str());
    std::fflush(stderr);
    std::_Exit(77);
  }
  return path;
}

}  // namespace test_support
