// The determinism suite (issue 14): the self-test's traced workloads (motion sampling for every model, MCL with the
// likelihood field and the beam model, MCL's recovery, EKF localization, cooperative EKF-SLAM, the filter loop with
// every motion model; firmware/selftest) hash every output of every step. Here: ten runs in one process give the same
// digests, equal to the stored ones (which the board images check under qemu, selftest.<board>, and the host-debug
// preset at -O0), and each workload's outputs stay within the stated tolerance of its golden trace
// (tests/golden/<workload>.csv). EST_UPDATE_GOLDEN=1 rewrites the goldens instead: commit them with the reason.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <string>

#include "golden_trace.hpp"
#include "selftest.hpp"

namespace {

const std::string kGoldenDir = EST_GOLDEN_DIR;

#ifndef EST_DETERMINISM_RUNS
#define EST_DETERMINISM_RUNS 10
#endif
constexpr int kRuns = EST_DETERMINISM_RUNS;

// Stated tolerance: 1e-9 relative, below one float ULP (6e-8): any drift of a bit shows, with how far it went.
constexpr est::test::Tolerance kTolerance{0.0, 1e-9};

}  // namespace

TEST_CASE("every traced workload gives the same digest ten times in one process, equal to the stored one",
          "[determinism]") {
  int n = 0;
  const est::selftest::Section* s = est::selftest::sections(n);
  int traced = 0;
  for (int i = 0; i < n; ++i) {
    if (s[i].trace == nullptr) continue;
    ++traced;
    for (int run = 0; run < kRuns; ++run) {
      const std::uint64_t d = s[i].run();
      INFO(s[i].name << " run " << run << ": 0x" << std::hex << d << " stored 0x" << s[i].expected);
      CHECK(d == s[i].expected);
    }
  }
  CHECK(traced >= 12);
}

TEST_CASE("every traced workload's outputs are within tolerance of its golden trace", "[determinism][golden]") {
  const bool update = std::getenv("EST_UPDATE_GOLDEN") != nullptr;
  int n = 0;
  const est::selftest::Section* s = est::selftest::sections(n);
  for (int i = 0; i < n; ++i) {
    if (s[i].trace == nullptr) continue;
    est::test::TraceRecorder rec;
    est::Trace t(&rec);
    s[i].trace(t);
    const std::string path = kGoldenDir + "/" + s[i].name + ".csv";
    if (update) {
      est::test::write_golden(path, s[i].name, rec.rows);
      WARN("rewrote " << path);
      continue;
    }
    const est::test::GoldenFile g = est::test::read_golden(path);
    INFO(g.error << " (EST_UPDATE_GOLDEN=1 writes the goldens)");
    REQUIRE(g.error.empty());
    const est::test::Comparison c = est::test::compare_with_golden(g, rec.rows, kTolerance);
    INFO(c.report(s[i].name));
    CHECK(c.ok);
  }
}
