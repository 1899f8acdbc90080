// The cooperative EKF-SLAM scenarios (team_scenarios.hpp): coop-slam, the exercise (two holonomic point robots, one
// landmark with an initial estimate, range only, every robot measuring the other and the landmark at every step,
// all four rows of z_k shared with the controls), and coop-slam-team (four robots, twelve landmarks mapped from
// scratch, range and bearing within a reach). Each robot's node is run in process as the network would run it: a
// team window and the estimator of estimator_node --filter coop-ekf (node/team_spec.hpp), fed every robot's message
// (each node in its own order of arrival), and, for the comparison, each robot's node fed only its own messages.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"
#include "node/pacer.hpp"
#include "node/team_spec.hpp"
#include "node/view_feed.hpp"
#include "sim/plot.hpp"
#include "sim/progress.hpp"
#include "team/coop_world.hpp"
#include "team/team_logs.hpp"
#include "team/team_scenarios.hpp"

namespace sim::team {

namespace fs = std::filesystem;
using est::team::TeamMessage;

namespace {

// One robot's node: its window and the team's estimator (heap: the estimator holds a 144 x 144 covariance).
struct TeamNode {
  node::TeamWindow window;
  node::TeamEstimator est;
  std::vector<std::string> lines;  // team_estimate_line per closed step
  std::vector<std::uint32_t> steps;
  bool keep_lines = false;
  void push(const TeamMessage& m) {
    window.push(m, [this](std::uint32_t seq, const TeamMessage* const* msgs) { close(seq, msgs); });
  }
  void flush() {
    window.flush([this](std::uint32_t seq, const TeamMessage* const* msgs) { close(seq, msgs); });
  }
  void close(std::uint32_t seq, const TeamMessage* const* msgs) {
    est.step(seq, msgs);
    if (keep_lines) lines.push_back(node::team_estimate_line(seq, est));
  }
};

// The 95 % two-sided band of chi2(n) (Wilson-Hilferty: within 1 % of the exact quantiles for n >= 3).
struct Band {
  double lo, hi;
};
Band chi2_band(int n) {
  const double k = static_cast<double>(n), a = 2.0 / (9.0 * k), z = 1.959964;
  return {k * std::pow(1.0 - a - z * std::sqrt(a), 3.0), k * std::pow(1.0 - a + z * std::sqrt(a), 3.0)};
}

// The figures of one estimate against the truth, accumulated per step.
struct Errors {
  std::vector<double> sq_sum;       // per robot, squared position error summed over steps
  std::vector<double> final_error;  // per robot, m
  double nees_sum = 0.0;
  int nees_steps = 0, in_band = 0;
  std::vector<std::vector<double>> per_step;  // [step][robot] position error, m
  std::vector<double> nees;                   // per step
};

double robot_error(const node::TeamEstimator& e, const CoopWorld& w, int a) {
  return static_cast<double>((e.slam().robot(a) - w.robot(a)).norm());
}

// NEES of robot `only`'s position (only >= 0) or of the whole state (robots and landmarks), in double.
double state_nees(const node::TeamEstimator& e, const CoopWorld& w, int only = -1) {
  const auto& s = e.slam();
  std::vector<int> idx;
  std::vector<double> err;
  for (int a = 0; a < s.robots(); ++a) {
    if (only >= 0 && a != only) continue;
    for (int i = 0; i < 2; ++i) {
      idx.push_back(2 * a + i);
      err.push_back(static_cast<double>(s.mean()(2 * a + i)) - static_cast<double>(w.robot(a)(i)));
    }
  }
  for (int k = 0; only < 0 && k < s.landmarks(); ++k)
    for (int i = 0; i < 2; ++i) {
      idx.push_back(s.landmark_offset(k) + i);
      err.push_back(static_cast<double>(s.landmark(k)(i)) - static_cast<double>(w.landmark_by_id(s.landmark_id(k))(i)));
    }
  const int n = static_cast<int>(idx.size());
  Eigen::MatrixXd P(n, n);
  Eigen::VectorXd e_(n);
  for (int r = 0; r < n; ++r) {
    e_(r) = err[static_cast<std::size_t>(r)];
    for (int c = 0; c < n; ++c)
      P(r, c) = static_cast<double>(s.covariance()(idx[static_cast<std::size_t>(r)], idx[static_cast<std::size_t>(c)]));
  }
  return e_.dot(P.ldlt().solve(e_));
}

void account(Errors& x, const node::TeamEstimator& e, const CoopWorld& w, int robot_of_node) {
  const int R = w.robots();
  if (x.sq_sum.empty()) x.sq_sum.assign(static_cast<std::size_t>(R), 0.0), x.final_error.assign(x.sq_sum.size(), 0.0);
  std::vector<double> row;
  for (int a = 0; a < R; ++a) {
    if (robot_of_node >= 0 && a != robot_of_node) {
      row.push_back(0.0);
      continue;
    }
    const double d = robot_error(e, w, a);
    x.sq_sum[static_cast<std::size_t>(a)] += d * d;
    x.final_error[static_cast<std::size_t>(a)] = d;
    row.push_back(d);
  }
  x.per_step.push_back(row);
  // The own-only node's NEES is its own robot's; the shared node's the whole state's.
  const double nees = state_nees(e, w, robot_of_node);
  const int dof = robot_of_node >= 0 ? 2 : e.slam().dim();
  const Band b = chi2_band(dof);
  x.nees.push_back(nees / dof);
  x.nees_sum += nees / dof;
  ++x.nees_steps;
  if (nees >= b.lo && nees <= b.hi) ++x.in_band;
}

nlohmann::json summary_json(const Errors& x, const node::TeamEstimator& landmarks_from, const CoopWorld& w,
                            int steps, bool per_robot_nees) {
  nlohmann::json j;
  j["per_robot"] = nlohmann::json::array();
  for (int a = 0; a < w.robots(); ++a)
    j["per_robot"].push_back({{"robot", a},
                              {"position_rmse_m", std::sqrt(x.sq_sum[static_cast<std::size_t>(a)] / steps)},
                              {"final_position_error_m", x.final_error[static_cast<std::size_t>(a)]}});
  const auto& s = landmarks_from.slam();
  j["landmarks"] = nlohmann::json::array();
  double sum = 0.0;
  for (int k = 0; k < s.landmarks(); ++k) {
    const double d = static_cast<double>((s.landmark(k) - w.landmark_by_id(s.landmark_id(k))).norm());
    sum += d;
    j["landmarks"].push_back({{"id", s.landmark_id(k)}, {"position_error_m", d}});
  }
  j["landmarks_mapped"] = s.landmarks();
  j["landmark_error_mean_m"] = s.landmarks() > 0 ? sum / s.landmarks() : 0.0;
  j["nees_of"] = per_robot_nees ? "each node's own robot position (2 dof)" : "the whole state (robots and landmarks)";
  j["nees_mean_per_dof"] = x.nees_sum / x.nees_steps;
  j["nees_in_95_band_share"] = static_cast<double>(x.in_band) / x.nees_steps;
  return j;
}

double mean_rmse(const nlohmann::json& j) {
  double s = 0.0;
  for (const auto& r : j["per_robot"]) s += r["position_rmse_m"].get<double>();
  return s / static_cast<double>(j["per_robot"].size());
}

void write_csv(const fs::path& p, const CoopWorld& w, const std::vector<std::vector<Eigen::Vector2f>>& truth,
               const std::vector<std::vector<Eigen::Vector2f>>& shared,
               const std::vector<std::vector<Eigen::Vector2f>>& own, const Errors& es, const Errors& eo) {
  std::ofstream f(p);
  f << "t_s";
  for (int a = 0; a < w.robots(); ++a)
    f << ",true_x" << a << ",true_y" << a << ",shared_x" << a << ",shared_y" << a << ",own_x" << a << ",own_y" << a
      << ",shared_err" << a << ",own_err" << a;
  f << ",shared_nees_per_dof,own0_nees_per_dof\n";
  for (std::size_t k = 0; k < truth.size(); ++k) {
    f << static_cast<double>(k + 1) * static_cast<double>(w.step_s());
    for (std::size_t a = 0; a < truth[k].size(); ++a)
      f << "," << truth[k][a](0) << "," << truth[k][a](1) << "," << shared[k][a](0) << "," << shared[k][a](1) << ","
        << own[k][a](0) << "," << own[k][a](1) << "," << es.per_step[k][a] << "," << eo.per_step[k][a];
    f << "," << es.nees[k] << "," << eo.nees[k] << "\n";
  }
  if (!f) throw std::runtime_error("cannot write " + p.string());
}

void plot(const fs::path& dir, const CoopWorld& w, const node::TeamEstimator& shared, const Band& band_per_dof) {
  static const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2",
                                 "#17becf"};
  {
    std::ofstream lm(dir / "landmarks.dat");
    for (int k = 0; k < w.landmarks(); ++k) lm << w.landmark(k)(0) << "," << w.landmark(k)(1) << "\n";
    std::ofstream le(dir / "landmarks_estimated.dat");
    for (int k = 0; k < shared.slam().landmarks(); ++k)
      le << shared.slam().landmark(k)(0) << "," << shared.slam().landmark(k)(1) << "\n";
    std::ofstream gp(dir / "trajectory.gp");
    gp << "# sim_host simulate --scenario: truth, shared and own-only estimates (gnuplot trajectory.gp here)\n"
          "set terminal pngcairo size 1200,900\nset output 'trajectory.png'\nset datafile separator ','\n"
          "set size ratio -1\nset key outside right\nset xlabel 'x (m)'\nset ylabel 'y (m)'\n"
          "set title 'Team paths: truth (solid), shared z and u (dashed), own measurements only (dotted)'\nplot ";
    for (int a = 0; a < w.robots(); ++a) {
      const int c = 2 + 8 * a;
      gp << "'trajectory.csv' skip 1 using " << c << ":" << c + 1 << " with lines lw 2 lc rgb '" << colors[a]
         << "' title 'robot " << a << " truth', '' skip 1 using " << c + 2 << ":" << c + 3
         << " with lines dt 2 lc rgb '" << colors[a] << "' title 'shared', '' skip 1 using " << c + 4 << ":"
         << c + 5 << " with lines dt 3 lc rgb '" << colors[a] << "' title 'own only', ";
    }
    gp << "'landmarks.dat' using 1:2 with points pt 5 ps 1.5 lc rgb 'black' title 'landmarks',"
          " 'landmarks_estimated.dat' using 1:2 with points pt 2 ps 2 lc rgb 'black' title 'mapped (shared)'\n";
  }
  run_gnuplot(dir / "trajectory.gp", dir / "trajectory.png");
  {
    std::ofstream gp(dir / "errors.gp");
    const int R = w.robots(), nees_col = 2 + 8 * R;
    gp << "# sim_host simulate --scenario: errors and NEES over time (gnuplot errors.gp here)\n"
          "set terminal pngcairo size 1200,900\nset output 'errors.png'\nset datafile separator ','\n"
          "set multiplot layout 2,1\nset key outside right\nset xlabel 't (s)'\nset ylabel 'position error (m)'\n"
          "set title 'Position error per robot: shared z and u (solid) vs own measurements only (dotted)'\nplot ";
    for (int a = 0; a < R; ++a)
      gp << (a ? ", " : "") << "'trajectory.csv' skip 1 using 1:" << 8 + 8 * a << " with lines lw 2 lc rgb '"
         << colors[a] << "' title 'robot " << a << " shared', '' skip 1 using 1:" << 9 + 8 * a
         << " with lines dt 3 lc rgb '" << colors[a] << "' title 'robot " << a << " own'";
    gp << "\nset ylabel 'NEES / dof'\nset logscale y\n"
          "set title 'NEES of the whole shared state per dof, with its 95 % band at the final dimension'\n"
          "plot 'trajectory.csv' skip 1 using 1:"
       << nees_col << " with lines lc rgb 'black' title 'shared', " << band_per_dof.lo
       << " with lines dt 2 lc rgb 'gray40' title '2.5 %', " << band_per_dof.hi
       << " with lines dt 2 lc rgb 'gray40' title '97.5 %'\nunset multiplot\n";
  }
  run_gnuplot(dir / "errors.gp", dir / "errors.png");
}

// Robot a's estimate of itself on node a (a point robot: no heading), with its position covariance.
TeamLogStep log_step(hal::TimeNs stamp_ns, const CoopWorld& w, const std::vector<std::unique_ptr<TeamNode>>& nodes) {
  TeamLogStep s;
  s.stamp_ns = stamp_ns;
  for (int a = 0; a < w.robots(); ++a) {
    s.truth.push_back({w.robot(a)(0), w.robot(a)(1), 0.0f});
    const auto& slam = nodes[static_cast<std::size_t>(a)]->est.slam();
    hal::Estimate e;
    e.stamp_ns = stamp_ns;
    e.pose = {slam.robot(a)(0), slam.robot(a)(1), 0.0f};
    e.covariance.topLeftCorner<2, 2>() = slam.covariance().block<2, 2>(2 * a, 2 * a);
    s.estimate.push_back(e);
  }
  return s;
}

}  // namespace

