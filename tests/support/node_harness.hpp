#pragma once
// Helpers for the tests that run estimator_node as a process (tests/test_estimator_node.cpp, the VM test
// tests/test_estimator_hil.cpp, tests/test_stamp_alignment.cpp): starting and stopping one, running a command with its output captured, reading the node's summary, and
// reading and comparing the estimates in LCM logs. Host only.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <est_lcm/pose_estimate_t.hpp>

#include "hal/status_word.hpp"
#include "sim_host/node/node_summary.hpp"

namespace est::test {

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Starts `cmd` through sh (exec'd, so the pid is the command's) without waiting for it.
inline pid_t spawn(const std::string& cmd) {
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", ("exec " + cmd).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

// Sends `sig` to a spawned process and reaps it; its exit status (-1: killed by a signal).
inline int stop(pid_t pid, int sig) {
  kill(pid, sig);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Whether `text` appears in `file` within `seconds` (polled every 20 ms).
inline bool wait_for_text(const std::string& file, const std::string& text, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (read_text(file).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// Runs `cmd` through sh with stdout and stderr into `output_path`; returns the exit status (-1: killed).
inline int run_command(const std::string& cmd, const std::string& output_path) {
  const int rc = std::system((cmd + " >" + output_path + " 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

using ::node::summary_value;  // node/node_summary.hpp

// The pose estimates of an LCM log, in order.
inline std::vector<est_lcm::pose_estimate_t> read_estimates(const std::string& path,
                                                             const std::string& channel = "EST_POSE") {
  std::vector<est_lcm::pose_estimate_t> out;
  ::lcm::LogFile log(path, "r");
  if (!log.good()) return out;
  while (const ::lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel != channel) continue;
    est_lcm::pose_estimate_t m;
    if (m.decode(e->data, 0, e->datalen) == e->datalen) out.push_back(m);
  }
  return out;
}

// The bits a replay must reproduce: the loop's own, without the deadline overrun (the wall clock's) and without
// input-rejected (which also counts transport rejects that a recorded input stream no longer carries).
inline std::uint32_t replayable_status(std::int32_t status) {
  return static_cast<std::uint32_t>(status) & hal::status::kLoopMask &
         ~(hal::status::kDeadlineOverrun | hal::status::kInputRejected);
}

// Stamp, pose, covariance and the replayable status bits, bit for bit.
inline bool same_estimate(const est_lcm::pose_estimate_t& a, const est_lcm::pose_estimate_t& b) {
  return a.stamp_ns == b.stamp_ns && std::memcmp(&a.x_m, &b.x_m, sizeof(float)) == 0 &&
         std::memcmp(&a.y_m, &b.y_m, sizeof(float)) == 0 &&
         std::memcmp(&a.theta_rad, &b.theta_rad, sizeof(float)) == 0 &&
         std::memcmp(a.covariance, b.covariance, sizeof(a.covariance)) == 0 &&
         replayable_status(a.status) == replayable_status(b.status);
}

// Index of the first estimate that differs, or -1 when both sequences are the same (lengths included).
inline long first_difference(const std::vector<est_lcm::pose_estimate_t>& a,
                             const std::vector<est_lcm::pose_estimate_t>& b) {
  const std::size_t n = a.size() < b.size() ? a.size() : b.size();
  for (std::size_t i = 0; i < n; ++i)
    if (!same_estimate(a[i], b[i])) return static_cast<long>(i);
  return a.size() == b.size() ? -1 : static_cast<long>(n);
}

// Whether LCM udpm on `url` delivers here: an instance hears its own messages through multicast loopback.
inline bool udpm_works(const std::string& url) {
  ::lcm::LCM lcm(url);
  if (!lcm.good()) return false;
  struct Heard {
    bool any = false;
    void on(const ::lcm::ReceiveBuffer*, const std::string&) { any = true; }
  } heard;
  lcm.subscribe("EST_UDPM_PROBE", &Heard::on, &heard);
  const char probe[] = "probe";
  for (int i = 0; i < 20 && !heard.any; ++i) {
    lcm.publish("EST_UDPM_PROBE", probe, sizeof probe);
    lcm.handleTimeout(100);
  }
  return heard.any;
}

// A udpm URL on a port of this process's own (tests running side by side do not hear each other), or exit 77 (ctest's
// SKIP) with the reason when multicast does not work here.
inline std::string udpm_url_or_skip() {
  const std::string url = "udpm://239.255.76.67:" + std::to_string(20000 + getpid() % 20000) + "?ttl=0";
  if (!udpm_works(url)) {
    std::fprintf(stderr, "SKIP: LCM udpm multicast does not work here (%s)\n", url.c_str());
    std::fflush(stderr);
    std::_Exit(77);
  }
  return url;
}

inline double wrap_angle(double a) { return std::remainder(a, 2.0 * 3.14159265358979323846); }

}  // namespace est::test
