#pragma once
// The world of the cooperative EKF-SLAM scenarios: R holonomic point robots (x_k+1 = x_k + u_k dt + w_k, the
// exercise's model, with w_k what the filter assumes) following smooth closed paths, M point landmarks, and each
// robot's range (and bearing) sensor, which sees every robot and landmark within its reach. The truth starts at a
// draw from the filter's prior (the team's initial estimate), so that the NEES is a test of consistency. Host only.
#include <cstdint>
#include <vector>

#include "est/eigen.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/team/team_message.hpp"
#include "node/team_spec.hpp"

namespace sim::team {

class CoopWorld {
 public:
  // The exercise: two robots on circles 4 m apart, one landmark between them with an initial estimate, range only,
  // always in view, 10 Hz.
  static CoopWorld exercise(std::uint64_t seed);
  // Four robots on circles from the corners of a 6 m x 5 m rectangle, twelve landmarks on a grid around them with no
  // prior (mapped from their first range and bearing), reach 8 m, 10 Hz.
  static CoopWorld team_of_four(std::uint64_t seed);

  // Moves the truth over step k (1, 2, ...) and returns every robot's message for it.
  std::vector<est::team::TeamMessage> step(std::uint32_t k);

  int robots() const { return static_cast<int>(x_.size()); }
  int landmarks() const { return static_cast<int>(m_.size()); }
  bool bearings() const { return bearings_; }
  float step_s() const { return spec_.estimator.step_s; }
  const Eigen::Vector2f& robot(int a) const { return x_[static_cast<std::size_t>(a)]; }
  const Eigen::Vector2f& landmark(int k) const { return m_[static_cast<std::size_t>(k)]; }
  Eigen::Vector2f landmark_by_id(std::int32_t id) const { return landmark(id - kFirstLandmarkId); }
  // The estimator's spec every node uses: the initial estimate, the priors' and the sensors' sigmas.
  const node::TeamSpec& spec() const { return spec_; }
  // The commanded velocity of robot a over step k.
  Eigen::Vector2f velocity(int a, std::uint32_t k) const;

  static constexpr std::int32_t kFirstLandmarkId = 100;

 private:
  CoopWorld(std::uint64_t seed, int robots, int landmarks, bool bearings);
  Eigen::Vector2f draw(float sigma);

  node::TeamSpec spec_;
  bool bearings_ = false;
  float reach_m_ = 1.0e9f;
  std::vector<Eigen::Vector2f> x_, m_, centre_;
  est::Rng rng_;
};

}  // namespace sim::team
