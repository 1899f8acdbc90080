#include "team/coop_world.hpp"

#include <cmath>

#include "est/random/samplers.hpp"

namespace sim::team {

using est::team::TeamMessage;

CoopWorld::CoopWorld(std::uint64_t seed, int robots, int landmarks, bool bearings)
    : bearings_(bearings), rng_(seed) {
  spec_.estimator.robots = robots;
  spec_.estimator.step_s = 0.1f;
  spec_.estimator.noise.sigma_range = 0.05f;
  spec_.estimator.noise.sigma_bearing = 0.02f;
  spec_.estimator.motion_sigma_mps = 0.05f;
  spec_.estimator.unknown_speed_mps = 0.5f;
  spec_.initial_sigma_m = 0.2f;
  spec_.landmark_sigma_m = 0.3f;
  spec_.window_steps = 10;
  (void)landmarks;
}

Eigen::Vector2f CoopWorld::draw(float s) {
  return Eigen::Vector2f(est::sample_normal(rng_, s), est::sample_normal(rng_, s));
}

CoopWorld CoopWorld::exercise(std::uint64_t seed) {
  CoopWorld w(seed, 2, 1, false);
  const Eigen::Vector2f start[2] = {{0.0f, 0.0f}, {4.0f, 0.0f}};
  for (const Eigen::Vector2f& p : start) {
    w.spec_.initial.push_back(p(0)), w.spec_.initial.push_back(p(1));
    w.x_.push_back(p + w.draw(w.spec_.initial_sigma_m));
  }
  const Eigen::Vector2f l0(2.0f, 3.0f);
  w.spec_.landmarks.push_back({kFirstLandmarkId, l0(0), l0(1)});
  w.m_.push_back(l0 + w.draw(w.spec_.landmark_sigma_m));
  return w;
}

CoopWorld CoopWorld::team_of_four(std::uint64_t seed) {
  CoopWorld w(seed, 4, 12, true);
  w.reach_m_ = 8.0f;
  for (int a = 0; a < 4; ++a) {
    const Eigen::Vector2f p(6.0f * static_cast<float>(a % 2), 5.0f * static_cast<float>(a / 2));
    w.spec_.initial.push_back(p(0)), w.spec_.initial.push_back(p(1));
    w.x_.push_back(p + w.draw(w.spec_.initial_sigma_m));
  }
  for (int k = 0; k < 12; ++k)  // a 4 x 3 grid, 4 m x 5 m apart, around the team
    w.m_.emplace_back(-3.0f + 4.0f * static_cast<float>(k % 4), -2.5f + 5.0f * static_cast<float>(k / 4));
  return w;
}

Eigen::Vector2f CoopWorld::velocity(int a, std::uint32_t k) const {
  // Circles of radius 1.5 m (0.9 m/s at 0.6 rad/s), every robot its own phase and sense; the circles are centred
  // where the robot starts, 1.5 m to its side.
  const float w = (a % 2 == 0 ? 0.6f : -0.5f);
  const float ph = w * spec_.estimator.step_s * static_cast<float>(k) + static_cast<float>(a);
  return Eigen::Vector2f(0.9f * std::cos(ph), 0.9f * std::sin(ph));
}

std::vector<TeamMessage> CoopWorld::step(std::uint32_t k) {
  using namespace est::team;
  const float dt = spec_.estimator.step_s;
  const int R = robots();
  std::vector<TeamMessage> out(static_cast<std::size_t>(R));
  for (int a = 0; a < R; ++a) {
    const Eigen::Vector2f u = velocity(a, k);
    x_[static_cast<std::size_t>(a)] += u * dt + draw(spec_.estimator.motion_sigma_mps * dt);
    TeamMessage& m = out[static_cast<std::size_t>(a)];
    m.robot = a;
    m.seq = k;
    m.stamp_ns = static_cast<TimeNs>(k) * static_cast<TimeNs>(std::llround(static_cast<double>(dt) * 1e9));
    m.control.kind = ControlKind::holonomic;
    m.control.dt_s = dt;
    m.control.v1 = u(0);
    m.control.v2 = u(1);
  }
  const float sr = spec_.estimator.noise.sigma_range, sb = spec_.estimator.noise.sigma_bearing;
  for (int a = 0; a < R; ++a) {
    TeamMessage& m = out[static_cast<std::size_t>(a)];
    auto see = [&](TargetKind t, std::int32_t id, const Eigen::Vector2f& p) {
      const Eigen::Vector2f d = p - x_[static_cast<std::size_t>(a)];
      if (d.norm() > reach_m_ || m.count >= kMaxTeamMeasurements) return;
      TeamMeasurement& z = m.measurements[m.count++];
      z.target = t;
      z.id = id;
      z.range_m = std::fabs(d.norm() + est::sample_normal(rng_, sr));
      z.has_bearing = bearings_;
      if (bearings_)
        z.bearing_rad = std::remainder(std::atan2(d(1), d(0)) + est::sample_normal(rng_, sb), 6.28318531f);
    };
    for (int b = 0; b < R; ++b)
      if (b != a) see(TargetKind::robot, b, x_[static_cast<std::size_t>(b)]);
    for (int l = 0; l < landmarks(); ++l)
      see(TargetKind::landmark, kFirstLandmarkId + l, m_[static_cast<std::size_t>(l)]);
  }
  return out;
}

}  // namespace sim::team
