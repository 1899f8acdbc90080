#pragma once
// Learning the beam model's intrinsic parameters by expectation maximization, Probabilistic Robotics table 6.2
// (learn_intrinsic_parameters), from readings z_i paired with the expected range z*_i at a known pose (ray cast
// in the map). Host only, double precision.
//
// Differences from the table, on purpose: the responsibilities include the mixture weights (the table's eta omits
// them, which is not EM); a max reading (z >= range_max) is the discrete atom of the firmware's model, so it is
// explained by p_max alone and every other reading by hit, short and rand; lambda_short is the maximum-likelihood
// value of the exponential truncated to [0, z*_i] (solved by bisection; the table's sum e / sum e z ignores the
// truncation and overestimates lambda by ~10-20 % for z* ~ 2-5 / lambda); sigma_hit ignores the truncation of the
// Gaussian to [0, z_max] (exact when z* is more than ~3 sigma from both ends).
#include <vector>

#include "est/sensor/beam_range_finder_model.hpp"

namespace est::sim {

struct RangeSample {
  double z;       // m, measured
  double z_star;  // m, expected (ray cast at the known pose)
};

struct LearnResult {
  BeamModelParams params;
  int iterations = 0;
  bool converged = false;  // largest parameter change below the tolerance
  double log_likelihood = 0.0;
};

// `initial` supplies range_max, max_bin_width and the starting point. Throws std::invalid_argument on empty or
// non-finite input.
LearnResult learn_intrinsic_parameters(const std::vector<RangeSample>& data, const BeamModelParams& initial,
                                       int max_iterations = 500, double tolerance = 1e-7);

}  // namespace est::sim
