// A live view fed from an estimator pipeline (node/view_feed.hpp).
#include "node/view_feed.hpp"

#include <CLI/CLI.hpp>
#include <array>
#include <chrono>
#include <cstdio>
#include <thread>

namespace node {

void add_view_options(CLI::App& app, std::uint16_t& port, bool& wait, double& speed, const std::string& what) {
  const char* view = "Live view";
  app.add_option("--view", port,
                 "serve a live view on 127.0.0.1:PORT (0: off): the Foxglove WebSocket protocol (connect Foxglove "
                 "Studio to ws://localhost:PORT: " + what + ") and a page drawing the same at http://localhost:PORT/")
      ->capture_default_str()->group(view);
  app.add_flag("--view-wait", wait, "replay: start once a viewer has subscribed (needs --view)")->group(view);
  app.add_option("--replay-speed", speed,
                 "replay pacing by the log's receive times: 0 as fast as possible, 1 real time, 2 twice as fast "
                 "(outputs unchanged, bit for bit); default 0, or 1 with --view")
      ->check(CLI::NonNegativeNumber)->group(view);
}

void wait_for_viewer(const view::LiveView& v, bool (*stopped)()) {
  while (v.subscribers() == 0 && !stopped()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

std::unique_ptr<view::LiveView> open_view(std::uint16_t port, const std::string& program, int team_robots) {
  auto v = std::make_unique<view::LiveView>(port, program.substr(0, program.find(' ')), team_robots);
  std::fprintf(stderr, "%s: live view on http://localhost:%u/ (Foxglove: ws://localhost:%u)\n", program.c_str(),
               unsigned{v->port()}, unsigned{v->port()});
  return v;
}

std::string view_counters_line(const view::LiveView& v) {
  const view::ViewCounters c = v.counters();
  char b[256];
  std::snprintf(b, sizeof b, "port=%u clients=%llu pages=%llu sent=%llu dropped_handoff=%llu dropped_slow=%llu",
                unsigned{v.port()}, static_cast<unsigned long long>(c.clients),
                static_cast<unsigned long long>(c.pages), static_cast<unsigned long long>(c.messages_sent),
                static_cast<unsigned long long>(c.dropped_handoff), static_cast<unsigned long long>(c.dropped_slow));
  return b;
}

view::EstimateSample view_sample(const hal::Estimate& e) {
  view::EstimateSample v;
  v.stamp_ns = e.stamp_ns;
  v.pose = {e.pose.x, e.pose.y, e.pose.theta};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) v.covariance[3 * r + k] = static_cast<double>(e.covariance(r, k));
  v.status = e.status;
  v.rejected_inputs = e.rejected_inputs;
  return v;
}

view::MapGrid view_map(const est::OccupancyGrid& g) {
  view::MapGrid m;
  m.width = g.width();
  m.height = g.height();
  m.resolution_m = static_cast<double>(g.resolution());
  m.origin_x = static_cast<double>(g.origin_x());
  m.origin_y = static_cast<double>(g.origin_y());
  m.cells.assign(g.cells(), g.cells() + g.cell_count());
  return m;
}

void feed_particles(view::LiveView& v, const EstimatorPipeline& p, hal::TimeNs stamp_ns) {
  if (!v.particles_due()) return;
  const est::ConstParticleSetView c = p.particles();
  if (c.count > 0) v.publish_particles(stamp_ns, c.x, c.y, c.theta, c.count);
}

void feed_team(view::LiveView& v, const TeamEstimator& e, std::int32_t own_robot, hal::TimeNs stamp_ns) {
  const auto& slam = e.slam();
  const auto& P = slam.covariance();
  for (int a = 0; a < slam.robots(); ++a) {
    view::EstimateSample s;
    s.stamp_ns = stamp_ns;
    const int o = slam.robot_offset(a);
    s.pose = {static_cast<double>(slam.mean()(o)), static_cast<double>(slam.mean()(o + 1)), 0.0};
    s.covariance[0] = static_cast<double>(P(o, o));
    s.covariance[1] = s.covariance[3] = static_cast<double>(P(o, o + 1));
    s.covariance[4] = static_cast<double>(P(o + 1, o + 1));
    s.status = e.status();
    v.publish_team_estimate(a, s, a == own_robot);
  }
  if (!v.landmarks_due()) return;
  std::array<view::LandmarkSample, kTeamMaxLandmarks> l;
  const int n = slam.landmarks() < kTeamMaxLandmarks ? slam.landmarks() : kTeamMaxLandmarks;
  for (int k = 0; k < n; ++k) {
    const int o = slam.landmark_offset(k);
    view::LandmarkSample& m = l[static_cast<std::size_t>(k)];
    m.id = slam.landmark_id(k);
    m.x = static_cast<double>(slam.mean()(o));
    m.y = static_cast<double>(slam.mean()(o + 1));
    m.covariance[0] = static_cast<double>(P(o, o));
    m.covariance[1] = m.covariance[2] = static_cast<double>(P(o, o + 1));
    m.covariance[3] = static_cast<double>(P(o + 1, o + 1));
  }
  v.publish_landmarks(stamp_ns, l.data(), static_cast<std::size_t>(n));
}

}  // namespace node
