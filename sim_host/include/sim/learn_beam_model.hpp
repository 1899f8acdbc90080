#pragma once
// `learn-beam-model`: the beam model's intrinsic parameters (z_hit, z_short, z_max, z_rand, sigma_hit,
// lambda_short) learned by EM (Thrun table 6.2, est::sim::learn_intrinsic_parameters) from a recorded LCM log's
// scans and ground-truth poses on a known map. Host only (may throw).
#include <cstdint>
#include <string>

#include "est/geometry/pose2.hpp"
#include "maps/learn_intrinsic_parameters.hpp"
#include "sim/scenario.hpp"

namespace sim {

struct LearnBeamModelOptions {
  std::string log_path;
  std::string map_yaml;         // empty: the synthetic office
  est::Pose2 mount{};           // rangefinder pose in the robot frame
  std::int32_t beam_stride = 4; // every s-th beam
  std::int64_t max_truth_gap_ns = 5000000;  // a scan needs a ground-truth pose within this of its stamp
};

struct LearnBeamModelResult {
  est::sim::LearnResult learned;
  std::uint64_t scans_used = 0;
  std::uint64_t scans_skipped = 0;     // no ground truth near the stamp, or a bad geometry
  std::uint64_t readings_used = 0;
  std::uint64_t readings_skipped = 0;  // NaN or infinite
};

LearnBeamModelResult learn_beam_model_from_log(const LearnBeamModelOptions& options);

}  // namespace sim
