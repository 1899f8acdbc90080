// A small recorded sensor stream (tests/support/office_sensor_log.hpp).
#include "office_sensor_log.hpp"

#include <lcm/lcm-cpp.hpp>
#include <stdexcept>

#include "est/random/xoshiro128.hpp"
#include "hal/lcm/lcm_backend.hpp"
#include "hal/lcm/lcm_convert.hpp"
#include "world/landmark_sensor.hpp"
#include "world/office_world.hpp"
#include "world/range_sensor.hpp"
#include "world/robots.hpp"

namespace est::test {

namespace {

template <typename Message>
void write(::lcm::LogFile& log, const std::string& channel, hal::TimeNs stamp_ns, const Message& m) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  ::lcm::LogEvent e{};
  e.timestamp = stamp_ns / 1000;
  e.channel = channel;
  e.datalen = static_cast<std::int32_t>(buf.size());
  e.data = buf.data();
  if (log.writeEvent(&e) != 0) throw std::runtime_error("cannot write the LCM log");
}

}  // namespace

est::DiffDriveParams office_robot_truth() {
  est::DiffDriveParams p;
  p.wheel_radius = 0.05f;
  p.track_width = 0.3f;
  p.ticks_per_rev = 4096u;
  p.travel_sigma_per_m = 0.02f;
  p.travel_sigma_floor = 0.0005f;
  p.final_rot_sigma = 0.002f;
  return p;
}

OfficeStream write_office_stream(const std::string& path, const OfficeStreamSpec& spec) {
  const auto& world = est::sim::office_world();
  ::lcm::LogFile log(path, "w");
  if (!log.good()) throw std::runtime_error("cannot create " + path);
  const hal::lcm::Channels ch;
  constexpr hal::TimeNs kStep = 10 * hal::kNsPerMs;
  constexpr float kDt = 0.01f;

  OfficeStream out;
  out.start = world.route.pose_on_segment(0, 0.0f);
  est::sim::DiffDriveRobot robot(world.route, out.start, 1, office_robot_truth(), spec.speed_mps, kDt);
  est::Rng motion_rng(spec.seed), scan_rng(spec.seed + 1000u), landmark_rng(spec.seed + 2000u);
  std::vector<est::sim::Sighting> sightings;
  std::vector<hal::LandmarkFeature> features;
  const est::ScanLayout layout = est::sim::lidar_360(spec.range_max_m);
  std::vector<float> ranges;
  hal::WheelTicks counters;
  counters.wheel_count = 2;
  const est::DiffDriveParams base = office_robot_truth();
  const float m_per_tick = est::diff_drive_m_per_tick(base);
  hal::OdometrySample odometry;  // the base's integrated pose, in its own frame (starting at the origin)
  const int steps = static_cast<int>(spec.duration_s * 100.0);
  for (int k = 0; k <= steps; ++k) {
    const hal::TimeNs t = spec.t0_ns + k * kStep;
    est::DiffDriveControl u{0, 0};
    if (k > 0) {
      u = robot.step(motion_rng);
      counters.count[0] += static_cast<std::uint32_t>(u.left_ticks);  // a 32-bit counter wraps
      counters.count[1] += static_cast<std::uint32_t>(u.right_ticks);
      odometry.pose = est::DiffDriveMotionModel::predict(odometry.pose, u, base);
    }
    counters.stamp_ns = t;
    write(log, ch.wheel_ticks, t, hal::lcm::to_lcm(counters, 32));
    ++out.encoder_messages;
    if (spec.twist && k > 0) {
      // The twist of the last 10 ms as the encoders measured it, stamped at its start: held over (t - 10 ms, t] as
      // a commanded twist would be.
      const float left = static_cast<float>(u.left_ticks) * m_per_tick;
      const float right = static_cast<float>(u.right_ticks) * m_per_tick;
      const hal::TwistSample twist{t - kStep, 0.5f * (left + right) / kDt, 0.0f,
                                   (right - left) / base.track_width / kDt};
      write(log, ch.twist, t - kStep, hal::lcm::to_lcm(twist));
      ++out.twist_messages;
    }
    if (spec.odometry) {
      odometry.stamp_ns = t;
      write(log, ch.odometry, t, hal::lcm::to_lcm(odometry));
      ++out.odometry_messages;
    }
    est_lcm::ground_truth_t g{};
    g.stamp_ns = t;
    g.x_m = robot.pose().x;
    g.y_m = robot.pose().y;
    g.theta_rad = robot.pose().theta;
    write(log, ch.ground_truth, t, g);
    out.truth_t.push_back(t);
    out.truth.push_back(robot.pose());
    if (k % spec.scan_every == 0) {
      est::sim::simulate_scan(world.grid(), robot.pose(), est::Pose2{}, layout, est::sim::RangeNoise{}, scan_rng,
                              ranges);
      hal::RangeScanView v;
      v.stamp_ns = t;
      v.geometry = {layout.angle_min, layout.angle_increment, layout.range_min, layout.range_max, 0.1f};
      v.ranges = ranges.data();
      v.count = ranges.size();
      write(log, ch.range_scan, t, hal::lcm::to_lcm(v));
      ++out.scan_messages;
    }
    if (spec.landmark_every > 0 && k % spec.landmark_every == 0) {
      est::sim::simulate_landmarks(world.grid(), world.landmarks(), robot.pose(), est::sim::LandmarkSensorSpec{},
                                   landmark_rng, sightings);
      features.clear();
      for (const est::sim::Sighting& s : sightings) features.push_back({s.f.range, s.f.bearing, s.f.signature, s.c});
      if (!features.empty()) {
        write(log, ch.landmarks, t, hal::lcm::to_lcm(hal::LandmarkSightingView{t, features.data(), features.size()}));
        ++out.landmark_messages;
        out.landmark_features += features.size();
      }
    }
  }
  return out;
}

}  // namespace est::test