void run_coop_slam(const TeamRunOptions& o, bool team_of_four) {
  CoopWorld w(team_of_four ? CoopWorld::team_of_four(o.seed) : CoopWorld::exercise(o.seed));
  const double duration = o.duration_s > 0.0 ? o.duration_s : 60.0;
  const int steps = static_cast<int>(std::lround(duration / static_cast<double>(w.step_s())));
  if (steps < 1) throw std::runtime_error("--duration shorter than one team step");
  const node::TeamSpec spec = w.spec();
  const int R = w.robots();

  std::vector<std::unique_ptr<TeamNode>> shared, own;
  for (int a = 0; a < R; ++a) {
    shared.push_back(std::make_unique<TeamNode>());
    own.push_back(std::make_unique<TeamNode>());
    node::start_team(spec, shared.back()->window, shared.back()->est);
    node::start_team(spec, own.back()->window, own.back()->est);
  }
  shared[0]->keep_lines = true;
  std::vector<std::vector<TeamMessage>> by_robot(static_cast<std::size_t>(R));
  std::vector<std::vector<Eigen::Vector2f>> truth, est_shared, est_own;
  std::vector<TeamLogStep> logged;  // the run log's truth and each robot's node's estimate of itself
  Errors es, eo;
  Progress progress(o.scenario, steps * static_cast<double>(w.step_s()), o.quiet, Progress::Unit::simulated_s, 2.0);
  node::Pacer pacer(o.view != nullptr ? o.view_speed : 0.0);
  for (std::uint32_t k = 1; k <= static_cast<std::uint32_t>(steps); ++k) {
    progress.update(k * static_cast<double>(w.step_s()));
    const std::vector<TeamMessage> msgs = w.step(k);
    for (int a = 0; a < R; ++a) {
      by_robot[static_cast<std::size_t>(a)].push_back(msgs[static_cast<std::size_t>(a)]);
      // Node a hears its own message first, then the others in turn after it: a different order at every node.
      TeamNode& n = *shared[static_cast<std::size_t>(a)];
      for (int i = 0; i < R; ++i) n.push(msgs[static_cast<std::size_t>((a + i) % R)]);
      // Without sharing a node waits for nobody (its step closes with its own message), and it has nothing to
      // fuse a range to a teammate with: it keeps its controls and landmark measurements. (Fusing the teammate
      // ranges against a teammate predicted without controls made the EKF inconsistent: NEES 4.8 per dof, and
      // twice the error, in the exercise at seed 1.)
      TeamMessage mine = msgs[static_cast<std::size_t>(a)];
      std::int32_t kept = 0;
      for (std::int32_t i = 0; i < mine.count; ++i)
        if (mine.measurements[i].target == est::team::TargetKind::landmark)
          mine.measurements[kept++] = mine.measurements[i];
      mine.count = kept;
      own[static_cast<std::size_t>(a)]->push(mine);
      own[static_cast<std::size_t>(a)]->flush();
    }
    std::vector<Eigen::Vector2f> t, s, m;
    for (int a = 0; a < R; ++a) {
      t.push_back(w.robot(a));
      s.push_back(shared[0]->est.slam().robot(a));
      m.push_back(own[static_cast<std::size_t>(a)]->est.slam().robot(a));
    }
    truth.push_back(t), est_shared.push_back(s), est_own.push_back(m);
    logged.push_back(log_step(msgs.front().stamp_ns, w, shared));
    if (o.view != nullptr) {  // what robot 0's node would show (every node holds the same estimate)
      pacer.at(msgs.front().stamp_ns);
      for (int a = 0; a < R; ++a)
        o.view->publish_team_truth(a, msgs.front().stamp_ns,
                                   {static_cast<double>(w.robot(a)(0)), static_cast<double>(w.robot(a)(1)), 0.0});
      node::feed_team(*o.view, shared[0]->est, 0, msgs.front().stamp_ns);
    }
    account(es, shared[0]->est, w, -1);
    // The own-only figures: robot a's position from robot a's node.
    std::vector<double> row;
    for (int a = 0; a < R; ++a) {
      const double d = robot_error(own[static_cast<std::size_t>(a)]->est, w, a);
      row.push_back(d);
      if (eo.sq_sum.empty()) eo.sq_sum.assign(static_cast<std::size_t>(R), 0.0), eo.final_error = eo.sq_sum;
      eo.sq_sum[static_cast<std::size_t>(a)] += d * d;
      eo.final_error[static_cast<std::size_t>(a)] = d;
      const double n = state_nees(own[static_cast<std::size_t>(a)]->est, w, a);
      const Band b = chi2_band(2);
      eo.nees_sum += n / 2.0 / R;
      if (n >= b.lo && n <= b.hi) eo.in_band += 1;
      if (a == 0) eo.nees.push_back(n / 2.0);
    }
    eo.nees_steps += 1;
    eo.per_step.push_back(row);
  }
  progress.finish();
  eo.in_band /= R;  // the share over every (node, step)

  bool identical = true;
  for (int a = 1; a < R; ++a) {
    const auto& x = shared[0]->est.slam();
    const auto& y = shared[static_cast<std::size_t>(a)]->est.slam();
    identical = identical && x.dim() == y.dim() &&
                std::memcmp(x.mean().data(), y.mean().data(), sizeof(float) * static_cast<std::size_t>(x.dim())) == 0 &&
                std::memcmp(x.covariance().data(), y.covariance().data(), sizeof(x.covariance())) == 0;
  }

  fs::create_directories(o.out);
  const fs::path dir(o.out);
  nlohmann::json j;
  j["scenario"] = o.scenario;
  j["seed"] = o.seed;
  j["robots"] = R;
  j["landmarks"] = w.landmarks();
  j["measurements"] = w.bearings() ? "range and bearing" : "range only";
  j["landmark_priors"] = static_cast<int>(spec.landmarks.size());
  j["steps"] = steps;
  j["step_s"] = w.step_s();
  j["shared"] = summary_json(es, shared[0]->est, w, steps, false);
  j["own_only"] = summary_json(eo, own[0]->est, w, steps, true);
  j["own_only"]["landmarks_from"] = "robot 0's node";
  j["own_only"]["nees_in_95_band_share"] = static_cast<double>(eo.in_band) / steps;
  j["own_only"]["nees_mean_per_dof"] = eo.nees_sum / steps;
  j["sharing_gain"] = {{"position_rmse_shared_m", mean_rmse(j["shared"])},
                       {"position_rmse_own_only_m", mean_rmse(j["own_only"])},
                       {"ratio", mean_rmse(j["shared"]) / mean_rmse(j["own_only"])}};
  j["nodes_identical"] = identical;
  const auto& wc = shared[0]->window.counters();
  const auto& c = shared[0]->est.slam().counters();
  j["window"] = {{"accepted", wc.accepted}, {"steps_closed", wc.steps_closed}, {"steps_complete", wc.steps_complete},
                 {"rejected", wc.rejected_total()}};
  j["measurements_fused"] = {{"accepted", c.accepted}, {"gated_out", c.gated_out}, {"pending", c.pending},
                             {"rejected", c.rejected()}};
  j["node_options"] = node::team_command_line(spec);
  {
    std::ofstream f(dir / "metrics.json");
    f << j.dump(2) << "\n";
    if (!f) throw std::runtime_error("cannot write " + (dir / "metrics.json").string());
  }
  {
    std::ofstream f(dir / "team_estimates.csv");
    f << node::team_estimate_header() << "\n";
    for (const std::string& l : shared[0]->lines) f << l << "\n";
  }
  write_csv(dir / "trajectory.csv", w, truth, est_shared, est_own, es, eo);
  write_team_logs(dir, o.scenario, by_robot, logged, &spec);
  if (o.plots) {
    const Band b = chi2_band(shared[0]->est.slam().dim());
    const double n = shared[0]->est.slam().dim();
    plot(dir, w, shared[0]->est, {b.lo / n, b.hi / n});
  }

  std::printf("%s: %d robots, %d landmarks (%s), %d steps of %.2f s, seed %llu\n", o.scenario.c_str(), R,
              w.landmarks(), w.bearings() ? "range and bearing" : "range only", steps,
              static_cast<double>(w.step_s()), static_cast<unsigned long long>(o.seed));
  for (int a = 0; a < R; ++a)
    std::printf("  robot %d: position RMSE %.3f m shared, %.3f m own measurements only\n", a,
                j["shared"]["per_robot"][static_cast<std::size_t>(a)]["position_rmse_m"].get<double>(),
                j["own_only"]["per_robot"][static_cast<std::size_t>(a)]["position_rmse_m"].get<double>());
  std::printf("  landmarks: mean error %.3f m shared (%d mapped), %.3f m own only\n",
              j["shared"]["landmark_error_mean_m"].get<double>(), j["shared"]["landmarks_mapped"].get<int>(),
              j["own_only"]["landmark_error_mean_m"].get<double>());
  std::printf("  NEES per dof %.2f, %.0f %% of steps inside the 95 %% band; every node identical: %s\n",
              j["shared"]["nees_mean_per_dof"].get<double>(),
              100.0 * j["shared"]["nees_in_95_band_share"].get<double>(),
              identical ? "yes" : "NO");
  std::printf("  -> %s (metrics.json, trajectory.csv, team_estimates.csv, run.lcmlog, logs/%s)\n", o.out.c_str(),
              o.plots ? ", trajectory.png, errors.png" : "");
}

}  // namespace sim::team
