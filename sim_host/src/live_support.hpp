#pragma once
// What the live runs share (live_run.cpp over LCM, live_run_can.cpp over CAN): the node processes, the collector
// of their estimates, the pairing with the lockstep run's and the printing. Internal to sim_host's live runs.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/pose_estimate_t.hpp>

#include "hal/lcm/lcm_convert.hpp"
#include "node/lcm_log_io.hpp"
#include "node/node_summary.hpp"
#include "node/pacer.hpp"
#include "sim/live_run.hpp"

namespace sim::live {

using node::summary_value;

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

inline std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// An executable beside this sim_host (or `given` when set).
inline std::string beside_exe(const std::string& given, const std::string& name) {
  if (!given.empty()) return given;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  const fs::path beside = self.parent_path() / name;
  if (ec || !fs::exists(beside)) throw std::runtime_error("--live: no " + name + " beside sim_host (" + beside.string() + ")");
  return beside.string();
}

// The sidecar's node options with `extra` (--node-args) in place of the options of the same names: "--name value..."
// groups, a group being an option and the words after it up to the next "--" option.
inline std::string with_node_args(const std::string& options, const std::string& extra) {
  const auto groups = [](const std::string& text) {
    std::vector<std::pair<std::string, std::string>> out;  // name, the whole group
    std::istringstream in(text);
    std::string w;
    while (in >> w) {
      if (w.compare(0, 2, "--") == 0 || out.empty()) out.push_back({w, w});
      else out.back().second += " " + w;
    }
    return out;
  };
  const auto more = groups(extra);
  std::string r;
  for (const auto& g : groups(options)) {
    bool replaced = false;
    for (const auto& m : more) replaced = replaced || m.first == g.first;
    if (!replaced) r += " " + g.second;
  }
  for (const auto& m : more) r += " " + m.second;
  return r;
}

// The node's options of a lockstep run (its sidecar's, which start with `--replay LOG`) less the replay, with
// --node-args in place of the options of the same names.
inline std::string live_node_options(const nlohmann::json& sidecar, const std::string& log, const LiveOptions& o) {
  const std::string options = sidecar.at("estimator_node_options").get<std::string>();
  const std::string replay = "--replay " + log;
  if (options.compare(0, replay.size(), replay) != 0) throw std::runtime_error("--live: the sidecar is not this run's");
  return with_node_args(options.substr(replay.size()), o.node_args);
}

inline std::string node_exe(const LiveOptions& o) { return beside_exe(o.node_exe, "estimator_node"); }

// One estimator_node process (or another command), its stdout and stderr in `log`.
class NodeProcess {
 public:
  NodeProcess(const std::string& cmd, fs::path log) : log_(std::move(log)) {
    pid_ = fork();
    if (pid_ == 0) {
      execl("/bin/sh", "sh", "-c", ("exec " + cmd + " >'" + log_.string() + "' 2>&1").c_str(),
            static_cast<char*>(nullptr));
      _exit(127);
    }
    if (pid_ < 0) throw std::runtime_error("--live: cannot start estimator_node");
  }
  ~NodeProcess() {
    if (pid_ > 0) stop();
  }
  NodeProcess(const NodeProcess&) = delete;
  NodeProcess& operator=(const NodeProcess&) = delete;

