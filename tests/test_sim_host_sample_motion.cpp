// sim_host sample-motion, run as a user runs it: the bicycle exercise's files, their statistics against an
// independent double-precision sampler, the PNGs, the terminal's word on case 5, and bad arguments.
#include <unistd.h>

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "statistics.hpp"

#ifndef SIM_HOST_EXE
#error "SIM_HOST_EXE must name the sim_host executable"
#endif

namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

struct Run {
  int status;
  std::string output;  // stdout and stderr
};

Run run(const std::string& args) {
  const std::string cmd = std::string("'") + SIM_HOST_EXE + "' " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  std::string out;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p) != nullptr) out += buf;
  const int rc = pclose(p);
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, out};
}

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("sim_host_sample_motion_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// Reads a pose CSV; requires the header and three finite numbers per row.
std::vector<std::array<double, 3>> read_csv(const fs::path& file) {
  std::ifstream f(file);
  REQUIRE(f.good());
  std::string line;
  std::getline(f, line);
  CHECK(line == "x_m,y_m,theta_rad");
  std::vector<std::array<double, 3>> rows;
  bool all_finite = true;
  while (std::getline(f, line)) {
    std::array<double, 3> r{};
    char c1 = 0, c2 = 0;
    std::istringstream s(line);
    s >> r[0] >> c1 >> r[1] >> c2 >> r[2];
    const bool ok = !s.fail() && c1 == ',' && c2 == ',' && std::isfinite(r[0]) && std::isfinite(r[1]) &&
                    std::isfinite(r[2]);
    all_finite = all_finite && ok;
    rows.push_back(r);
  }
  CHECK(all_finite);
  return rows;
}

// A PNG: the signature, an IHDR of positive size first, IEND last.
bool valid_png(const fs::path& file, std::uint32_t& width, std::uint32_t& height) {
  std::ifstream f(file, std::ios::binary);
  std::vector<unsigned char> b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const unsigned char sig[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  if (b.size() < 8 + 25 + 12) return false;
  for (int i = 0; i < 8; ++i)
    if (b[static_cast<std::size_t>(i)] != sig[i]) return false;
  const auto be32 = [&](std::size_t at) {
    return static_cast<std::uint32_t>(b[at]) << 24 | static_cast<std::uint32_t>(b[at + 1]) << 16 |
           static_cast<std::uint32_t>(b[at + 2]) << 8 | static_cast<std::uint32_t>(b[at + 3]);
  };
  if (std::string(b.begin() + 12, b.begin() + 16) != "IHDR") return false;
  width = be32(16);
  height = be32(20);
  return width > 0 && height > 0 && std::string(b.end() - 8, b.end() - 4) == "IEND";
}

// The exercise's bicycle in double, independent of the firmware: steering and speed noise, clamp-free case
// (|a| far from the stop), the front wheel rotated about the ICR.
std::array<double, 2> reference_mean_xy(double a_deg, double v_cm_s, int n) {
  std::mt19937_64 gen(12345u);
  std::normal_distribution<double> unit(0.0, 1.0);
  const double l = 1.0, v = v_cm_s / 100.0, sigma_a = 5.0 * kDeg, sigma_v = std::sqrt(0.5 * std::fabs(v));
  double sx = 0.0, sy = 0.0;
  for (int i = 0; i < n; ++i) {
    const double a = a_deg * kDeg + sigma_a * unit(gen);
    const double s = v + sigma_v * unit(gen);
    const double cy = l / std::tan(a);  // ICR (-l, l / tan a); the front wheel at the origin
    const double turn = s * std::sin(a) / l;
    const double px = l, py = -cy;
    sx += -l + std::cos(turn) * px - std::sin(turn) * py;
    sy += cy + std::sin(turn) * px + std::cos(turn) * py;
  }
  return {sx / n, sy / n};
}

double mean_of(const std::vector<std::array<double, 3>>& rows, std::size_t c) {
  double s = 0.0;
  for (const auto& r : rows) s += r[c];
  return s / static_cast<double>(rows.size());
}

double sd_of(const std::vector<std::array<double, 3>>& rows, std::size_t c) {
  std::vector<double> v;
  for (const auto& r : rows) v.push_back(r[c]);
  return std::sqrt(est::test::moments(v).variance);
}

}  // namespace

TEST_CASE("sim_host sample-motion bicycle-exercise reproduces the textbook exercise", "[sim_host]") {
  TempDir dir;
  const Run r = run("sample-motion bicycle-exercise --out '" + dir.path.string() + "'");
  INFO(r.output);
  REQUIRE(r.status == 0);
  // The terminal says what became of case 5's 85 deg: the documented policy clamps it to the 80 deg stop.
  CHECK(r.output.find("case5: steering 85 deg is beyond the 80 deg stop: clamped to 80 deg") != std::string::npos);

  std::vector<std::vector<std::array<double, 3>>> cases;
  for (int k = 1; k <= 5; ++k) {
    const fs::path csv = dir.path / ("case" + std::to_string(k) + ".csv");
    const fs::path png = dir.path / ("case" + std::to_string(k) + ".png");
    INFO("case " << k);
    REQUIRE(fs::exists(csv));
    cases.push_back(read_csv(csv));
    CHECK(cases.back().size() == 5000u);
    std::uint32_t w = 0, h = 0;
    CHECK(valid_png(png, w, h));
    CHECK(w >= 400u);
    CHECK(h >= 300u);
  }

  // Case 1 (25 deg, 20 cm/s): the noise-free pose is (17.7, 9.2) cm. The cloud's mean is near it, but not on it:
  // the speed's sd (31.6 cm/s) exceeds the speed, and the arc's curvature pulls the mean ~2 cm into the turn. So:
  // within 3.5 cm of the noise-free pose, and within 4 standard errors of an independent double sampler's mean.
  const auto& c1 = cases[0];
  const double mx = mean_of(c1, 0), my = mean_of(c1, 1);
  const double h = 0.5 * 0.2 * std::sin(25.0 * kDeg);
  const double fx = 0.2 * std::sin(h) / h * std::cos(25.0 * kDeg + h), fy = 0.2 * std::sin(h) / h * std::sin(25.0 * kDeg + h);
  INFO("case 1 mean (" << mx * 100 << ", " << my * 100 << ") cm, noise-free (" << fx * 100 << ", " << fy * 100 << ") cm");
  CHECK(std::hypot(mx - fx, my - fy) < 0.035);
  const auto ref = reference_mean_xy(25.0, 20.0, 400000);
  const double se_x = sd_of(c1, 0) / std::sqrt(5000.0), se_y = sd_of(c1, 1) / std::sqrt(5000.0);
  INFO("reference mean (" << ref[0] * 100 << ", " << ref[1] * 100 << ") cm, se (" << se_x * 100 << ", " << se_y * 100
                          << ") cm");
  CHECK(std::fabs(mx - ref[0]) < 4.0 * se_x);
  CHECK(std::fabs(my - ref[1]) < 4.0 * se_y);

  // Case 2 is case 1 mirrored in y (steering -25 deg): means of x equal, of y and theta opposite, within 4 standard
  // errors of the difference of two independent means; the spreads equal within 10 %.
  const auto& c2 = cases[1];
  CHECK(std::fabs(mean_of(c2, 0) - mx) < 4.0 * std::sqrt(2.0) * se_x);
  CHECK(std::fabs(mean_of(c2, 1) + my) < 4.0 * std::sqrt(2.0) * se_y);
  CHECK(std::fabs(mean_of(c2, 2) + mean_of(c1, 2)) < 4.0 * std::sqrt(2.0) * sd_of(c1, 2) / std::sqrt(5000.0));
  CHECK(sd_of(c2, 1) == Approx(sd_of(c1, 1)).epsilon(0.1));

  // Case 5 at the stop: every sample's implied steering (from the ICR through its front wheel) is within the stop.
  double worst = 0.0;
  for (const auto& q : cases[4]) {
    const double num = q[1], den = 0.5 * (q[0] * q[0] + q[1] * q[1]) + q[0];
    worst = std::max(worst, std::fabs(std::atan(num / den)));
  }
  INFO("largest implied steering in case 5: " << worst / kDeg << " deg");
  CHECK(worst <= 80.0 * kDeg + 1e-4);
}

TEST_CASE("sim_host sample-motion is repeatable by seed", "[sim_host]") {
  TempDir dir;
  const std::string base = "sample-motion bicycle --v 0.5 --steer-deg 10 --n 200 --out '" + dir.path.string() + "'";
  REQUIRE(run(base + " --name a").status == 0);
  REQUIRE(run(base + " --name b").status == 0);
  REQUIRE(run(base + " --name c --seed 7").status == 0);
  const auto slurp = [&](const char* n) {
    std::ifstream f(dir.path / (std::string(n) + ".csv"));
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  };
  CHECK(slurp("a") == slurp("b"));
  CHECK(slurp("a") != slurp("c"));
}

TEST_CASE("sim_host sample-motion runs every model from the command line", "[sim_host]") {
  TempDir dir;
  const std::string out = " --n 300 --out '" + dir.path.string() + "'";
  CHECK(run("sample-motion velocity --v 1 --w 0.5 --dt 1 --alpha 0.01,0,0.01,0,0.001,0" + out).status == 0);
  CHECK(run("sample-motion odometry --odom-prev 0,0,0 --odom 1,0.2,0.3" + out).status == 0);
  CHECK(run("sample-motion diff-drive --left-ticks 3000 --right-ticks 3300" + out).status == 0);
  CHECK(run("sample-motion diff-drive --left-rad-s 10 --right-rad-s 12 --dt 0.5 --name speeds" + out).status == 0);
  CHECK(run("sample-motion omni --v1 1 --v2 0.5 --w 0.3" + out).status == 0);
  for (const char* n : {"velocity", "odometry", "diff_drive", "speeds", "omni"}) {
    INFO(n);
    CHECK(read_csv(dir.path / (std::string(n) + ".csv")).size() == 300u);
    std::uint32_t w = 0, h = 0;
    CHECK(valid_png(dir.path / (std::string(n) + ".png"), w, h));
  }
}

TEST_CASE("sim_host sample-motion rejects bad arguments with a message and a non-zero exit", "[sim_host]") {
  TempDir dir;
  const std::string out = " --out '" + dir.path.string() + "'";
  const Run steer = run("sample-motion bicycle --steer-deg 100" + out);
  CHECK(steer.status != 0);
  CHECK(steer.output.find("rejected_range") != std::string::npos);
  const Run dt = run("sample-motion velocity --dt -1" + out);
  CHECK(dt.status != 0);
  CHECK(dt.output.find("rejected_range") != std::string::npos);
  const Run nan = run("sample-motion omni --v1 nan" + out);
  CHECK(nan.status != 0);
  CHECK(nan.output.find("rejected_nonfinite") != std::string::npos);
  const Run n = run("sample-motion bicycle-exercise --n -5" + out);
  CHECK(n.status != 0);
  CHECK(n.output.find("--n") != std::string::npos);
  const Run no_out = run("sample-motion bicycle");
  CHECK(no_out.status != 0);
  CHECK(no_out.output.find("--out") != std::string::npos);
  const Run alpha = run("sample-motion omni --alpha 1,2" + out);
  CHECK(alpha.status != 0);
  const Run model = run("sample-motion unicycle" + out);
  CHECK(model.status != 0);
  const Run both = run("sample-motion diff-drive --left-ticks 1 --left-rad-s 2 --right-rad-s 2" + out);
  CHECK(both.status != 0);
}
