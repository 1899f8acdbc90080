// sim_host import / eval carmen (sim_host/data/carmen.hpp) on the Radish / Freiburg corrected logs
// (../shared/datasets/carmen-radish-logs; skipped when absent): what the import counts and corrects, malformed lines
// skipped or refused with their place, the map built from the corrected poses, and MCL's errors against the
// corrected poses within bounds, so that a regression on real data fails here.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <unistd.h>
#include <zlib.h>

#include "data/carmen.hpp"
#include "datasets.hpp"

using namespace sim::data;
namespace fs = std::filesystem;

namespace {

std::string temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("est_data_carmen_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

std::string log_of(const std::string& site) {
  return test_support::dataset_or_skip("carmen-radish-logs") + "/corrected-logs-acschaefer-ple/" + site +
         "-corrected.log.gz";
}

// The first `lines` lines of a gzipped log, uncompressed, with line `bad` (1-based) replaced by `replacement`.
std::string plain_copy(const std::string& gz, const std::string& out, int lines, int bad,
                       const std::string& replacement) {
  gzFile in = gzopen(gz.c_str(), "rb");
  REQUIRE(in != nullptr);
  std::ofstream o(out);
  char buf[65536];
  for (int n = 1; n <= lines && gzgets(in, buf, sizeof buf) != nullptr; ++n) o << (n == bad ? replacement + "\n" : buf);
  gzclose(in);
  return out;
}

std::uint64_t imported(const ImportReport& r, const std::string& what) {
  const auto it = r.imported().find(what);
  return it == r.imported().end() ? 0 : it->second;
}

}  // namespace

TEST_CASE("CARMEN intel imports every scan and ODOM line, the corrected poses as the reference", "[carmen]") {
  const std::string out = temp_dir("import");
  ImportReport report(OnError::refuse, nullptr);
  const CarmenImport r = import_carmen(log_of("intel"), out + "/intel.lcmlog", {}, report);
  // SOURCE.md: 910 FLASER scans of 180 beams, 14 541 ODOM lines, one stamp-0 (or garbage-stamped) reset per scan.
  CHECK(r.site == "intel");
  CHECK(r.scans == 910);
  CHECK(r.beams == 180);
  CHECK(imported(report, "scans (FLASER)") == 910);
  CHECK(imported(report, "ODOM lines") == 14541);
  CHECK(imported(report, "ODOM stamp-0 lines (corrected pose after a scan: not odometry)") == 910);
  CHECK(imported(report, "NEFF lines (GMapping diagnostics, not used)") == 910);
  CHECK(report.skipped_total() == 0);
  CHECK(r.geometry.range_max_m == Approx(81.83f));
  CHECK(r.geometry.angle_increment_rad == Approx(M_PI / 180.0));
  CHECK(r.t_first_s == Approx(32.9068));
  CHECK(r.t_last_s == Approx(2683.8).margin(0.1));
  // Lines before the first scan have no reference; the rest, less the resets, are the odometry (with the bridged
  // pauses on top).
  const std::uint64_t before = imported(report, "ODOM lines before the first scan (no reference: not imported)");
  CHECK(before > 100);
  const std::uint64_t after = imported(report, "odometry poses after the last scan (no reference: not written)");
  CHECK(r.odometry + after == 14541 - 910 - before + imported(report, "odometry poses interpolated across gaps"));

  const CarmenLog log = read_carmen_log(out + "/intel.lcmlog");
  REQUIRE(log.scans.size() == 910);
  REQUIRE(log.reference.size() == 910);
  CHECK(log.odometry.size() == r.odometry);
  // The first scan's corrected pose, as printed in the file.
  CHECK(log.reference.front().x == Approx(0.600266).margin(1e-5));
  CHECK(log.reference.front().theta == Approx(-0.354665).margin(1e-5));
  for (std::size_t k = 1; k < log.odometry.size(); ++k) {
    INFO("odometry pose " << k << " at " << log.odometry[k].t_ns);
    REQUIRE(log.odometry[k].t_ns > log.odometry[k - 1].t_ns);
    REQUIRE(log.odometry[k].t_ns - log.odometry[k - 1].t_ns <= 260000000);  // bridged to the 0.25 s gap limit
  }
  // The raw odometry drifts from the corrected poses: metres by the end of the 45 min run.
  const TimedPose& o = log.odometry.back();
  const TimedPose& c = log.reference.back();
  CHECK(std::hypot(o.x - c.x, o.y - c.y) > 1.0);
}

TEST_CASE("CARMEN malformed lines are reported with their line number, then skipped and counted or refused",
          "[carmen]") {
  const std::string out = temp_dir("malformed");
  // intel line 175 is the first FLASER; line 172 an ODOM line.
  const std::string bad_scan = plain_copy(log_of("intel"), out + "/bad-scan.log", 2000, 175, "FLASER 180 1.09 1.08");
  const std::string bad_odom = plain_copy(log_of("intel"), out + "/bad-odom.log", 2000, 172,
                                          "ODOM 0.697032 nan -0.23353 0 0 0 32.6483 pippo 32.6483");
  {
    ImportReport report(OnError::skip, nullptr);
    const CarmenImport r = import_carmen(bad_scan, out + "/a.lcmlog", {}, report);
    CHECK(report.skipped_total() == 1);
    CHECK(report.skipped().at("FLASER: the field count does not match its beam count") == 1);
    ImportReport clean(OnError::skip, nullptr);
    const CarmenImport c = import_carmen(plain_copy(log_of("intel"), out + "/clean.log", 2000, 0, ""),
                                         out + "/c.lcmlog", {}, clean);
    CHECK(r.scans + 1 == c.scans);
    CHECK(clean.skipped_total() == 0);
  }
  {
    ImportReport report(OnError::skip, nullptr);
    import_carmen(bad_odom, out + "/b.lcmlog", {}, report);
    CHECK(report.skipped().at("ODOM: a field is not a finite number") == 1);
  }
  ImportReport refuse(OnError::refuse, nullptr);
  try {
    import_carmen(bad_scan, out + "/r.lcmlog", {}, refuse);
    FAIL("refuse did not stop the import");
  } catch (const ImportError& e) {
    CHECK(std::string(e.what()).find("bad-scan.log:175:") != std::string::npos);
  }
}

TEST_CASE("CARMEN ROBOTLASER1 lines import with their own geometry and the laser's mount", "[carmen]") {
  const std::string out = temp_dir("robotlaser");
  const std::string path = out + "/rl.log";
  {
    std::ofstream f(path);
    f << "ODOM 0 0 0 0 0 0 1.0 h 1.0\n";
    // type start fov res max accuracy mode n r1..r5 m laser(x y t) robot(x y t) tv rv fs ss ta ts host lts
    f << "ROBOTLASER1 0 -1.0 2.0 0.5 8.0 0.01 0 5 1 2 3 8.0 4 0 0.1 0 0 0 0 0 0 0 0 0 0 1.0 h 1.0\n";
    f << "ODOM 0 0 0 0 0 0 0 h 0\n";
    f << "ODOM 0.1 0 0 0 0 0 1.1 h 1.1\n";
    f << "ROBOTLASER1 0 -1.0 2.0 0.5 8.0 0.01 0 5 1 2 3 8.0 4 0 0.2 0 0 0.1 0 0 0 0 0 0 0 1.1 h 1.1\n";
    f << "ROBOTLASER1 0 -1.0 2.0 0.5 8.0 0.01 0 5 1 2 3\n";
  }
  ImportReport report(OnError::skip, nullptr);
  const CarmenImport r = import_carmen(path, out + "/rl.lcmlog", {}, report);
  CHECK(r.scans == 2);
  CHECK(r.beams == 5);
  CHECK(r.geometry.angle_min_rad == Approx(-1.0f));
  CHECK(r.geometry.angle_increment_rad == Approx(0.5f));
  CHECK(r.geometry.range_max_m == Approx(8.0f));
  CHECK(r.mount.x == Approx(0.1f));
  CHECK(report.skipped().at("ROBOTLASER1: the field count does not match its beam and remission counts") == 1);
  const CarmenLog log = read_carmen_log(out + "/rl.lcmlog");
  REQUIRE(log.reference.size() == 2);
  CHECK(log.reference[1].x == Approx(0.1));
}

namespace {

// One evaluation of the first 120 scans of intel (about 7 minutes of log time, 90 m of travel), shared by the
// cases below (ctest runs each in its own process, in a folder of its own); each case asserts one part of it.
const CarmenEval& intel_slice() {
  static const CarmenEval ev = [] {
    CarmenEvalOptions o;
    o.out_dir = temp_dir("eval-" + std::to_string(getpid()));
    o.import.max_scans = 120;
    o.global_starts = 2;
    o.global_seconds = 150.0;
    o.quiet = true;
    return eval_carmen(log_of("intel"), o);
  }();
  return ev;
}

const CarmenMethodResult& method(const CarmenEval& ev, const std::string& name) {
  for (const CarmenMethodResult& m : ev.methods)
    if (m.name == name) return m;
  FAIL("no method " << name);
  return ev.methods.front();
}

}  // namespace

TEST_CASE("CARMEN intel: the grid built from the corrected poses has walls where the scans end", "[carmen]") {
  const CarmenEval& ev = intel_slice();
  CHECK(ev.import.scans == 120);
  CHECK(ev.map.resolution_m == Approx(0.05));
  // The lab is about 30 m x 30 m; the slice sees most of it.
  CHECK(ev.map.width * ev.map.resolution_m > 20.0);
  CHECK(ev.map.width * ev.map.resolution_m < 45.0);
  CHECK(ev.map.height * ev.map.resolution_m < 45.0);
  CHECK(ev.map.occupied > 2000);
  CHECK(ev.map.free > 20 * ev.map.occupied);
  // Measured 0.94 with the FLASER bearings -pi/2 + i pi/180; a wrong bearing convention or pose frame smears the
  // walls and drops it well below.
  CHECK(ev.map.endpoints_on_walls > 0.90);
  CHECK(fs::exists(ev.map.yaml));
  CHECK(fs::exists(ev.map.pgm));
}

TEST_CASE("CARMEN intel: the trajectories plot is framed on the map, not stretched by dead reckoning's drift",
          "[carmen]") {
  const CarmenEval& ev = intel_slice();
  std::ifstream f(fs::path(ev.log_path).parent_path() / "trajectories.gp");
  const std::string gp((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::ostringstream x, y;
  x << "set xrange [" << ev.map.origin_x << ":" << ev.map.origin_x + ev.map.width * ev.map.resolution_m << "]";
  y << "set yrange [" << ev.map.origin_y << ":" << ev.map.origin_y + ev.map.height * ev.map.resolution_m << "]";
  CHECK(gp.find(x.str()) != std::string::npos);
  CHECK(gp.find(y.str()) != std::string::npos);
  for (const char* png : {"trajectories.png", "errors.png"}) {
    INFO(png);
    CHECK(fs::file_size(fs::path(ev.log_path).parent_path() / png) > 10000u);
  }
}

TEST_CASE("CARMEN intel: MCL tracking on the raw odometry stays within 0.15 m of the corrected poses", "[carmen]") {
  const CarmenEval& ev = intel_slice();
  const CarmenMethodResult& dr = method(ev, "dead-reckoning");
  const CarmenMethodResult& mcl = method(ev, "mcl-tracking");
  CHECK(mcl.error.n == 120);
  // Measured 0.05 m and 0.01 rad; the raw odometry drifts by metres (13 m RMSE) over the same slice.
  CHECK(mcl.error.rmse_xy_m < 0.15);
  CHECK(mcl.error.rmse_theta_rad < 0.05);
  CHECK(mcl.error.max_xy_m < 0.6);
  CHECK(dr.error.rmse_xy_m > 2.0);
  CHECK(mcl.rejects == 0);
}

TEST_CASE("CARMEN intel: global localization from an unknown start succeeds", "[carmen]") {
  const CarmenEval& ev = intel_slice();
  REQUIRE(ev.global.size() == 2);
  int ok = 0;
  for (const CarmenGlobalRun& g : ev.global) {
    if (!g.localized) continue;
    ++ok;
    CHECK(g.time_to_localize_s < 120.0);
    CHECK(g.after.rmse_xy_m < 0.3);
  }
  CHECK(ok >= 1);
  CHECK(ev.global_success_rate == Approx(ok / 2.0));
}

TEST_CASE("global localization counts as localized only when the estimate holds: a find lost again is no success",
          "[carmen]") {
  // 60 s of scans at 10 Hz; the estimate is either on the reference or 2 m off.
  Trajectory ref, est;
  const auto make = [&](const std::function<bool(int)>& close) {
    ref.clear();
    est.clear();
    for (int k = 0; k < 600; ++k) {
      const std::int64_t t = static_cast<std::int64_t>(k) * 100000000;
      ref.push_back({t, 0.01 * k, 0.0, 0.0});
      est.push_back({t, 0.01 * k + (close(k) ? 0.1 : 2.0), 0.0, 0.0});
    }
  };
  const CarmenEvalOptions o;  // within 0.5 m and 0.3 rad for 10 s, and at 90 % of the scans to the end
  make([](int k) { return k >= 50; });  // found at 5 s, kept
  CarmenGlobalRun g = judge_global_localization(est, ref, o);
  CHECK(g.localized);
  CHECK(g.time_to_localize_s == Approx(5.0));
  CHECK(g.kept_fraction == Approx(1.0));
  CHECK(g.after.rmse_xy_m == Approx(0.1).margin(1e-6));
  make([](int k) { return k >= 50 && k < 80; });  // close for 3 s (30 scans), then lost again
  CHECK_FALSE(judge_global_localization(est, ref, o).localized);
  make([](int k) { return k >= 50 && (k < 200 || k % 3 != 0); });  // held 15 s, then off at a third of the scans
  g = judge_global_localization(est, ref, o);
  CHECK_FALSE(g.localized);
  make([](int k) { return (k >= 50 && k < 80) || k >= 300; });  // a false find, then the real one at 30 s
  g = judge_global_localization(est, ref, o);
  CHECK(g.localized);
  CHECK(g.time_to_localize_s == Approx(30.0));
  make([](int k) { return k >= 595; });  // close only in the last 0.5 s: not held for 10 s
  CHECK_FALSE(judge_global_localization(est, ref, o).localized);
}

TEST_CASE("CARMEN intel: the beam model's EM gives sane parameters and a higher likelihood", "[carmen]") {
  const CarmenBeamModel& b = intel_slice().beam;
  REQUIRE(b.learned);
  CHECK(b.readings > 5000);
  CHECK(b.z_hit + b.z_short + b.z_max + b.z_rand == Approx(1.0f).margin(1e-3));
  CHECK(b.z_hit > 0.6f);
  CHECK(b.z_max > 0.0f);
  CHECK(b.z_max < 0.2f);
  CHECK(b.sigma_hit > 0.01f);
  CHECK(b.sigma_hit < 0.3f);
  CHECK(b.lambda_short > 0.0f);
  CHECK(b.range_max == Approx(81.83f));
  CHECK(b.log_likelihood_final > b.log_likelihood_initial + 0.1);
}

TEST_CASE("CARMEN stamps beyond an int64 of nanoseconds are refused, and a long odometry pause is not interpolated",
          "[carmen]") {
  // Synthetic (no dataset needed): the CARMEN fuzzer found a stamp of 5e27 s making ceil(gap / 0.25 s) overflow an
  // int, and any long pause would have been filled with gap / 0.25 s interpolated poses.
  const std::string out = temp_dir("stamps");
  const std::string path = out + "/s.log";
  {
    std::ofstream f(path);
    f << "FLASER 3 1 2 3 0 0 0 0 0 0 1.0 h 1.0\n";
    f << "ODOM 0 0 0 0 0 0 1.0 h 1.0\n";
    f << "ODOM 0.1 0 0 0 0 0 1.1 h 1.1\n";
    f << "ODOM 0.2 0 0 0 0 0 5e27 h 1.2\n";
    f << "FLASER 3 1 2 3 0 0 0 0 0 0 -4 h 1.3\n";
    f << "ODOM 0.3 0 0 0 0 0 1000.0 h 1000.0\n";
    f << "FLASER 3 1 2 3 0.3 0 0 0.3 0 0 1000.0 h 1000.0\n";
  }
  ImportReport report(OnError::skip, nullptr);
  const CarmenImport r = import_carmen(path, out + "/s.lcmlog", {}, report);
  CHECK(r.scans == 2);
  CHECK(report.skipped().at("ODOM: timestamp outside 0 .. 9e9 s") == 1);
  CHECK(report.skipped().at("FLASER: timestamp outside 0 .. 9e9 s") == 1);
  CHECK(report.imported().at("odometry pauses over 60 s (not interpolated: the HAL drops the motion across)") == 1);
  CHECK(report.imported().at("odometry poses interpolated across gaps") == 0);
}
