#include "sim/scenario_run.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>
#include <thread>

#include "node/view_feed.hpp"
#include "sim/progress.hpp"
#include "sim/record.hpp"
#include "sim/sample_motion.hpp"
#include "sim/simulate.hpp"
#include "team/team_scenarios.hpp"

namespace sim {
namespace {

std::string num(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

void print_summary(const SimResult& r, const ScenarioConfig& sc, const SimWorld& w, const std::string& out) {
  const SimMetrics& m = r.metrics;
  std::cout << "simulate (" << r.description << "): " << to_string(sc.robot) << " in " << w.name << ", " << num("%.1f", sc.duration_s)
            << " s, seed " << sc.seed << ": " << r.rows.size() << " estimates in " << num("%.1f", r.wall_s) << " s ("
            << num("%.1f", sc.duration_s / std::max(r.wall_s, 1e-9)) << "x real time)\n";
  for (const PhaseMetrics& p : m.phases) {
    const bool kidnap = p.name == "kidnap recovery";
    std::cout << "  " << p.name << " (from " << num("%.2f", p.start_s) << " s"
              << (kidnap ? ", carried " + num("%.1f", r.stream.kidnap_distance_m) + " m" : std::string()) << "): ";
    if (kidnap && p.lost_at_s < 0.0)
      std::cout << "the estimate never left the bounds: NOT a loss, NOT recovered\n";
    else if (p.localized)
      std::cout << (kidnap ? "lost at " + num("%.2f", p.lost_at_s) + " s, " : std::string()) << "localized after "
                << num("%.2f", p.time_to_localize_s) << " s" << (kidnap ? " from the loss" : "") << "\n";
    else
      std::cout << "NOT localized by " << num("%.2f", p.end_s) << " s\n";
    if (p.localized && p.particles_mean >= 0.0)
      std::cout << "    once localized: " << p.injected_particles << " of " << p.drawn_particles
                << " particles drawn were injected (" << num("%.3f", 100.0 * p.injected_share)
                << " %), particles mean " << num("%.0f", p.particles_mean) << ", max " << p.particles_max << "\n";
  }
  if (m.rmse_position_m >= 0.0)
    std::cout << "  once localized (" << num("%.1f", m.localized_time_s) << " s): position RMSE "
              << num("%.3f", m.rmse_position_m) << " m (max " << num("%.3f", m.max_position_error_m)
              << " m), heading RMSE " << num("%.2f", m.rmse_heading_deg) << " deg (max "
              << num("%.2f", m.max_heading_error_deg) << " deg); outside the bounds for "
              << num("%.2f", m.outside_bounds_s) << " s\n";
  const auto expected = r.stream.expected_counts();
  const auto observed = r.observed_counts();
  std::map<std::string, int> keys = expected;
  for (const auto& kv : observed) keys[kv.first] += 0;
  int injected = 0;
  for (const InjectedFault& f : r.stream.faults)
    if (f.key.rfind("event.", 0) != 0) ++injected;
  bool match = true;
  std::cout << "  faults: " << injected << " injected into the streams; rejects by counter (counted / injected):\n";
  for (const auto& kv : keys) {
    const int e = expected.count(kv.first) ? expected.at(kv.first) : 0;
    const int o = observed.count(kv.first) ? observed.at(kv.first) : 0;
    match = match && e == o;
    std::cout << "    " << kv.first << std::string(kv.first.size() < 34 ? 34 - kv.first.size() : 1, ' ') << o << " / "
              << e << (e == o ? "" : "   <-- MISMATCH") << "\n";
  }
  std::cout << "  every injected fault counted with its reason: " << (match ? "yes" : "NO") << "\n";
  std::cout << "  loop: " << r.loop.predictions << " predictions, " << r.loop.corrections << " corrections; outputs "
               "with stale inputs:";
  for (const est::loop::InputKindInfo& k : est::loop::kInputKinds)
    if (r.loop.of(k.kind).accepted > 0 || r.loop.of(k.kind).stale > 0) std::cout << " " << k.name << " " << r.loop.of(k.kind).stale;
  std::cout << "; worst step " << num("%.2f", static_cast<double>(r.loop.worst_step_ns) * 1e-6) << " ms, "
            << r.loop.overruns << " steps over their deadline (wall clock)\n";
  if (r.filter == est::loop::Filter::mcl)
    std::cout << "  mcl: " << r.mcl.resamplings << " resamplings drew " << r.mcl.drawn_particles << " particles, "
              << r.mcl.injected_particles << " of them injected\n";
  std::cout << "  outputs in " << out << "/\n";
}

// The live view of a run (--view PORT; team_robots > 0: a team's channels) with the world's map (if any), started
// once a viewer has subscribed with --view-wait; null without --view.
std::unique_ptr<view::LiveView> open_run_view(const RunOptions& o, int team_robots, const SimWorld* world) {
  if (o.view_port == 0) return nullptr;
  std::unique_ptr<view::LiveView> view = node::open_view(o.view_port, "sim_host", team_robots);
  if (world != nullptr && world->grid.valid()) view->set_map(node::view_map(world->grid));
  if (o.view_wait) {
    std::fprintf(stderr, "sim_host: waiting for a viewer to subscribe\n");
    node::wait_for_viewer(*view, [] { return false; });
  }
  return view;
}

// Sends what is queued, closes the view and says what it sent.
void close_run_view(view::LiveView* view) {
  if (view == nullptr) return;
  view->stop();
  std::fprintf(stderr, "sim_host: view: %s\n", node::view_counters_line(*view).c_str());
}

}  // namespace

void run_scenario(const ScenarioFile& f, const RunOptions& o) {
  switch (f.runner) {
    case ScenarioRunner::simulate: {
      const SimWorld world = load_world(f.scenario);
      const std::unique_ptr<view::LiveView> view = open_run_view(o, 0, &world);
      RunView watch;
      watch.view = view.get();
      watch.speed = o.view_speed;
      // A run longer than a few seconds shows its simulated time on a terminal.
      Progress progress("simulate", f.scenario.duration_s, o.quiet, Progress::Unit::simulated_s, 2.0);
      const SimResult r = run_simulation(f.scenario, f.filter, world, &progress, view ? &watch : nullptr);
      progress.finish();
      close_run_view(view.get());
      write_simulation_outputs(r, f.scenario, f.filter, world, o.out, o.plots);
      // The run as one LCM log: its inputs, the ground truth and the estimates, with the sidecar that says how to
      // replay it (estimator_node --replay gives the same estimates).
      const std::string log = (std::filesystem::path(o.out) / "run.lcmlog").string();
      const RecordSummary logged = record_lcm_log(r.stream, log, &r.estimates);
      std::ofstream(log + ".json") << record_sidecar_json(r.stream, f.scenario, world, logged, log, &f.filter);
      print_summary(r, f.scenario, world, o.out);
      std::cout << "  log: " << log << " (inputs, ground truth, estimates on EST_POSE; replay: " << log
                << ".json's estimator_node_options)\n";
      if (!o.live_lcm_url.empty()) {
        std::cout.flush();
        LiveOptions live = o.live;
        live.lcm_url = o.live_lcm_url;
        const LiveResult lr = run_live_robot(r, f.scenario, f.filter, o.out, live);
        if (lr.node_exit != 0) throw std::runtime_error("--live: estimator_node exited with status " +
                                                        std::to_string(lr.node_exit));
      }
      return;
    }
    case ScenarioRunner::team: {
      team::TeamRunOptions t;
      t.scenario = f.team;
      t.out = o.out;
      t.seed = f.scenario.seed;
      t.duration_s = f.team_duration_s;
      t.plots = o.plots;
      t.quiet = o.quiet;
      if (!o.live_lcm_url.empty() && f.team == "diffdrive-landmarks")
        throw std::invalid_argument("--live: no node runs the anonymous team of diffdrive-landmarks");
      const std::unique_ptr<view::LiveView> view = open_run_view(o, team::team_scenario(f.team).robots, nullptr);
      t.view = view.get();
      t.view_speed = o.view_speed;
      team::run_team_scenario(t);
      close_run_view(view.get());
      if (!o.live_lcm_url.empty()) {
        std::cout.flush();
        LiveOptions live = o.live;
        live.lcm_url = o.live_lcm_url;
        const LiveResult lr = run_live_team(o.out, live);
        if (lr.node_exit != 0) throw std::runtime_error("--live: a team node exited with status " +
                                                        std::to_string(lr.node_exit));
      }
      return;
    }
    case ScenarioRunner::exercise: {
      if (o.view_port != 0) throw std::invalid_argument("--view: an exercise draws samples, it has no live view");
      if (!o.live_lcm_url.empty()) throw std::invalid_argument("--live: an exercise draws samples, no node runs it");
      const std::vector<MotionCloud> clouds = bicycle_exercise(f.exercise_seed, f.exercise_samples);
      for (const MotionCloud& c : clouds) {
        write_cloud(c, o.out);
        std::cout << f.exercise << " " << c.name << ": " << c.samples.size() << " samples -> " << o.out << "/"
                  << c.name << ".csv, " << c.name << ".png  (" << c.title << ")\n";
        if (!c.note.empty()) std::cout << f.exercise << " " << c.name << ": " << c.note << "\n";
      }
      return;
    }
  }
}

}  // namespace sim
