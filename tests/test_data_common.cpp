// sim_host/data's shared parts: the import report (every malformed line counted by reason, or refused with its
// place), the line reader (plain and gzipped, CRLF), strict number fields, and trajectory errors against a reference.
#include <catch2/catch.hpp>
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "data/eval_report.hpp"
#include "data/import_report.hpp"
#include "data/line_reader.hpp"

using namespace sim::data;

namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("est_data_common_" + name)).string();
}

}  // namespace

TEST_CASE("the import report counts skipped lines by reason and refuses with the file and line", "[data]") {
  ImportReport skip(OnError::skip, nullptr);
  skip.bad_line("a.dat", 3, "4 fields expected");
  skip.bad_line("a.dat", 9, "4 fields expected");
  skip.bad_line("b.dat", 1, "time not a number");
  skip.count("odometry", 10);
  CHECK(skip.skipped_total() == 3);
  CHECK(skip.skipped().at("4 fields expected") == 2);
  CHECK(skip.skipped().at("time not a number") == 1);
  CHECK(skip.imported().at("odometry") == 10);

  ImportReport refuse(OnError::refuse, nullptr);
  try {
    refuse.bad_line("a.dat", 17, "range not a number");
    FAIL("refuse mode must throw");
  } catch (const ImportError& e) {
    CHECK(std::string(e.what()).find("a.dat:17: range not a number") != std::string::npos);
  }
  CHECK(refuse.skipped_total() == 0);
}

TEST_CASE("the line reader reads plain and gzipped files alike, numbering lines and dropping CR", "[data]") {
  const std::string text = "# header\r\n1 2.5\r\n\r\nlast-without-newline";
  const std::string plain = temp_path("plain.txt");
  const std::string gz = temp_path("packed.txt.gz");
  std::ofstream(plain, std::ios::binary) << text;
  gzFile g = gzopen(gz.c_str(), "wb");
  REQUIRE(g != nullptr);
  gzwrite(g, text.data(), static_cast<unsigned>(text.size()));
  gzclose(g);
  for (const std::string& path : {plain, gz}) {
    LineReader r(path);
    std::string line;
    REQUIRE(r.next(line));
    CHECK(line == "# header");
    CHECK(blank_or_comment(line));
    REQUIRE(r.next(line));
    CHECK(line == "1 2.5");
    REQUIRE(r.next(line));
    CHECK(line.empty());
    REQUIRE(r.next(line));
    CHECK(line == "last-without-newline");
    CHECK(r.line_number() == 4);
    CHECK_FALSE(r.next(line));
  }
  CHECK_THROWS(LineReader(temp_path("does-not-exist")));
  std::filesystem::remove(plain);
  std::filesystem::remove(gz);
}

TEST_CASE("number fields are numbers in full and finite, or refused", "[data]") {
  double d = 0.0;
  std::int64_t i = 0;
  CHECK(parse_double("5.0371e-07", d));
  CHECK(d == 5.0371e-07);
  CHECK_FALSE(parse_double("1.5x", d));
  CHECK_FALSE(parse_double("nan", d));
  CHECK_FALSE(parse_double("inf", d));
  CHECK_FALSE(parse_double("", d));
  CHECK(parse_int("-42", i));
  CHECK(i == -42);
  CHECK_FALSE(parse_int("4.2", i));
  CHECK_FALSE(parse_int("12a", i));
  const auto f = split_fields("  1\t 2.5  abc\r");
  REQUIRE(f.size() == 3);
  CHECK(f[2] == "abc");
}

TEST_CASE("trajectory errors interpolate the reference and wrap headings", "[data]") {
  Trajectory ref{{0, 0.0, 0.0, 3.1}, {1000000000, 1.0, 0.0, -3.1}};
  Trajectory est{{500000000, 0.5, 0.3, M_PI}, {2000000000, 9.0, 9.0, 0.0}};  // the second has no reference
  const TrajectoryError e = trajectory_error(est, ref, 2000000000);
  REQUIRE(e.n == 1);
  CHECK(e.rmse_xy_m == Approx(0.3).margin(1e-12));
  CHECK(e.rmse_theta_rad == Approx(0.0).margin(1e-9));  // 3.1 -> -3.1 interpolates through pi, not through 0
  CHECK(trajectory_error(est, ref, 100).n == 0);         // a gap longer than allowed is no reference
}

TEST_CASE("a NUL byte inside a line is part of the line, so the row is refused rather than read as blank",
          "[data]") {
  // The datasets' fuzzer found a row with a NUL byte passed over in silence: the reader cut the line at the NUL and
  // the rest looked blank.
  const std::string path = temp_path("nul.dat");
  const std::string text = std::string("1 2\n") + std::string("\0 3\n", 4) + "4 5\n";
  std::ofstream(path, std::ios::binary) << text;
  ImportReport skip(OnError::skip, nullptr);
  const NumericRows rows = read_numeric_rows(path, 2, skip);
  REQUIRE(rows.values.size() == 2u);
  CHECK(rows.lines[1] == 3u);
  CHECK(skip.skipped_total() == 1);
  CHECK(skip.skipped().at("a field is not a finite number") == 1);
}
