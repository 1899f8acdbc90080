// `sim_host run --live` (sim/live_run.hpp): the run's streams in real time to estimator_node processes over LCM.
#include "sim/live_run.hpp"

#include "live_support.hpp"

namespace sim {
using namespace live;

LiveResult run_live_robot(const SimResult& lockstep, const ScenarioConfig& sc, const FilterOptions& fo,
                          const std::string& out, const LiveOptions& o) {
  if (!o.can_interface.empty()) return run_live_robot_can(lockstep, sc, fo, out, o);
  const fs::path dir = fs::path(out) / "live";
  fs::create_directories(dir);
  const std::string log = (fs::path(out) / "run.lcmlog").string();
  const nlohmann::json sidecar = nlohmann::json::parse(read_text(log + ".json"));
  const std::string options = live_node_options(sidecar, log, o);

  std::printf("live: the run again in real time (%.1f s): estimator_node on LCM %s\n", sc.duration_s,
              o.lcm_url.c_str());
  std::fflush(stdout);
  LiveResult result;
  NodeProcess node(node_exe(o) + " --lcm '" + o.lcm_url + "'" + options, dir / "node.txt");
  if (!node.wait_for("estimator_node: running", o.start_timeout_s))
    throw std::runtime_error("--live: estimator_node did not start: " + read_text(dir / "node.txt"));
  Collector heard(o.lcm_url);
  const auto t0 = Clock::now();
  const std::map<std::string, std::size_t> published = play_log(
      log, o.lcm_url, [](const std::string& ch) { return ch != "EST_POSE" && ch != "EST_GROUND_TRUTH"; });
  const double played_s = std::chrono::duration<double>(Clock::now() - t0).count();
  std::this_thread::sleep_for(std::chrono::duration<double>(o.drain_s));
  result.node_exit = node.stop();
  heard.finish();
  const std::string summary = read_text(dir / "node.txt");

  const auto found = heard.estimates().find("EST_POSE");
  const std::vector<est_lcm::pose_estimate_t> live =
      found != heard.estimates().end() ? found->second : std::vector<est_lcm::pose_estimate_t>{};
  write_estimates(dir / "live.lcmlog", heard.estimates());
  std::vector<OutputRow> rows;
  for (const est_lcm::pose_estimate_t& m : live) rows.push_back(output_row(lockstep.stream, hal::lcm::to_hal(m)));
  std::stable_sort(rows.begin(), rows.end(), [](const OutputRow& a, const OutputRow& b) { return a.t_ns < b.t_ns; });
  const SimMetrics lm = compute_metrics(lockstep.stream, rows, fo);
  std::vector<est_lcm::pose_estimate_t> ref;
  for (const hal::Estimate& e : lockstep.estimates) ref.push_back(hal::lcm::to_lcm(e));
  const Pairing p = pair_by_stamp(ref, live);

  for (const auto& kv : published) result.inputs_published += kv.second;
  result.estimates = live.size();
  result.matched = p.matched;
  result.identical = p.identical;
  const long long accepted = summary_value(summary, "  rejects.lcm:", "accepted");
  const long long rejected = summary_value(summary, "  rejects:", "total");
  result.inputs_all_accounted = accepted == static_cast<long long>(result.inputs_published);
  int lockstep_rejects = 0;
  for (const auto& kv : lockstep.observed_counts()) lockstep_rejects += kv.second;

  const SimMetrics& km = lockstep.metrics;
  std::printf("live against lockstep (%s, %.1f s of inputs played in %.1f s):\n", lockstep.description.c_str(),
              sc.duration_s, played_s);
  row("", "lockstep", "live");
  row("estimates", std::to_string(lockstep.estimates.size()), std::to_string(live.size()));
  metric_rows(km, lm, lockstep_rejects, rejected);
  std::printf("  live estimates paired with the lockstep's by stamp: %zu of %zu, %zu identical to the bit; worst "
              "difference %.4f m, %.4f rad\n",
              p.matched, lockstep.estimates.size(), p.identical, p.worst_m, p.worst_rad);
  std::printf("  inputs: %zu published on LCM, %lld taken by the node's LCM input (%s)\n", result.inputs_published,
              accepted, result.inputs_all_accounted ? "every one" : "SOME LOST");
  std::printf("  estimator_node: exit status %d; its summary in %s, its estimates in %s\n", result.node_exit,
              (dir / "node.txt").string().c_str(), (dir / "live.lcmlog").string().c_str());

  nlohmann::json j;
  j["lcm_url"] = o.lcm_url;
  j["played_s"] = played_s;
  j["lockstep"] = metrics_of(km, lockstep.estimates.size());
  j["lockstep"]["inputs_rejected"] = lockstep_rejects;
  j["live"] = metrics_of(lm, live.size());
  j["live"]["inputs_rejected"] = rejected;
  j["paired"] = {{"matched", p.matched}, {"identical", p.identical}, {"worst_position_m", p.worst_m},
                 {"worst_heading_rad", p.worst_rad}};
  j["inputs"] = {{"published", result.inputs_published}, {"accepted_by_lcm_input", accepted},
                 {"all_accounted", result.inputs_all_accounted}};
  j["nodes"] = nlohmann::json::array({{{"exit_status", result.node_exit}, {"summary", (dir / "node.txt").string()}}});
  std::ofstream(dir / "live.json") << j.dump(2) << "\n";
  return result;
}

LiveResult run_live_team(const std::string& out, const LiveOptions& o) {
  const fs::path dir = fs::path(out) / "live";
  fs::create_directories(dir);
  const std::string log = (fs::path(out) / "run.lcmlog").string();
  const nlohmann::json sidecar = nlohmann::json::parse(read_text(log + ".json"));
  if (!sidecar.contains("team_node_options"))
    throw std::invalid_argument("--live: no node runs this team (" + sidecar.value("scenario", std::string()) + ")");
  if (!o.can_interface.empty())
    throw std::invalid_argument("--live --can: a team's messages have no CAN frames (estimator.dbc): use --lcm alone");
  const std::string options = with_node_args(sidecar.at("team_node_options").get<std::string>(), o.node_args);
  const int robots = sidecar.at("robots").get<int>();

  // The lockstep run's truth and estimates, from its log.
  std::map<std::string, std::vector<est_lcm::pose_estimate_t>> lockstep;
  std::vector<std::map<std::int64_t, est_lcm::ground_truth_t>> truth(static_cast<std::size_t>(robots));
  {
    ::lcm::LogFile in(log, "r");
    while (const ::lcm::LogEvent* e = in.readNextEvent()) {
      if (e->channel.rfind("EST_POSE_", 0) == 0) {
        est_lcm::pose_estimate_t m;
        if (m.decode(e->data, 0, e->datalen) == e->datalen) lockstep[e->channel].push_back(m);
      } else if (e->channel.rfind("EST_GROUND_TRUTH_", 0) == 0) {
        est_lcm::ground_truth_t g;
        const int a = std::atoi(e->channel.c_str() + 17);
        if (g.decode(e->data, 0, e->datalen) == e->datalen && a >= 0 && a < robots)
          truth[static_cast<std::size_t>(a)][g.stamp_ns] = g;
      }
    }
  }

  std::printf("live: the team run again in real time: %d team nodes on LCM %s\n", robots, o.lcm_url.c_str());
  std::fflush(stdout);
  LiveResult result;
  const std::string exe = node_exe(o);
  std::vector<std::unique_ptr<NodeProcess>> nodes;
  for (int a = 0; a < robots; ++a) {
    const std::string s = std::to_string(a);
    nodes.push_back(std::make_unique<NodeProcess>(
        exe + " " + options + " --robot-id " + s + " --lcm '" + o.lcm_url + "' --team-out '" +
            (dir / ("team_" + s + ".csv")).string() + "' --team-counts '" + (dir / ("counts_" + s + ".txt")).string() +
            "'",
        dir / ("node_" + s + ".txt")));
  }
  for (const auto& n : nodes)
    if (!n->wait_for("running", o.start_timeout_s))
      throw std::runtime_error("--live: a team node did not start: " + read_text(n->log()));
  Collector heard(o.lcm_url);
  const auto t0 = Clock::now();
  const std::map<std::string, std::size_t> published =
      play_log(log, o.lcm_url, [](const std::string& ch) { return ch.rfind("EST_TEAM_OWN_", 0) == 0; });
  const double played_s = std::chrono::duration<double>(Clock::now() - t0).count();
  std::this_thread::sleep_for(std::chrono::duration<double>(o.drain_s));
  result.node_exit = 0;
  for (const auto& n : nodes) {
    const int rc = n->stop();
    if (rc != 0) result.node_exit = rc;
  }
  heard.finish();
  write_estimates(dir / "live.lcmlog", heard.estimates());

  const std::string expected_lines = read_text(fs::path(out) / "team_estimates.csv");
  nlohmann::json j;
  j["lcm_url"] = o.lcm_url;
  j["played_s"] = played_s;
  j["robots"] = nlohmann::json::array();
  std::printf("live against lockstep (%d steps played in %.1f s), per robot: estimates and position RMSE lockstep / "
              "live, paired by stamp (identical), the node's team lines against the run's:\n",
              sidecar.at("steps").get<int>(), played_s);
  bool all_in = true;
  for (int a = 0; a < robots; ++a) {
    const std::string ch = "EST_POSE_" + std::to_string(a);
    const auto f = heard.estimates().find(ch);
    const std::vector<est_lcm::pose_estimate_t> live =
        f != heard.estimates().end() ? f->second : std::vector<est_lcm::pose_estimate_t>{};
    const auto rmse = [&](const std::vector<est_lcm::pose_estimate_t>& v) {
      double se = 0.0;
      std::size_t n = 0;
      for (const est_lcm::pose_estimate_t& m : v) {
        const auto t = truth[static_cast<std::size_t>(a)].find(m.stamp_ns);
        if (t == truth[static_cast<std::size_t>(a)].end()) continue;
        se += std::pow(std::hypot(static_cast<double>(m.x_m - t->second.x_m), static_cast<double>(m.y_m - t->second.y_m)), 2);
        ++n;
      }
      return n > 0 ? std::sqrt(se / static_cast<double>(n)) : -1.0;
    };
    const Pairing p = pair_by_stamp(lockstep[ch], live);
    // The node's team lines against the run's (node 0's; every node of the team holds the same estimate).
    const std::string lines = read_text(dir / ("team_" + std::to_string(a) + ".csv"));
    const bool same_lines = lines == expected_lines;
    const std::string counts = read_text(dir / ("counts_" + std::to_string(a) + ".txt"));
    long long own = -1;
    {
      std::istringstream in(counts);
      std::string k;
      long long v = 0;
      while (in >> k >> v)
        if (k == "own_received") own = v;
    }
    const std::size_t sent = published.count("EST_TEAM_OWN_" + std::to_string(a))
                                 ? published.at("EST_TEAM_OWN_" + std::to_string(a))
                                 : 0;
    all_in = all_in && own == static_cast<long long>(sent);
    result.inputs_published += sent;
    result.estimates += live.size();
    result.matched += p.matched;
    result.identical += p.identical;
    std::printf("  robot %d: %zu / %zu estimates, RMSE %.3f / %.3f m, paired %zu (%zu identical), worst %.4f m; "
                "team lines %s; own messages %zu sent, %lld received\n",
                a, lockstep[ch].size(), live.size(), rmse(lockstep[ch]), rmse(live), p.matched, p.identical,
                p.worst_m, same_lines ? "identical" : "DIFFER", sent, own);
    j["robots"].push_back({{"robot", a},
                           {"estimates_lockstep", lockstep[ch].size()},
                           {"estimates_live", live.size()},
                           {"rmse_lockstep_m", rmse(lockstep[ch])},
                           {"rmse_live_m", rmse(live)},
                           {"paired", p.matched},
                           {"identical", p.identical},
                           {"worst_position_m", p.worst_m},
                           {"team_lines_identical", same_lines},
                           {"own_sent", sent},
                           {"own_received", own},
                           {"exit_status", nodes[static_cast<std::size_t>(a)]->stop()},
                           {"summary", nodes[static_cast<std::size_t>(a)]->log().string()}});
  }
  result.inputs_all_accounted = all_in;
  std::printf("  every own message reached its node: %s; nodes' exit status %d; summaries in %s/node_<a>.txt\n",
              all_in ? "yes" : "NO", result.node_exit, dir.string().c_str());
  std::ofstream(dir / "live.json") << j.dump(2) << "\n";
  return result;
}

}  // namespace sim
