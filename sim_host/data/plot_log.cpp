// The plots of an LCM log (data/plot_log.hpp).
#include "data/plot_log.hpp"

#include <CLI/CLI.hpp>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <stdexcept>

#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/pose_estimate_t.hpp>

#include "hal/lcm/lcm_log_reader.hpp"
#include "sim/plot.hpp"

namespace sim::data {
namespace {

namespace fs = std::filesystem;
constexpr std::int64_t kMaxTruthGapNs = 200000000;  // 0.2 s without a truth sample: no reference there

// The suffix of `channel` after `prefix` when it is "" or "_<digits>"; false otherwise (EST_POSE_STATUS is not a pose).
bool suffix_of(const std::string& channel, const std::string& prefix, std::string& suffix) {
  if (channel.compare(0, prefix.size(), prefix) != 0) return false;
  suffix = channel.substr(prefix.size());
  if (suffix.empty()) return true;
  if (suffix.size() < 2 || suffix[0] != '_') return false;
  for (std::size_t i = 1; i < suffix.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(suffix[i]))) return false;
  return true;
}

std::string label(const std::string& suffix) { return suffix.empty() ? "robot" : "robot " + suffix.substr(1); }
std::string file_key(const std::string& suffix) { return suffix.empty() ? "robot" : "robot" + suffix; }

}  // namespace

std::vector<LogSeries> read_log_series(const std::vector<std::string>& logs) {
  std::map<std::string, LogSeries> by;
  for (const std::string& path : logs) {
    hal::lcm::read_lcm_log(path, "sim_host plot: warning", stderr, [&](const hal::lcm::LcmLogEvent& e) {
      std::string s;
      if (suffix_of(e.channel, "EST_POSE", s)) {
        est_lcm::pose_estimate_t p;
        if (p.decode(e.data.data(), 0, e.size()) != e.size())
          throw std::runtime_error(path + ": " + e.channel + ": not a pose_estimate_t");
        by[s].estimate.push_back({p.stamp_ns, p.x_m, p.y_m, p.theta_rad});
      } else if (suffix_of(e.channel, "EST_GROUND_TRUTH", s)) {
        est_lcm::ground_truth_t g;
        if (g.decode(e.data.data(), 0, e.size()) != e.size())
          throw std::runtime_error(path + ": " + e.channel + ": not a ground_truth_t");
        by[s].truth.push_back({g.stamp_ns, g.x_m, g.y_m, g.theta_rad});
      }
    });
  }
  std::vector<LogSeries> out;
  for (auto& [suffix, series] : by) {
    series.suffix = suffix;
    if (!series.truth.empty() && !series.estimate.empty())
      series.error = trajectory_error(series.estimate, series.truth, kMaxTruthGapNs);
    out.push_back(std::move(series));
  }
  return out;
}

