// sim_host import / eval mrclam (sim_host/data/mrclam.hpp, mrclam_eval.hpp) on slices of UTIAS MRCLAM Datasets 1
// and 2 (../shared/datasets/utias-mrclam; skipped when absent): what the import writes and counts, Dataset 1's
// landmark fix, malformed lines skipped or refused with their place, and the evaluation's errors against Vicon
// within bounds, so that a regression of any filter on real data fails here.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "data/mrclam.hpp"
#include "data/mrclam_eval.hpp"
#include "datasets.hpp"

using namespace sim::data;
namespace fs = std::filesystem;

namespace {

std::string temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("est_data_mrclam_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

const MrclamMethodResult& method(const MrclamEval& ev, const std::string& name) {
  const auto it = std::find_if(ev.methods.begin(), ev.methods.end(),
                               [&](const MrclamMethodResult& m) { return m.name == name; });
  REQUIRE(it != ev.methods.end());
  return *it;
}

// Position RMSE against Vicon of the robot's twists dead-reckoned (midpoint heading) from its true pose, restarted
// from the true pose every `restart_s`.
double drift_rmse(const MrclamRobotLog& r, double restart_s) {
  const std::vector<MrclamTwist>& tw = r.twists;
  REQUIRE(!tw.empty());
  const std::int64_t restart_ns = static_cast<std::int64_t>(restart_s * 1e9);
  std::size_t k = 0;
  std::int64_t t = 0, next_restart = std::numeric_limits<std::int64_t>::min();
  double x = 0.0, y = 0.0, th = 0.0, sq = 0.0;
  std::size_t n = 0;
  for (const TimedPose& g : r.truth) {
    if (g.t_ns >= next_restart) {
      x = g.x, y = g.y, th = g.theta, t = g.t_ns;
      next_restart = g.t_ns + restart_ns;
      continue;
    }
    while (t < g.t_ns) {  // the twist of [tw[k], tw[k + 1]) over [t, g.t_ns)
      while (k + 1 < tw.size() && tw[k + 1].t_ns <= t) ++k;
      if (tw[k].t_ns > t) {  // before the first twist: standing
        t = std::min(g.t_ns, tw[k].t_ns);
        continue;
      }
      const std::int64_t end = k + 1 < tw.size() ? std::min(g.t_ns, tw[k + 1].t_ns) : g.t_ns;
      const double dt = static_cast<double>(end - t) * 1e-9;
      x += tw[k].v * dt * std::cos(th + 0.5 * tw[k].w * dt);
      y += tw[k].v * dt * std::sin(th + 0.5 * tw[k].w * dt);
      th += tw[k].w * dt;
      t = end;
    }
    sq += (g.x - x) * (g.x - x) + (g.y - y) * (g.y - y);
    ++n;
  }
  REQUIRE(n > 0u);
  return std::sqrt(sq / static_cast<double>(n));
}

}  // namespace

TEST_CASE("MRCLAM sampled Dataset 1 imports every robot's streams and corrects the swapped landmarks", "[mrclam]") {
  const std::string dir = test_support::dataset_or_skip("utias-mrclam/sampled-50hz/MRCLAM_Dataset1");
  const std::string out = temp_dir("import1");
  ImportReport report(OnError::refuse, nullptr);
  MrclamImportOptions o;
  o.max_seconds = 100.0;
  const MrclamImport r = import_mrclam(dir, out + "/d1.lcmlog", o, report);
  CHECK(r.sampled);
  CHECK(r.dataset == 1);
  CHECK(r.has_ground_truth);
  REQUIRE(r.landmarks.size() == 15);
  // Subject 11 is observed near (0.015, -2.831): after the fix the map agrees, and the note says so.
  const auto l11 = std::find_if(r.landmarks.begin(), r.landmarks.end(), [](const auto& l) { return l.subject == 11; });
  CHECK(l11->x == Approx(0.036).margin(0.05));
  CHECK(l11->y == Approx(-2.844).margin(0.05));
  REQUIRE(report.notes().size() >= 1);
  CHECK(report.notes()[0].find("11 and 17") != std::string::npos);
  // 100 s at 50 Hz: rows 0..5000 of odometry and ground truth for each of the five robots.
  CHECK(report.imported().at("odometry (v, w)") == 5u * 5001u);
  CHECK(report.imported().at("landmark sightings") > 500u);
  CHECK(report.imported().at("robot sightings") > 50u);
  CHECK(report.skipped_total() == 0);
  CHECK(fs::exists(r.landmarks_csv));
  CHECK(fs::exists(r.arena_yaml));

  const auto robots = read_mrclam_log(out + "/d1.lcmlog", {1, 2, 3, 4, 5});
  REQUIRE(robots.size() == 5);
  for (const MrclamRobotLog& rb : robots) {
    CHECK(rb.twists.size() == 5001u);
    CHECK(rb.truth.size() == 5001u);
    CHECK(rb.truth.back().t_ns == 100000000000LL);  // row k at 0.02 k s exactly
    for (const MrclamSighting& s : rb.robots) CHECK((s.id >= 1 && s.id <= 5 && s.id != rb.subject));
    for (const MrclamSighting& s : rb.landmarks) CHECK((s.id >= 0 && s.id < 15));
  }

  ImportReport kept(OnError::skip, nullptr);
  o.fix_landmarks = false;
  const MrclamImport raw = import_mrclam(dir, out + "/d1-kept.lcmlog", o, kept);
  const auto k11 =
      std::find_if(raw.landmarks.begin(), raw.landmarks.end(), [](const auto& l) { return l.subject == 11; });
  CHECK(k11->x == Approx(3.151).margin(0.01));
  CHECK(std::none_of(kept.notes().begin(), kept.notes().end(),
                     [](const std::string& n) { return n.find("11 and 17") != std::string::npos; }));
}

TEST_CASE("MRCLAM raw Dataset 2 imports with its absolute times and says it has no ground truth", "[mrclam]") {
  const std::string dir = test_support::dataset_or_skip("utias-mrclam/raw/MRCLAM_Dataset2");
  const std::string out = temp_dir("import2");
  ImportReport report(OnError::skip, nullptr);
  MrclamImportOptions o;
  o.max_seconds = 60.0;
  const MrclamImport r = import_mrclam(dir, out + "/d2.lcmlog", o, report);
  CHECK_FALSE(r.sampled);
  CHECK(r.dataset == 2);
  CHECK_FALSE(r.has_ground_truth);
  CHECK(r.t0_unix_s == Approx(1248275403.0).margin(10.0));
  CHECK(r.duration_s == Approx(60.0).margin(0.1));
  // Irregular odometry, 46 Hz per robot over the first minute (59 Hz over the whole dataset).
  CHECK(report.imported().at("odometry (v, w)") > 5u * 2400u);
  CHECK(std::any_of(report.notes().begin(), report.notes().end(),
                    [](const std::string& n) { return n.find("no robot ground truth") != std::string::npos; }));
  const auto robots = read_mrclam_log(out + "/d2.lcmlog", {1, 2, 3, 4, 5});
  for (const MrclamRobotLog& rb : robots) {
    CHECK(rb.truth.empty());
    REQUIRE(rb.twists.size() > 1200u);  // robots start at different times
    CHECK(std::is_sorted(rb.twists.begin(), rb.twists.end(), [](auto& a, auto& b) { return a.t_ns < b.t_ns; }));
  }
}

TEST_CASE("a malformed MRCLAM line is skipped and counted, or refuses the import, with its file and line", "[mrclam]") {
  const std::string dir = test_support::dataset_or_skip("utias-mrclam/sampled-50hz/MRCLAM_Dataset1");
  const std::string copy = temp_dir("bad") + "/MRCLAM_Dataset1";
  fs::copy(dir, copy);
  {  // line 3 of robot 2's measurements loses a field, line 5 gets a word for its range
    std::ifstream in(copy + "/Robot2_Measurement.dat");
    std::string text, line;
    for (int n = 1; std::getline(in, line); ++n) {
      if (n == 3) line = "12.48 9 2.717";
      if (n == 5) line = "12.7 25 far -0.244";
      text += line + "\n";
    }
    in.close();
    std::ofstream(copy + "/Robot2_Measurement.dat") << text;
  }
  MrclamImportOptions o;
  o.max_seconds = 30.0;
  ImportReport skip(OnError::skip, nullptr);
  import_mrclam(copy, copy + "/../skip.lcmlog", o, skip);
  CHECK(skip.skipped_total() == 2);
  CHECK(skip.skipped().at("4 fields expected") == 1);
  CHECK(skip.skipped().at("a field is not a finite number") == 1);

  ImportReport refuse(OnError::refuse, nullptr);
  try {
    import_mrclam(copy, copy + "/../refuse.lcmlog", o, refuse);
    FAIL("the import must refuse");
  } catch (const ImportError& e) {
    CHECK(std::string(e.what()).find("Robot2_Measurement.dat:3: 4 fields expected") != std::string::npos);
  }
}

TEST_CASE("MRCLAM rows whose values a log cannot carry are skipped by reason, and the rest imported", "[mrclam]") {
  // Synthetic, raw layout (no dataset needed): the values the importer once converted or stamped unchecked (a
  // barcode of 1e20 to int, a landmark 1e9 m away sizing the arena map, times of 1e30 s, floats beyond their range,
  // a row before the time origin stamped negative: found by fuzz_mrclam).
  const std::string dir = temp_dir("ranges") + "/MRCLAM_Dataset9";
  fs::create_directories(dir);
  std::ofstream(dir + "/Barcodes.dat") << "# Subject #    Barcode #\n1 5\n6 14\n7 1e20\n";
  std::ofstream(dir + "/Landmark_Groundtruth.dat") << "# Subject # x y sx sy\n6 1.0 2.0 0 0\n8 1e9 0 0 0\n";
  std::ofstream(dir + "/Robot1_Odometry.dat") << "# Time [s] v [m/s] w [rad/s]\n"
                                                 "1248272262.0 0.1 0.0\n1e30 0.1 0.0\n1248272262.1 1e39 0.0\n"
                                                 "1248272262.2 0.1 0.01\n";
  std::ofstream(dir + "/Robot1_Measurement.dat") << "# Time [s] Subject # range [m] bearing [rad]\n"
                                                    "1248272262.05 14 2.2 0.1\n1248272262.06 14 1e39 0.1\n"
                                                    "1248272262.07 1e20 2.0 0.1\n1248272262.08 14 2.0 -1e39\n"
                                                    "1248272200.0 14 2.0 0.1\n";  // before t0
  std::ofstream(dir + "/Robot1_Groundtruth.dat") << "# Time [s] x [m] y [m] orientation [rad]\n"
                                                    "1248272262.0 0 0 0\n1248272262.1 1e39 0 0\n";
  MrclamImportOptions o;
  o.robots = {1};
  ImportReport skip(OnError::skip, nullptr);
  const std::string out = temp_dir("ranges_out") + "/r.lcmlog";
  const MrclamImport r = import_mrclam(dir, out, o, skip);
  CHECK(skip.skipped().at("subject and barcode must be whole numbers in 1 .. 1000 and 0 .. 1000") == 1);
  CHECK(skip.skipped().at("landmark beyond 100 m of the origin") == 1);
  CHECK(skip.skipped().at("time outside 0 .. 9e9 s") == 1);
  CHECK(skip.skipped().at("speed beyond 100 m/s or 100 rad/s") == 1);
  CHECK(skip.skipped().at("range not in (0, 1000] m") == 1);
  CHECK(skip.skipped().at("barcode must be a whole number in 0 .. 1000") == 1);
  CHECK(skip.skipped().at("bearing beyond 100 rad") == 1);
  CHECK(skip.skipped().at("pose beyond 100 m of the origin or a heading beyond 100 rad") == 1);
  CHECK(skip.skipped().at("time before the previous row's") == 1);
  CHECK(skip.skipped_total() == 9);
  REQUIRE(r.landmarks.size() == 1u);
  const std::vector<MrclamRobotLog> back = read_mrclam_log(out, {1});
  REQUIRE(back.size() == 1u);
  CHECK(back[0].twists.size() == 2u);
  CHECK(back[0].truth.size() == 1u);
  REQUIRE(back[0].landmarks.size() == 1u);
  CHECK(back[0].landmarks[0].range == Approx(2.2));
  CHECK(static_cast<double>(back[0].twists.back().t_ns) == Approx(2e8).margin(1e3));  // from the earliest time
}

TEST_CASE("MRCLAM Dataset 1, first 300 s: EKF localization within 0.13 m of Vicon, the team better than each alone",
          "[mrclam][eval]") {
  const std::string dir = test_support::dataset_or_skip("utias-mrclam/sampled-50hz/MRCLAM_Dataset1");
  MrclamEvalOptions o;
  o.out_dir = temp_dir("eval1");
  o.max_seconds = 300.0;
  o.methods = {"dead-reckoning", "ekf-known-landmarks", "ekf-unknown-correspondence", "cooperative-localization",
               "cooperative-ekf-slam"};
  o.plots = true;
  o.quiet = true;
  const MrclamEval ev = eval_mrclam(dir, o);
  CHECK(ev.calibration_dir.find("MRCLAM_Dataset2") != std::string::npos);  // calibrated on the other dataset
  const MrclamMethodResult& dr = method(ev, "dead-reckoning");
  const MrclamMethodResult& ekf = method(ev, "ekf-known-landmarks");
  const MrclamMethodResult& unknown = method(ev, "ekf-unknown-correspondence");
  const MrclamMethodResult& coop = method(ev, "cooperative-localization");
  const MrclamMethodResult& slam = method(ev, "cooperative-ekf-slam");
  double dr_mean = 0.0, ekf_mean = 0.0, coop_mean = 0.0;
  for (std::size_t a = 0; a < 5; ++a) {
    INFO("robot " << ekf.robots[a].id << ": dead reckoning " << dr.robots[a].error.rmse_xy_m << " m, EKF "
                  << ekf.robots[a].error.rmse_xy_m << " m, unknown " << unknown.robots[a].error.rmse_xy_m
                  << " m, team " << coop.robots[a].error.rmse_xy_m << " m, SLAM " << slam.robots[a].error.rmse_xy_m);
    // Measured: EKF 0.06-0.11 m, unknown correspondence 0.07-0.13, team 0.04-0.09, SLAM 0.07-0.12.
    CHECK(ekf.robots[a].error.n > 10000u);
    CHECK(ekf.robots[a].error.rmse_xy_m < 0.13);
    CHECK(ekf.robots[a].error.rmse_theta_rad < 0.12);
    CHECK(unknown.robots[a].error.rmse_xy_m < 0.17);
    CHECK(coop.robots[a].error.rmse_xy_m < 0.15);
    CHECK(slam.robots[a].error.rmse_xy_m < 0.20);
    dr_mean += dr.robots[a].error.rmse_xy_m / 5.0;
    ekf_mean += ekf.robots[a].error.rmse_xy_m / 5.0;
    coop_mean += coop.robots[a].error.rmse_xy_m / 5.0;
  }
  CHECK(dr_mean > 5.0 * ekf_mean);
  CHECK(coop_mean < 0.9 * ekf_mean);  // measured 0.072 against 0.087
  CHECK(slam.detail.find("15 landmarks mapped") != std::string::npos);
  const nlohmann::json j = to_json(ev);
  REQUIRE(j["methods"].size() == 5);
  CHECK(j["methods"][1]["name"] == "ekf-known-landmarks");
  CHECK(j["methods"][1]["robots"][0]["id"] == 1);
  CHECK(j["methods"][1]["robots"][0]["rmse_xy_m"].get<double>() == Approx(ekf.robots[0].error.rmse_xy_m));
  // What the run was asked, beside its figures: a result read later says which settings gave it.
  CHECK(j["settings"]["association"] == "jcbb");
  CHECK(j["settings"]["lone_pairing_sigma_m"].get<double>() == Approx(o.noise.lone_pairing_sigma_m));
  CHECK(j["settings"]["ambiguity_nats"].get<double>() == Approx(2.0));
  CHECK(j["settings"]["max_seconds"].get<double>() == Approx(o.max_seconds));
  // The trajectories plot: a panel per robot and method, each robot's estimate over its own true path, its RMSE in
  // the panel's title.
  std::ifstream gp_file(fs::path(o.out_dir) / "trajectories.gp");
  const std::string gp((std::istreambuf_iterator<char>(gp_file)), std::istreambuf_iterator<char>());
  CHECK(gp.find("set multiplot layout 5,5") != std::string::npos);
  std::size_t panels = 0;
  for (std::size_t at = gp.find("\nplot "); at != std::string::npos; at = gp.find("\nplot ", at + 1)) ++panels;
  CHECK(panels == 25u);
  const std::string title = "ekf-known-landmarks\\nrobot 4: " + fixed(ekf.robots[3].error.rmse_xy_m, 3) + " m RMSE";
  CHECK(gp.find(title) != std::string::npos);
  CHECK(gp.find("'truth-robot4.csv' u 2:3 w l lc rgb 'gray70' lw 2, 'ekf-known-landmarks-robot4.csv'") !=
        std::string::npos);
  for (const char* png : {"trajectories.png", "errors.png"}) {
    INFO(png);
    CHECK(fs::file_size(fs::path(o.out_dir) / png) > 10000u);
  }
}

TEST_CASE("MRCLAM odometry calibration: the robots' motion follows their commands by 0.2-0.3 s", "[mrclam]") {
  // The commanded (v, w) are bang-bang turn pulses; Vicon's turns follow them by about a quarter second, and a
  // calibration without that lag explains the true turns worse (the 1 s heading error drops by ~30 % with it).
  const std::string dir = test_support::dataset_or_skip("utias-mrclam/sampled-50hz/MRCLAM_Dataset2");
  const MrclamOdometryScales c = fit_mrclam_odometry_scales(dir);
  for (int r = 1; r <= kMrclamRobots; ++r) {
    INFO("robot " << r << ": v " << c.v[r] << ", w " << c.w[r] << ", lag " << c.lag_s[r] << " s");
    CHECK(c.lag_s[r] >= 0.18);
    CHECK(c.lag_s[r] <= 0.30);
    CHECK(c.v[r] == Approx(0.91).margin(0.03));  // measured 0.910-0.932
    CHECK(c.w[r] == Approx(0.96).margin(0.02));  // measured 0.950-0.971
  }
  CHECK_THROWS_AS(fit_mrclam_odometry_scales(dir, 0.2), std::invalid_argument);
}

TEST_CASE("MRCLAM odometry calibration: fitted over 2 s windows on one dataset, it dead-reckons the other's stretches "
          "between landmark sightings better than over 0.5 s windows",
          "[mrclam]") {
  // Dead reckoning restarted from Vicon every 30 s, Dataset 2 with Dataset 1's fit, position RMSE by robot: 0.120,
  // 0.125, 0.122, 0.109, 0.114 m (2 s windows) against 0.120, 0.148, 0.129, 0.135, 0.148 m (0.5 s windows, which
  // cut the robots' answer to each turn pulse short and scale w by 0.83-0.94 instead of 0.94-0.97).
  const std::string fit_dir = test_support::dataset_or_skip("utias-mrclam/sampled-50hz/MRCLAM_Dataset1");
  const std::string dir = test_support::dataset_or_skip("utias-mrclam/sampled-50hz/MRCLAM_Dataset2");
  double mean[2] = {};
  double per_robot[2][kMrclamRobots + 1] = {};
  const double windows[2] = {0.5, 2.0};
  for (int i = 0; i < 2; ++i) {
    const MrclamOdometryScales c = fit_mrclam_odometry_scales(fit_dir, windows[i]);
    MrclamImportOptions o;
    for (int r = 1; r <= kMrclamRobots; ++r) o.scale_v[r] = c.v[r], o.scale_w[r] = c.w[r], o.lag_s[r] = c.lag_s[r];
    const std::string log = (fs::path(temp_dir("drift")) / "d2.lcmlog").string();
    ImportReport report(OnError::refuse, nullptr);
    import_mrclam(dir, log, o, report);
    for (const MrclamRobotLog& r : read_mrclam_log(log, o.robots)) {
      per_robot[i][r.subject] = drift_rmse(r, 30.0);
      mean[i] += per_robot[i][r.subject] / kMrclamRobots;
    }
  }
  for (int r = 1; r <= kMrclamRobots; ++r) {
    INFO("robot " << r << ": " << per_robot[1][r] << " m (2 s windows) against " << per_robot[0][r] << " m (0.5 s)");
    CHECK(per_robot[1][r] > 0.05);  // the restarts leave a drift to measure
    CHECK(per_robot[1][r] <= per_robot[0][r] + 0.002);
  }
  CHECK(mean[1] < mean[0] - 0.01);  // measured 0.118 against 0.136 m
}

TEST_CASE("MRCLAM Datasets 1 and 2, full runs: EKF localization tracks every robot, with or without the sensor's ids, "
          "and the team does better than each alone",
          "[mrclam][eval]") {
  // Full runs (1500 s and 1900 s) of the two EKFs, which take seconds: with the lag-calibrated odometry and the
  // camera's range noise growing with the range, the known-correspondence means are 0.096 and 0.115 m (0.111 and
  // 0.136 with a constant 0.2 m; 0.118 and 0.152 without the lag too), every robot but robot 4 at or under 0.117 m
  // (robot 4: 0.131 and 0.168 m, its sightings up to 78 and 129 s apart; 0.128 and 0.188 m with the odometry fitted
  // over 0.5 s windows, which fails the 0.18 m bound). Unknown correspondence, each camera frame associated jointly
  // (JCBB, 2 nats, the camera's range noise, no lone pairing with a runner-up above 0.3 m, the gate re-opened in
  // heading only): means 0.108 and 0.117 m, every robot at or under 0.157 m but robot 4 of Dataset 2 (0.173 m; 0.194 m
  // with the 0.5 s fit, 0.212 m when the reopening widened the position by 0.5 m too): the target, no robot
  // lost, each under 0.20 m, is checked as it stands. Without the lone pairing rule and with a constant 0.2 m
  // the means were 0.119 and 0.136 m (worst 0.161 and 0.220 m); one sighting at a time (table 7.3, 1 nat) 0.279 and
  // 0.240 m, worst 0.72 m (4.8 m with table 7.3's plain maximum).
  for (const char* name : {"MRCLAM_Dataset1", "MRCLAM_Dataset2"}) {
    const std::string dir = test_support::dataset_or_skip(std::string("utias-mrclam/sampled-50hz/") + name);
    MrclamEvalOptions o;
    o.out_dir = temp_dir(std::string("full_") + name);
    o.methods = {"ekf-known-landmarks", "ekf-unknown-correspondence", "cooperative-localization"};
    o.plots = false;
    o.quiet = true;
    const MrclamEval ev = eval_mrclam(dir, o);
    const MrclamMethodResult& ekf = method(ev, "ekf-known-landmarks");
    const MrclamMethodResult& unknown = method(ev, "ekf-unknown-correspondence");
    const MrclamMethodResult& team = method(ev, "cooperative-localization");
    double ekf_mean = 0.0, unknown_mean = 0.0;
    for (std::size_t a = 0; a < 5; ++a) {
      INFO(name << " robot " << ekf.robots[a].id << ": EKF " << ekf.robots[a].error.rmse_xy_m << " m / "
                << ekf.robots[a].error.rmse_theta_rad << " rad, unknown " << unknown.robots[a].error.rmse_xy_m);
      CHECK(ekf.robots[a].error.rmse_xy_m < (ekf.robots[a].id == 4 ? 0.18 : 0.125));
      CHECK(ekf.robots[a].error.rmse_theta_rad < 0.16);
      CHECK(unknown.robots[a].error.rmse_xy_m < 0.20);
      // The team (the robots' sightings of each other shared) does better than each robot alone: measured 0.060-0.099
      // m against 0.073-0.168 m, the closest robot 3 of Dataset 1 (0.060 against 0.073 m). With the team's heading
      // noise at 0.01 rad per step robot 2 of Dataset 2 fails it (0.10613 against 0.10613 m, 4e-6 m worse).
      INFO("team " << team.robots[a].error.rmse_xy_m << " m");
      CHECK(team.robots[a].error.rmse_xy_m < ekf.robots[a].error.rmse_xy_m);
      ekf_mean += ekf.robots[a].error.rmse_xy_m / 5.0;
      unknown_mean += unknown.robots[a].error.rmse_xy_m / 5.0;
    }
    INFO(name << ": means EKF " << ekf_mean << " m, unknown " << unknown_mean << " m");
    CHECK(ekf_mean < 0.13);
    CHECK(unknown_mean < 0.135);
  }
}

TEST_CASE("MRCLAM Dataset 2, full run: MCL on the landmarks through estimator_node's pipeline keeps every robot",
          "[mrclam][eval]") {
  // 100 particles (the evaluation's 500 take 145 s): with MCL's rotation noise a4 = 5 (MrclamNoise::mcl_a4) every
  // robot at 0.169-0.289 m, mean 0.207 m; with the shared a4 = 0.5 robot 4 is lost for 150 s after a turn in place
  // the commands under-report by 0.7 rad (0.772 m, robot 5 0.384 m, mean 0.349 m). About 33 s.
  const std::string dir = test_support::dataset_or_skip("utias-mrclam/sampled-50hz/MRCLAM_Dataset2");
  MrclamEvalOptions o;
  o.out_dir = temp_dir("eval2");
  o.methods = {"dead-reckoning", "mcl-landmarks"};
  o.particles = 100;
  o.plots = false;
  o.quiet = true;
  const MrclamEval ev = eval_mrclam(dir, o);
  const MrclamMethodResult& dr = method(ev, "dead-reckoning");
  const MrclamMethodResult& mcl = method(ev, "mcl-landmarks");
  double dr_mean = 0.0, mcl_mean = 0.0;
  for (std::size_t a = 0; a < 5; ++a) {
    INFO("robot " << mcl.robots[a].id << ": MCL " << mcl.robots[a].error.rmse_xy_m << " m, dead reckoning "
                  << dr.robots[a].error.rmse_xy_m << " m");
    CHECK(mcl.robots[a].error.n > 50000u);
    CHECK(mcl.robots[a].error.rmse_xy_m < 0.35);
    dr_mean += dr.robots[a].error.rmse_xy_m / 5.0;
    mcl_mean += mcl.robots[a].error.rmse_xy_m / 5.0;
  }
  CHECK(mcl_mean < 0.25);
  CHECK(mcl_mean < dr_mean);
}
