#pragma once
// Victoria Park (Guivant and Nebot, ACFR): a utility car with Ackermann steering drives 26 min among trees. From the
// text release and its RFS-SLAM conversions (acfr-text-rfsslam/): inputs.dat (time, speed of the rear left wheel's
// encoder, steering angle; 40 Hz), measurements.dat (tree detections of the laser: time, range, beam angle in [0, pi]
// with pi/2 straight ahead, diameter), gps.dat (time, x, y in RFS-SLAM's frame, with dropouts and jumps). All three
// share one time base (the first GPS fix at 0).
//
// The car is the book's bicycle (est/motion/bicycle_model.hpp) referenced at the FRONT axle's middle: that is where
// the firmware's model puts its pose, and where the steering angle the dataset gives is the wheel's angle (the
// equivalent front wheel of the Ackermann pair). Geometry (info.txt, car.bmp; the car drawn from above, forward left):
//   L = 2.83 m  wheelbase;  H = 0.76 m  the encoder's wheel (rear left) from the centreline;
//   a = 0.95 m, b = 0.5 m  the laser (and the GPS antenna, car.bmp: "laser and gps position") ahead of the front
//                          axle and to the left of the centreline, on the encoder's side.
// The speed: the rear axle's middle moves on a circle of radius R = L / tan(steer) about the instantaneous centre of
// rotation, the rear left wheel on R - H, the front axle's middle on R / cos(steer); the encoder's speed v_e gives
//   v_front = v_e / ((1 - tan(steer) H / L) cos(steer)).
// The tree detections: a point at (range, beam - pi/2) in the laser's frame is at (a, b) + that point in the front
// axle's frame; the importer writes its range and bearing from the front axle's middle, so that every consumer sees
// one reference point (est's range-bearing model puts the sensor at the pose).
//
// The import writes one LCM log, stamps in the dataset's seconds:
//   EST_WHEEL_TICKS   encoder_ticks_t, one wheel: the front axle middle's travel as a counter of metres_per_tick
//                     (the bicycle's traction encoder; the remainder is carried, so no travel is lost to rounding)
//   EST_STEERING      steering_t: the steering angle as given
//   EST_LANDMARKS     landmark_sighting_t: one per laser scan, every tree detected, from the front axle's middle,
//                     signature = the tree's diameter (m), id = -1 (the correspondence is unknown)
//   EST_GPS           ground_truth_t: the GPS fixes (theta NaN), the position of the laser / antenna
// Host only.
#include <cstdint>
#include <string>
#include <vector>

#include "data/eval_report.hpp"
#include "data/import_report.hpp"

namespace sim::data {

struct VictoriaGeometry {
  double wheelbase = 2.83;       // L, m
  double encoder_offset = 0.76;  // H, m, the rear left wheel from the centreline
  double laser_ahead = 0.95;     // a, m, ahead of the front axle
  double laser_left = 0.5;       // b, m, left of the centreline
};

// The encoder's speed (rear left wheel) as the speed of the front axle's middle (the comment above).
double victoria_front_speed(double encoder_speed, double steer, const VictoriaGeometry& g);

struct VictoriaImportOptions {
  VictoriaGeometry geometry;
  double max_seconds = 0.0;         // > 0: only t <= max_seconds
  double metres_per_tick = 0.001;   // of EST_WHEEL_TICKS
};

struct VictoriaImport {
  std::string folder;  // where the files were read (acfr-text-rfsslam/)
  double duration_s = 0.0;
  std::uint64_t inputs = 0, scans = 0, detections = 0, gps = 0;
  std::uint64_t events = 0;
};

// Imports the dataset (its folder, or its acfr-text-rfsslam/ folder) into `out_log`; throws std::runtime_error for a
// folder without the files, ImportError for a malformed line under OnError::refuse.
VictoriaImport import_victoria(const std::string& dir, const std::string& out_log,
                               const VictoriaImportOptions& options, ImportReport& report);

// The streams read back from an imported log.
struct VictoriaTicks {
  std::int64_t t_ns = 0;
  std::uint32_t count = 0;
};
struct VictoriaSteering {
  std::int64_t t_ns = 0;
  double angle = 0.0;
};
struct VictoriaDetection {
  double range = 0.0, bearing = 0.0, diameter = 0.0;  // from the front axle's middle
};
struct VictoriaScan {
  std::int64_t t_ns = 0;
  std::vector<VictoriaDetection> trees;
};
struct VictoriaLog {
  std::vector<VictoriaTicks> ticks;
  std::vector<VictoriaSteering> steering;
  std::vector<VictoriaScan> scans;
  Trajectory gps;  // theta 0 (a fix has none)
};
VictoriaLog read_victoria_log(const std::string& log);

}  // namespace sim::data
