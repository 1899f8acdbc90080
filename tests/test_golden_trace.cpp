// The golden-trace comparer (tests/support/golden_trace.hpp): a trace equal to its golden passes, a perturbed one
// fails naming the workload, row, column, golden and new values, with every column's deviation.
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

#include "golden_trace.hpp"
#include "selftest.hpp"

namespace {

const est::selftest::Section& section_named(const std::string& name) {
  int n = 0;
  const est::selftest::Section* s = est::selftest::sections(n);
  for (int i = 0; i < n; ++i)
    if (name == s[i].name) return s[i];
  FAIL("no section " << name);
  return s[0];
}

std::vector<est::test::TraceRow> trace_of(const est::selftest::Section& s) {
  est::test::TraceRecorder rec;
  est::Trace t(&rec);
  s.trace(t);
  return rec.rows;
}

std::string scratch_file(const char* name) {
  char tmpl[] = "/tmp/est_golden_XXXXXX";
  const char* d = mkdtemp(tmpl);
  REQUIRE(d != nullptr);
  return std::string(d) + "/" + name;
}

}  // namespace

TEST_CASE("a trace's sink sees every output the digest takes, named, and does not change the digest", "[golden]") {
  const auto& s = section_named("loop_ekf");
  est::test::TraceRecorder rec;
  est::Trace traced(&rec);
  s.trace(traced);
  CHECK(traced.value() == s.run());
  CHECK(traced.value() == s.expected);
  // 300 published estimates (one per 10 ms over 3 s) of 14 outputs (stamp, x, y, theta, 9 of P, status), then the
  // 10 end rows.
  CHECK(rec.rows.size() == 300u * 14u + 10u);
  CHECK(rec.rows[1].quantity == "x");
  CHECK(rec.rows[4].quantity == "P[0]");
}

TEST_CASE("a run written as its golden and read back compares equal in every column", "[golden]") {
  const auto rows = trace_of(section_named("motion_b"));
  const std::string path = scratch_file("motion_b.csv");
  est::test::write_golden(path, "motion_b", rows);
  const est::test::GoldenFile g = est::test::read_golden(path);
  REQUIRE(g.error.empty());
  CHECK(g.rows.size() <= est::test::kGoldenRowTarget + 64u);
  CHECK(g.stride > 1u);
  const est::test::Comparison c = est::test::compare_with_golden(g, rows, est::test::Tolerance{});
  INFO(c.report("motion_b"));
  CHECK(c.ok);
  CHECK(!c.columns.empty());
  for (const auto& col : c.columns) CHECK(col.max_abs == 0.0);
}

TEST_CASE("a perturbed trace fails, naming the workload, row, column, golden and new values", "[golden]") {
  auto rows = trace_of(section_named("motion_b"));
  const std::string path = scratch_file("motion_b.csv");
  est::test::write_golden(path, "motion_b", rows);
  const est::test::GoldenFile g = est::test::read_golden(path);
  REQUIRE(g.error.empty());
  // One ULP-sized drift (1e-6 relative) in the omni chain's x at a kept step.
  std::size_t at = rows.size();
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (rows[i].quantity == "omni.x" && rows[i].step == g.stride * 3u && at == rows.size()) at = i;
  REQUIRE(at < rows.size());
  const double golden_value = rows[at].value;
  rows[at].value *= 1.0 + 1e-6;
  const est::test::Comparison c = est::test::compare_with_golden(g, rows, est::test::Tolerance{});
  const std::string report = c.report("motion_b");
  INFO(report);
  CHECK_FALSE(c.ok);
  CHECK(report.find("motion_b") != std::string::npos);
  CHECK(report.find("column omni.x") != std::string::npos);
  CHECK(report.find("step " + std::to_string(g.stride * 3u)) != std::string::npos);
  char golden_text[64];
  std::snprintf(golden_text, sizeof golden_text, "golden %.17g", golden_value);
  CHECK(report.find(golden_text) != std::string::npos);
  // The same drift passes a tolerance stated for it.
  CHECK(est::test::compare_with_golden(g, rows, est::test::Tolerance{0.0, 1e-5}).ok);
  // A missing output does not line up.
  rows.erase(rows.begin() + static_cast<std::ptrdiff_t>(at));
  const est::test::Comparison shifted = est::test::compare_with_golden(g, rows, est::test::Tolerance{});
  CHECK_FALSE(shifted.ok);
  CHECK(shifted.failure.find("no longer line up") != std::string::npos);
}