  // Whether the node said `text` within `seconds` (false at once when it exited).
  bool wait_for(const std::string& text, double seconds) {
    const auto end = Clock::now() + std::chrono::duration<double>(seconds);
    while (Clock::now() < end) {
      if (read_text(log_).find(text) != std::string::npos) return true;
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exit_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        pid_ = -1;
        return false;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  // SIGINT (the node's summary and a clean exit), SIGKILL after 10 s; the exit status (-1: killed by a signal).
  int stop() {
    if (pid_ <= 0) return exit_;
    kill(pid_, SIGINT);
    return wait(10.0);
  }
  // Waits for it to exit on its own (SIGKILL after `seconds`); the exit status (-1: killed by a signal).
  int wait(double seconds) {
    if (pid_ <= 0) return exit_;
    int status = 0;
    const auto end = Clock::now() + std::chrono::duration<double>(seconds);
    while (waitpid(pid_, &status, WNOHANG) == 0) {
      if (Clock::now() > end) {
        kill(pid_, SIGKILL);
        waitpid(pid_, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    pid_ = -1;
    exit_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return exit_;
  }
  const fs::path& log() const { return log_; }

 private:
  fs::path log_;
  pid_t pid_ = -1;
  int exit_ = -1;
};

// The estimates the nodes publish (EST_POSE, EST_POSE_<a>), heard on a thread of their own while the streams play.
class Collector {
 public:
  explicit Collector(const std::string& url) : lcm_(url) {
    if (!lcm_.good()) throw std::runtime_error("--live: LCM could not start on '" + url + "'");
    lcm_.subscribe("EST_POSE(_[0-9]+)?", &Collector::on, this);
    thread_ = std::thread([this] {
      while (!done_) lcm_.handleTimeout(50);
    });
  }
  ~Collector() { finish(); }
  void finish() {
    done_ = true;
    if (thread_.joinable()) thread_.join();
  }
  // The latest stamp of an estimate heard so far (any channel; INT64_MIN before the first), while it runs.
  std::int64_t latest_stamp_ns() const { return latest_; }
  // How many estimates it heard so far, while it runs.
  std::size_t heard() const { return heard_; }
  // By channel, in the order heard (after finish()).
  const std::map<std::string, std::vector<est_lcm::pose_estimate_t>>& estimates() const { return by_channel_; }

 private:
  void on(const ::lcm::ReceiveBuffer* b, const std::string& channel) {
    est_lcm::pose_estimate_t m;
    const int n = static_cast<int>(b->data_size);
    if (m.decode(b->data, 0, n) != n) return;
    const std::int64_t stamp = m.stamp_ns;  // read before the push (GCC 12 at -O2 sees a dangling m after it)
    by_channel_[channel].push_back(m);
    if (stamp > latest_) latest_ = stamp;
    ++heard_;
  }
  ::lcm::LCM lcm_;
  std::atomic<bool> done_{false};
  std::atomic<std::int64_t> latest_{INT64_MIN};
  std::atomic<std::size_t> heard_{0};
  std::thread thread_;
  std::map<std::string, std::vector<est_lcm::pose_estimate_t>> by_channel_;
};

// The log's events on the channels `play` takes, published on `url` at their times (real time), by channel.
template <typename Play>
inline std::map<std::string, std::size_t> play_log(const std::string& log_path, const std::string& url, Play play) {
  ::lcm::LogFile log(log_path, "r");
  if (!log.good()) throw std::runtime_error("--live: cannot read " + log_path);
  ::lcm::LCM lcm(url);
  if (!lcm.good()) throw std::runtime_error("--live: LCM could not start on '" + url + "'");
  node::Pacer pacer(1.0);
  std::map<std::string, std::size_t> published;
  while (const ::lcm::LogEvent* e = log.readNextEvent()) {
    if (!play(e->channel)) continue;
    pacer.at(e->timestamp * 1000);
    if (lcm.publish(e->channel, e->data, static_cast<unsigned>(e->datalen)) == 0) ++published[e->channel];
  }
  return published;
}

// The published estimates as a log (event times their stamps), for sim_host plot beside the run's log.
inline void write_estimates(const fs::path& path, const std::map<std::string, std::vector<est_lcm::pose_estimate_t>>& by) {
  node::LogWriter w(path.string());
  for (const auto& [channel, list] : by)
    for (const est_lcm::pose_estimate_t& m : list) w.write(channel, m.stamp_ns, m);
}

inline bool same_bits(const est_lcm::pose_estimate_t& a, const est_lcm::pose_estimate_t& b) {
  return a.stamp_ns == b.stamp_ns && std::memcmp(&a.x_m, &b.x_m, sizeof(float)) == 0 &&
         std::memcmp(&a.y_m, &b.y_m, sizeof(float)) == 0 &&
         std::memcmp(&a.theta_rad, &b.theta_rad, sizeof(float)) == 0 &&
         std::memcmp(a.covariance, b.covariance, sizeof(a.covariance)) == 0;
}

// Live estimates paired with the lockstep's of the same stamp (the k-th of a stamp with the k-th: a scan applied
// right after a prediction gives two outputs at one time).
struct Pairing {
  std::size_t matched = 0, identical = 0;
  double worst_m = 0.0, worst_rad = 0.0;
};
inline Pairing pair_by_stamp(const std::vector<est_lcm::pose_estimate_t>& lockstep,
                      const std::vector<est_lcm::pose_estimate_t>& live) {
  std::map<std::int64_t, std::vector<const est_lcm::pose_estimate_t*>> by;
  for (const est_lcm::pose_estimate_t& e : lockstep) by[e.stamp_ns].push_back(&e);
  std::map<std::int64_t, std::size_t> used;
  Pairing p;
  for (const est_lcm::pose_estimate_t& l : live) {
    const auto it = by.find(l.stamp_ns);
    if (it == by.end()) continue;
    std::size_t& k = used[l.stamp_ns];
    if (k >= it->second.size()) continue;
    const est_lcm::pose_estimate_t& r = *it->second[k++];
    ++p.matched;
    if (same_bits(l, r)) ++p.identical;
    p.worst_m = std::max(p.worst_m, std::hypot(static_cast<double>(l.x_m - r.x_m), static_cast<double>(l.y_m - r.y_m)));
    p.worst_rad = std::max(p.worst_rad, std::fabs(std::remainder(static_cast<double>(l.theta_rad - r.theta_rad),
                                                                 6.283185307179586)));
  }
  return p;
}

inline std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

inline void row(const std::string& what, const std::string& lockstep, const std::string& live) {
  std::printf("  %-38s %14s %14s\n", what.c_str(), lockstep.c_str(), live.c_str());
}

inline std::string metric(double v, const char* f, const char* unit) { return v < 0.0 ? "-" : fmt(f, v) + unit; }

// The rows of the metrics both live runs print beside the lockstep run's (km lockstep, lm live).
inline void metric_rows(const SimMetrics& km, const SimMetrics& lm, long long lockstep_rejects, long long rejected) {
  for (std::size_t i = 0; i < km.phases.size() && i < lm.phases.size(); ++i)
    row(km.phases[i].name + ": localized after", metric(km.phases[i].time_to_localize_s, "%.2f", " s"),
        metric(lm.phases[i].time_to_localize_s, "%.2f", " s"));
  row("position RMSE once localized", metric(km.rmse_position_m, "%.3f", " m"), metric(lm.rmse_position_m, "%.3f", " m"));
  row("max position error once localized", metric(km.max_position_error_m, "%.3f", " m"),
      metric(lm.max_position_error_m, "%.3f", " m"));
  row("heading RMSE once localized", metric(km.rmse_heading_deg, "%.2f", " deg"),
      metric(lm.rmse_heading_deg, "%.2f", " deg"));
  row("position RMSE over every estimate", metric(km.rmse_position_all_m, "%.3f", " m"),
      metric(lm.rmse_position_all_m, "%.3f", " m"));
  row("inputs rejected (counted)", std::to_string(lockstep_rejects), std::to_string(rejected));
}

inline nlohmann::json metrics_of(const SimMetrics& m, std::size_t estimates) {
  nlohmann::json j;
  j["estimates"] = estimates;
  j["rmse_position_m"] = m.rmse_position_m;
  j["max_position_error_m"] = m.max_position_error_m;
  j["rmse_heading_deg"] = m.rmse_heading_deg;
  j["rmse_position_all_m"] = m.rmse_position_all_m;
  j["localized_time_s"] = m.localized_time_s;
  j["phases"] = nlohmann::json::array();
  for (const PhaseMetrics& p : m.phases)
    j["phases"].push_back({{"name", p.name}, {"localized", p.localized}, {"time_to_localize_s", p.time_to_localize_s}});
  return j;
}

}  // namespace sim::live
