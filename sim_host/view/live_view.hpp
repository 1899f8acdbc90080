#pragma once
// The live view: a server on 127.0.0.1:PORT (websocketpp, one thread of its own) that speaks the Foxglove WebSocket
// protocol (view/foxglove_json.hpp says the channels), so Foxglove Studio connects to ws://localhost:PORT, and
// serves the project's own page (view/page/index.html, built in) at http://localhost:PORT/, which draws the same
// channels over the same protocol. Any host program feeds it: the map once, then estimates, the ground truth and
// particle clouds as they come (host only).
//
// The producer never waits: estimates and truths go through a bounded single-producer ring and particle clouds
// through a triple buffer (the newest wins); a full ring drops and counts, and a client whose socket has more than
// kMaxBufferedBytes unsent is skipped and counted. Particles are taken at most every kParticlePeriod of wall time
// (particles_due()), so a replay at full speed does not copy clouds it cannot show.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "view/foxglove_json.hpp"

namespace view {

inline constexpr std::size_t kMaxCloudPoses = 2000;              // particles sent per cloud (decimated)
inline constexpr std::size_t kMaxViewLandmarks = 256;            // landmarks sent per set
inline constexpr std::size_t kMaxBufferedBytes = 4u << 20;       // per client, before its messages are dropped
inline constexpr std::chrono::milliseconds kParticlePeriod{100};  // ~10 Hz

struct ViewCounters {
  std::uint64_t clients = 0;          // connected over the run (WebSocket)
  std::uint64_t pages = 0;            // page requests served (HTTP)
  std::uint64_t messages_sent = 0;    // message data frames
  std::uint64_t dropped_handoff = 0;  // estimates and truths the server had no room for; clouds overwritten unsent
  std::uint64_t dropped_slow = 0;     // frames not sent to a client that was behind
};

class LiveView {
 public:
  // Listens on 127.0.0.1:port and starts the server thread; throws std::runtime_error with one line on failure.
  // team_robots > 0: a team's channels (view/foxglove_json.hpp) instead of one robot's.
  LiveView(std::uint16_t port, const std::string& name, int team_robots = 0);
  ~LiveView();  // stop()
  // Sends what is queued, closes the connections and joins the thread (at most ~3 s); idempotent.
  void stop();
  LiveView(const LiveView&) = delete;
  LiveView& operator=(const LiveView&) = delete;

  // The map, once (before or after start); sent to each subscriber of /map.
  void set_map(const MapGrid& map);
  // Never block; what does not fit is dropped and counted.
  void publish_estimate(const EstimateSample& e);
  void publish_truth(TimeNs stamp_ns, const Pose& p);
  bool particles_due();  // whether a cloud is wanted now (rate limit, and someone subscribed)
  // Every stride-th particle, at most kMaxCloudPoses of them.
  void publish_particles(TimeNs stamp_ns, const float* x, const float* y, const float* theta, std::uint32_t count);

  // A team's view: robot a's estimate (its status too, with_status: the node's own robot) and truth, and the
  // mapped landmarks (landmarks_due(): at the particles' rate, when someone subscribed; the newest set wins).
  void publish_team_estimate(int robot, const EstimateSample& e, bool with_status);
  void publish_team_truth(int robot, TimeNs stamp_ns, const Pose& p);
  bool landmarks_due();
  void publish_landmarks(TimeNs stamp_ns, const LandmarkSample* landmarks, std::size_t count);

  std::uint32_t subscribers() const;  // clients subscribed to any channel now
  ViewCounters counters() const;
  std::uint16_t port() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::chrono::steady_clock::time_point next_cloud_{}, next_landmarks_{};
};

}  // namespace view
