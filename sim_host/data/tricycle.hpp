#pragma once
// The front-tractor tricycle calibration set (Grisetti's Probabilistic Robotics course, Sapienza): one record per
// line at about 25 Hz, "time: T ticks: STEER TRACTION model_pose: X Y THETA tracker_pose: X Y THETA", after a '#'
// header with the kinematic parameters' initial guesses, the encoders' maxima and the laser's pose on the robot.
//   steering  an absolute encoder, 0 .. steer_max - 1 (8192); ticks above steer_max / 2 are negative angles
//   traction  an incremental encoder stored in a uint32: it wraps at 2^32 (the set starts just below it), so only
//             differences modulo 2^32 mean anything
//   tracker   the pose of the laser sensor from an independent odometry of that sensor: the calibration's reference
//   model     the robot's own uncalibrated odometry, not imported (the set's README: "you can ignore this")
// The course's conventions for the parameters, kept here so that its numbers compare:
//   steering angle a = ksteer * 2 pi * signed_ticks / steer_max + steer_offset   (rad, left positive)
//   front wheel travel s = ktraction * delta_ticks / traction_max                (m)
//   axis_length: the front wheel's distance to the rear axle's middle, base_link (m)
//
// The import writes one LCM log, t = 0 at the first record (its Unix time in the summary):
//   EST_WHEEL_TICKS     encoder_ticks_t, one wheel: the traction counter as read (counter_bits 32)
//   EST_STEERING        steering_t: the steering angle by the calibration given (default: the header's guesses)
//   EST_STEERING_TICKS  encoder_ticks_t, one wheel: the raw absolute steering encoder (counter_bits 13), so that an
//                       evaluation can calibrate it again
//   EST_GROUND_TRUTH    ground_truth_t: the tracked sensor pose (the reference, never an estimator input)
// Host only.
#include <cstdint>
#include <string>
#include <vector>

#include "data/eval_report.hpp"
#include "data/import_report.hpp"

namespace sim::data {

inline const char* const kSteeringTicksChannel = "EST_STEERING_TICKS";  // encoder_ticks_t: an absolute encoder

// The front-tractor tricycle's kinematic parameters and the sensor's pose on base_link, in the course's units.
struct TricycleParams {
  double ksteer = 0.1;             // rad of steering per rad of encoder turn
  double ktraction = 0.0106141;    // m of front wheel travel per traction_max ticks
  double axis_length = 1.4;        // m, front wheel to the rear axle's middle
  double steer_offset = 0.0;       // rad, the steering angle at encoder zero
  double laser_x = 1.5, laser_y = 0.0, laser_theta = 0.0;  // the sensor in base_link, m, m, rad
};

// The dataset's '#' header: the initial guesses and the encoders' ranges.
struct TricycleHeader {
  TricycleParams guess;
  std::int64_t steer_max = 8192;
  std::int64_t traction_max = 5000;
  bool complete = false;  // every value was found in the header (else the defaults above stand in, and a note says)
};

struct TricycleImportOptions {
  double max_seconds = 0.0;   // > 0: only t <= max_seconds
  bool calibrated = false;    // the steering angle of EST_STEERING from `params` instead of the header's guesses
  TricycleParams params;
};

struct TricycleImport {
  TricycleHeader header;
  double t0_unix_s = 0.0;
  double duration_s = 0.0;
  std::uint64_t records = 0;
  std::uint64_t traction_wraps = 0;  // times the traction counter passed 2^32
  std::uint64_t events = 0;
};

// Imports `file` into `out_log`; throws std::runtime_error when the file cannot be read or holds no record,
// ImportError for a malformed line under OnError::refuse.
TricycleImport import_tricycle(const std::string& file, const std::string& out_log,
                               const TricycleImportOptions& options, ImportReport& report);

// One record read back from an imported log.
struct TricycleRecord {
  std::int64_t t_ns = 0;
  std::uint32_t steer_ticks = 0;     // absolute
  std::uint32_t traction_ticks = 0;  // the counter as read (wraps at 2^32)
  TimedPose tracker;                 // the sensor's tracked pose
};
std::vector<TricycleRecord> read_tricycle_log(const std::string& log);

// The traction increment from a to b, modulo 2^32 (a counter that wrapped is not a jump of 2^32).
inline std::int64_t traction_increment(std::uint32_t a, std::uint32_t b) {
  return static_cast<std::int64_t>(static_cast<std::int32_t>(b - a));
}
// The steering angle of an absolute reading: ticks above steer_max / 2 are negative (the encoder's zero is straight).
double tricycle_steering_angle(std::uint32_t ticks, const TricycleParams& p, std::int64_t steer_max);

}  // namespace sim::data