std::vector<std::string> write_log_plots(const std::vector<LogSeries>& series, const std::string& dir) {
  const fs::path d(dir);
  fs::create_directories(d);
  std::int64_t t0 = INT64_MAX;
  for (const LogSeries& s : series) {
    if (!s.truth.empty()) t0 = std::min(t0, s.truth.front().t_ns);
    if (!s.estimate.empty()) t0 = std::min(t0, s.estimate.front().t_ns);
  }
  const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"};
  std::ofstream tr(d / "trajectories.gp"), er(d / "errors.gp");
  tr << "set terminal pngcairo size 900,700 font ',9'\nset output 'trajectories.png'\nset size ratio -1\n"
        "set title 'estimates (colour) and ground truth (grey)'\nset xlabel 'x (m)'\nset ylabel 'y (m)'\nplot ";
  er << "set terminal pngcairo size 1000,400 font ',9'\nset output 'errors.png'\nset title 'position error "
        "against the ground truth'\nset xlabel 't (s)'\nset ylabel 'm'\nplot ";
  bool any_error = false;
  std::size_t k = 0;
  for (const LogSeries& s : series) {
    const std::string key = file_key(s.suffix), color = colors[k++ % 5];
    std::ofstream t(d / (key + "-truth.csv")), e(d / (key + "-estimate.csv"));
    t << "t x y theta\n";
    for (const TimedPose& p : s.truth)
      t << static_cast<double>(p.t_ns - t0) * 1e-9 << " " << p.x << " " << p.y << " " << p.theta << "\n";
    e << "t x y theta err_xy err_theta\n";
    const std::vector<ErrorSample> errs =
        s.truth.empty() ? std::vector<ErrorSample>{} : error_series(s.estimate, s.truth, kMaxTruthGapNs, t0);
    if (!errs.empty()) any_error = true;
    std::size_t j = 0;
    for (const TimedPose& p : s.estimate) {
      const double ts = static_cast<double>(p.t_ns - t0) * 1e-9;
      while (j + 1 < errs.size() && errs[j].t_s < ts) ++j;
      e << ts << " " << p.x << " " << p.y << " " << p.theta << " " << (errs.empty() ? 0.0 : errs[j].xy_m) << " "
        << (errs.empty() ? 0.0 : errs[j].theta_rad) << "\n";
    }
    if (k > 1) tr << ", ";
    tr << "'" << key << "-truth.csv' u 2:3 w l lc rgb 'gray70' lw 2 t '" << label(s.suffix) << " truth', '" << key
       << "-estimate.csv' u 2:3 w l lc rgb '" << color << "' t '" << label(s.suffix) << " estimate'";
    if (!errs.empty())
      er << (k > 1 ? ", " : "") << "'" << key << "-estimate.csv' u 1:5 w l lc rgb '" << color << "' t '"
         << label(s.suffix) << "'";
  }
  tr << "\n";
  er << "\n";
  tr.close();
  er.close();
  std::vector<std::string> pngs;
  if (series.empty()) return pngs;
  sim::run_gnuplot(d / "trajectories.gp", d / "trajectories.png");
  pngs.push_back((d / "trajectories.png").string());
  if (any_error) {
    sim::run_gnuplot(d / "errors.gp", d / "errors.png");
    pngs.push_back((d / "errors.png").string());
  }
  return pngs;
}

void add_plot_command(CLI::App& app) {
  auto logs = std::make_shared<std::vector<std::string>>();
  auto out = std::make_shared<std::string>("plots");
  auto no_plots = std::make_shared<bool>(false);
  CLI::App* c = app.add_subcommand(
      "plot",
      "Plots any LCM log the project writes or imports, from the log alone: the estimates (EST_POSE[_n]) against "
      "the ground truth (EST_GROUND_TRUTH[_n]), paired by channel suffix: trajectories.png, errors.png and a table "
      "of the errors. A run's log (sim_host run), a recording, an imported dataset, or estimator_node's --out beside "
      "the log it replayed");
  c->add_option("LOG", *logs, "LCM logs (their channels are merged)")->required()->check(CLI::ExistingFile);
  c->add_option("--out", *out, "folder for the PNGs and their data")->capture_default_str();
  c->add_flag("--no-plots", *no_plots, "only the table");
  c->callback([=] {
    const std::vector<LogSeries> series = read_log_series(*logs);
    if (series.empty()) throw std::runtime_error("no EST_POSE or EST_GROUND_TRUTH channel in the log");
    std::vector<std::vector<std::string>> rows;
    for (const LogSeries& s : series)
      rows.push_back({label(s.suffix), std::to_string(s.estimate.size()), std::to_string(s.truth.size()),
                      s.error.n > 0 ? fixed(s.error.rmse_xy_m, 3) + " m" : "-",
                      s.error.n > 0 ? fixed(s.error.rmse_theta_rad, 3) : "-",
                      s.error.n > 0 ? fixed(s.error.max_xy_m, 3) + " m" : "-"});
    print_table(stdout, {"series", "estimates", "truths", "RMSE xy", "RMSE theta (rad)", "max xy"}, rows);
    if (*no_plots) return;
    for (const std::string& p : write_log_plots(series, *out)) std::printf("  %s\n", p.c_str());
  });
}

}  // namespace sim::data
