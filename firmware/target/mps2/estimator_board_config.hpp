#pragma once
// estimator-board.elf's static configuration, the reference rig: a differential drive (the office robot's wheels)
// localized by augmented MCL on a 360-beam rangefinder with the likelihood field, 512 particles, every 6th beam,
// a fixed seed, no KLD (so the particle capacity cannot change a result), starting from a known pose.
//
// One header for both sides: the image builds its pipeline from it (estimator_board_main.cpp), and the host test
// (tests/board/) builds the matching estimator_node command line from the same constants, each named beside the node
// option it sets, so the two cannot drift apart. What the node has no option for is asserted equal to the default
// both sides take (the static_asserts below). Where the board's capacities are smaller than the node's (particles
// 512 vs 20000, beams 360 vs 1440, queue 32 vs 256, scan slots 2 vs 4, map 512 x 512 vs 2048 x 2048) results
// cannot differ as long as nothing exceeds them: KLD is off, and the image reports its queue_full count (the test
// requires 0) and rejects a larger scan or map with a counted reason instead of truncating it.
#include <cstdint>

#include "est/filter/augmented_mcl.hpp"
#include "est/geometry/pose2.hpp"
#include "est/loop/configured_loop.hpp"
#include "est/loop/likelihood_field_scan.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "hal/sample_timing.hpp"
#include "hal/sensors/wheel_ticks/can.hpp"

namespace board {

// The loop's static configuration (est/loop/configured_loop.hpp).
struct EstimatorBoardConfig {
  using Model = est::DiffDriveMotionModel;                                  // --model diff-drive
  static constexpr est::loop::Filter kFilter = est::loop::Filter::mcl;      // --filter mcl
  using ScanModel = est::loop::LikelihoodFieldScan;                         // --sensor-model likelihood-field
  static constexpr std::uint32_t kMaxParticles = 512;
  static constexpr std::int32_t kMaxBeams = 360;       // also the scan reassembler's and the HAL gate's limit
  static constexpr std::uint32_t kQueueCapacity = 32;  // 20 ms of 100 Hz encoders and 10 Hz scans need ~4
  static constexpr std::uint32_t kScanSlots = 2;
  static constexpr est::loop::LoopTiming kTiming{};    // --predict-hz, --reorder-window, --encoder-timeout, ...
};

// The board's map capacity (cells per side): the office (400 x 300 at 0.05 m) and anything up to 25.6 m square.
inline constexpr std::int32_t kMapMaxSide = 512;

// The rig's parameters: run-time values of the estimator, fixed in this image.
namespace rig {
inline constexpr std::uint32_t kParticles = EstimatorBoardConfig::kMaxParticles;  // --particles
inline constexpr std::uint64_t kSeed = 11;                                         // --seed
inline constexpr std::int32_t kBeamStride = 6;                                     // --beam-stride: 60 of 360 beams
// The start of the office route (sim_host/world/office_world.hpp), where tests/support/office_sensor_log.hpp's
// stream begins; the test checks that.
inline constexpr est::Pose2 kInitialPose{5.5f, 7.3f, 0.0f};                        // --initial-pose
inline constexpr float kInitialSigmaXy = 0.2f;                                     // --initial-sigma xy,
inline constexpr float kInitialSigmaTheta = 0.1f;                                  //                 theta
// --wheel-radius, --track-width, --ticks-per-rev, --travel-sigma-per-m, --travel-sigma-floor, --rot-sigma
inline constexpr est::DiffDriveParams kDiffDrive{0.05f, 0.3f, 4096u, 0.05f, 0.003f, 0.01f};
// --z-hit, --z-max, --z-rand, --sigma-hit, --range-max, --max-distance
inline constexpr est::LikelihoodFieldParams kField{0.85f, 0.05f, 0.10f, 0.2f, 12.0f, 2.0f};
inline constexpr est::Pose2 kSensorMount{0.0f, 0.0f, 0.0f};                        // --sensor-mount
inline constexpr float kClearance = 0.2f;                                          // --clearance
inline constexpr float kClusterCell = 1.0f;                                        // --cluster-cell
inline constexpr est::MclConfig kMcl{};  // --alpha-slow, --alpha-fast, --max-injection, recovery (no --no-recovery)
// The HAL gate: --wheel-count, --max-age, --max-future (the same timing for every sensor, as the node sets it).
inline constexpr std::uint8_t kWheelCount = 2;
inline constexpr hal::TimingLimits kTimingLimits{};
// The encoder counters of the bus (the node uses the same for --replay-can).
inline constexpr std::uint8_t kCounterBits = hal::can::kCanWheelCounterBits;
// The interface name of the output candump lines (estimator_node --out-can writes "can0").
inline constexpr const char* kOutputInterface = "can0";
}  // namespace rig

// What the node has no option for: the defaults both sides take.
static_assert(!rig::kMcl.kld, "KLD would make the particle capacity (512 here, 20000 in the node) part of the result");
static_assert(rig::kMcl.resample_ess_fraction == est::MclConfig{}.resample_ess_fraction &&
                  rig::kMcl.occupied_log_weight == est::MclConfig{}.occupied_log_weight,
              "estimator_node has no option for these: the rig must keep MclConfig's defaults");
static_assert(EstimatorBoardConfig::kTiming.max_catch_up_predictions ==
                  est::loop::LoopTiming{}.max_catch_up_predictions,
              "estimator_node has no option for this: the rig must keep LoopTiming's default");
static_assert(rig::kParticles <= EstimatorBoardConfig::kMaxParticles, "more particles than the capacity");

}  // namespace board
