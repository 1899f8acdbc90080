#pragma once
// Pacing for a watched run: holds each event until its time, scaled by 1 / speed, has passed on the wall clock since
// the first event (speed <= 0: no pacing). estimator_node's replay (the log's receive times) and sim_host run's
// stream (the arrival times) share it. Host only.
#include <chrono>
#include <cstdint>
#include <thread>

namespace node {

class Pacer {
 public:
  explicit Pacer(double speed) : speed_(speed) {}
  void at(std::int64_t t_ns) {
    if (speed_ <= 0.0) return;
    const auto now = std::chrono::steady_clock::now();
    if (!started_) {
      started_ = true;
      first_ns_ = t_ns;
      wall_start_ = now;
      return;
    }
    const auto due = wall_start_ + std::chrono::nanoseconds(
                                       static_cast<std::int64_t>(static_cast<double>(t_ns - first_ns_) / speed_));
    if (due > now) std::this_thread::sleep_until(due);
  }

 private:
  double speed_;
  bool started_ = false;
  std::int64_t first_ns_ = 0;
  std::chrono::steady_clock::time_point wall_start_;
};

}  // namespace node
