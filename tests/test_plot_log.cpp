// sim_host plot (data/plot_log.hpp): a run's LCM log plotted from the log alone gives the errors the run measured,
// pairs channels by suffix, and refuses what is not an LCM log.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "data/plot_log.hpp"
#include "scratch_dir.hpp"
#include "sim/builtin_scenarios.hpp"
#include "sim/scenario_run.hpp"

namespace {

namespace fs = std::filesystem;
using est::test::ScratchDir;

// The position RMSE over every row of a run's trajectory.csv (its truth and estimate columns by name).
double trajectory_csv_rmse(const fs::path& csv, std::size_t& rows) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream h(line);
  for (std::string n; std::getline(h, n, ',');) names.push_back(n);
  const auto col = [&](const std::string& n) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == n) return i;
    FAIL("no column " << n << " in " << line);
    return std::size_t{0};
  };
  const std::size_t tx = col("truth_x_m"), ty = col("truth_y_m"), ex = col("est_x_m"), ey = col("est_y_m");
  double se = 0.0;
  rows = 0;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream s(line);
    for (std::string f; std::getline(s, f, ',');) v.push_back(std::stod(f));
    se += std::pow(v[ex] - v[tx], 2) + std::pow(v[ey] - v[ty], 2);
    ++rows;
  }
  return std::sqrt(se / static_cast<double>(rows));
}

}  // namespace

TEST_CASE("a run's log plotted from the log alone gives the run's position RMSE", "[plot_log]") {
  ScratchDir d("plot_log");
  sim::ScenarioFile f = sim::load_scenario("kidnapped");
  f.scenario.duration_s = 15.0;  // global localization, the kidnapping at 12 s: errors of metres, then centimetres
  sim::run_scenario(f, sim::RunOptions{d.path.string(), false, true});
  const std::vector<sim::data::LogSeries> s = sim::data::read_log_series({(d.path / "run.lcmlog").string()});
  REQUIRE(s.size() == 1u);
  CHECK(s[0].suffix.empty());
  CHECK(s[0].estimate.size() == 1500u);
  CHECK(s[0].truth.size() >= 1500u);
  std::size_t rows = 0;
  const double rmse = trajectory_csv_rmse(d.path / "trajectory.csv", rows);
  INFO("log: " << s[0].error.rmse_xy_m << " m over " << s[0].error.n << "; trajectory.csv: " << rmse << " m over "
               << rows);
  CHECK(rows == 1500u);
  CHECK(s[0].error.n == 1500u);
  CHECK(rmse > 0.05);  // the global start and the kidnapping are in it
  CHECK(s[0].error.rmse_xy_m == Approx(rmse).epsilon(1e-4));
  const std::vector<std::string> pngs = sim::data::write_log_plots(s, (d.path / "plots").string());
  REQUIRE(pngs.size() == 2u);
  for (const std::string& p : pngs) CHECK(fs::file_size(p) > 1000u);
}

TEST_CASE("a file that is not an LCM log is refused with its name", "[plot_log]") {
  ScratchDir d("plot_log_bad");
  const fs::path bad = d.path / "not-a-log.lcmlog";
  std::ofstream(bad) << "this is not an LCM log\n";
  try {
    sim::data::read_log_series({bad.string()});
    FAIL("read as a log");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()).find("not-a-log.lcmlog: not an LCM log") != std::string::npos);
  }
}
