#pragma once
// The cooperative EKF-SLAM exercise as a message generator for the team tests: R holonomic point robots driving
// circles and M point landmarks, every robot measuring its range (and, with bearings, its world-frame bearing) to
// every other robot and every landmark at every step, the truth drawn from the filter's prior (so that NEES is
// consistent). Step k's messages are what the robots would share.
#include <cmath>
#include <vector>

#include "est/eigen.hpp"
#include "est/random/samplers.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/team/team_message.hpp"

namespace est::test {

struct TeamExercise {
  int robots = 2;
  int landmarks = 1;
  bool bearings = false;
  float step_s = 0.1f;
  float sigma_range = 0.05f, sigma_bearing = 0.02f;
  float motion_sigma_mps = 0.05f;  // per axis, as the filter's CoopEkfConfig says
  float sigma_robot0 = 0.2f, sigma_landmark0 = 0.3f;
  std::vector<Eigen::Vector2f> robot0, landmark0;  // the initial estimate
  std::vector<Eigen::Vector2f> x, m;               // the truth
  est::Rng rng;

  TeamExercise(int r, int l, bool with_bearings, std::uint64_t seed)
      : robots(r), landmarks(l), bearings(with_bearings), rng(seed) {
    for (int a = 0; a < r; ++a) robot0.emplace_back(4.0f * static_cast<float>(a % 2), 3.0f * static_cast<float>(a / 2));
    if (l == 1) landmark0.emplace_back(2.0f, 3.0f);  // the exercise's one landmark, between and above the robots
    for (int k = 0; l > 1 && k < l; ++k)               // a grid around the team: 4 columns, 3 m apart
      landmark0.emplace_back(-2.0f + 3.0f * static_cast<float>(k % 4), -2.0f + 3.5f * static_cast<float>(k / 4));
    for (const auto& p : robot0) x.push_back(p + draw(sigma_robot0));
    for (const auto& p : landmark0) m.push_back(p + draw(sigma_landmark0));
  }
  Eigen::Vector2f draw(float s) { return Eigen::Vector2f(est::sample_normal(rng, s), est::sample_normal(rng, s)); }

  // The commanded velocity of robot a at step k: circles of radius ~1.5 m, each robot its own phase and sense.
  Eigen::Vector2f velocity(int a, std::uint32_t k) const {
    const float w = (a % 2 == 0 ? 0.6f : -0.5f) * step_s;
    const float ph = w * static_cast<float>(k) + static_cast<float>(a);
    return Eigen::Vector2f(0.9f * std::cos(ph), 0.9f * std::sin(ph));
  }

  // Moves the truth over step k and returns every robot's message for it.
  std::vector<est::team::TeamMessage> step(std::uint32_t k) {
    using namespace est::team;
    std::vector<TeamMessage> out(static_cast<std::size_t>(robots));
    for (int a = 0; a < robots; ++a) {
      const Eigen::Vector2f u = velocity(a, k);
      x[static_cast<std::size_t>(a)] += u * step_s + draw(motion_sigma_mps * step_s);
      TeamMessage& msg = out[static_cast<std::size_t>(a)];
      msg.robot = a;
      msg.seq = k;
      msg.stamp_ns = static_cast<TimeNs>(k) * static_cast<TimeNs>(step_s * 1e9f);
      msg.control.kind = ControlKind::holonomic;
      msg.control.dt_s = step_s;
      msg.control.v1 = u(0);
      msg.control.v2 = u(1);
    }
    for (int a = 0; a < robots; ++a) {
      TeamMessage& msg = out[static_cast<std::size_t>(a)];
      auto add = [&](TargetKind t, std::int32_t id, const Eigen::Vector2f& p) {
        const Eigen::Vector2f d = p - x[static_cast<std::size_t>(a)];
        TeamMeasurement& z = msg.measurements[msg.count++];
        z.target = t;
        z.id = id;
        z.range_m = std::fabs(d.norm() + est::sample_normal(rng, sigma_range));
        z.has_bearing = bearings;
        if (bearings) z.bearing_rad = std::remainder(std::atan2(d(1), d(0)) + est::sample_normal(rng, sigma_bearing),
                                                     6.2831853f);
      };
      for (int b = 0; b < robots; ++b)
        if (b != a) add(TargetKind::robot, b, x[static_cast<std::size_t>(b)]);
      for (int l = 0; l < landmarks; ++l) add(TargetKind::landmark, 100 + l, m[static_cast<std::size_t>(l)]);
    }
    return out;
  }
};

}  // namespace est::test
