#pragma once
// What a host program runs (estimator_node, the simulator): the robot model, the filter and MCL's range model, every
// parameter of the estimator they choose, the initial belief, and the loop's and the HAL's limits, in one struct
// with defaults. estimator_node fills it from its command line (node/node_config.hpp), the simulator from its
// scenario; node/estimator_pipeline.hpp turns it into the firmware's pipeline. Host only.
#include <cstdint>
#include <string>

#include "est/filter/augmented_mcl.hpp"
#include "est/geometry/pose2.hpp"
#include "est/loop/configured_loop.hpp"
#include "est/loop/control_assemblers.hpp"
#include "est/loop/steered_scan.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/motion/holonomic_pose_model.hpp"
#include "est/motion/odometry_model.hpp"
#include "est/motion/omni_model.hpp"
#include "est/motion/velocity_model.hpp"
#include "est/sensor/beam_range_finder_model.hpp"
#include "est/sensor/landmark_model.hpp"
#include "est/sensor/likelihood_field_range_finder_model.hpp"
#include "hal/validated_inputs.hpp"

namespace node {

// Every motion model of est/motion, by the name the command lines use.
using RobotModel = est::loop::MotionModelKind;
inline constexpr RobotModel kRobotModels[] = {RobotModel::velocity, RobotModel::odometry, RobotModel::bicycle,
                                              RobotModel::diff_drive, RobotModel::omni, RobotModel::holonomic};
const char* to_string(RobotModel m);      // "velocity", "odometry", "bicycle", "diff-drive", "omni", "holonomic"
bool parse(const std::string& s, RobotModel& out);

// MCL's range models (est/loop/likelihood_field_scan.hpp, beam_scan.hpp, steered_scan.hpp).
using RangeModel = est::loop::RangeModelKind;
const char* to_string(RangeModel m);      // "likelihood-field", "beam", "steered"
bool parse(const std::string& s, RangeModel& out);

// Where the beam model's z* comes from: the heading range table (approximate, est/map/heading_range_table.hpp) or
// the cone caster (exact, est/map/cone_ray_caster.hpp).
enum class BeamCast : std::uint8_t { table, cone };
const char* to_string(BeamCast c);  // "table", "cone"
bool parse(const std::string& s, BeamCast& out);

const char* to_string(est::loop::Filter f);  // "mcl", "ekf", "ekf-slam"
bool parse(const std::string& s, est::loop::Filter& out);

// Each model's parameters and its control assembler's configuration. Noise defaults are for 100 Hz predictions:
// per-step floors cover what the inputs do not see (slip, quantization, the encoders' scale error).
struct MotionSpec {
  est::VelocityParams velocity{0.01f, 0.001f, 0.01f, 0.01f, 0.0005f, 0.0005f, 0.01f};
  est::OdometryParams odometry{0.002f, 0.005f, 0.01f, 0.0005f, 1.0e-4f};
  est::BicycleParams bicycle{0.6f, 1.0471976f, 0.04f, 0.1f, 0.01f, 0.01f};
  est::DiffDriveParams diff_drive{0.05f, 0.3f, 4096u, 0.05f, 0.003f, 0.01f};
  est::OmniParams omni{{0.3f, 0.05f, 0.05f, 0.05f, 0.3f, 0.05f, 0.1f, 0.1f, 0.3f}, 0.01f};
  est::HolonomicPoseParams holonomic{};  // B and Q are set per step by the assembler
  est::loop::ControlAssembler<est::BicycleMotionModel>::Config bicycle_control{};
  est::loop::ControlAssembler<est::OmniMotionModel>::Config omni_control{};
  est::loop::ControlAssembler<est::HolonomicPoseMotionModel>::Config holonomic_control{
      Eigen::Matrix2f::Identity() * 0.004f, 0.002f};
};

struct EstimatorSpec {
  RobotModel model = RobotModel::diff_drive;
  est::loop::Filter filter = est::loop::Filter::mcl;
  RangeModel range_model = RangeModel::likelihood_field;
  MotionSpec motion;

  // The rangefinder: where it sits (fixed, or on the handlebar for the steered model) and its models.
  est::Pose2 sensor_mount{};
  est::loop::SteeredScanConfig steered{};
  est::LikelihoodFieldParams field{0.85f, 0.05f, 0.10f, 0.2f, 12.0f, 2.0f};
  est::BeamModelParams beam{0.80f, 0.10f, 0.05f, 0.05f, 0.2f, 0.5f, 12.0f, 0.05f};
  std::int32_t heading_bins = 64;   // the beam model's heading range table (or cone caster) on the host
  BeamCast beam_cast = BeamCast::table;
  std::int32_t beam_stride = 4;

  // MCL; the averages' rates as sim_host simulate's (sim/simulate.hpp FilterOptions: per scan).
  est::MclConfig mcl = [] {
    est::MclConfig c;
    c.alpha_slow = 0.005f;
    c.alpha_fast = 0.3f;
    return c;
  }();
  std::uint32_t particles = 1000;
  std::uint64_t seed = 1;
  float clearance_m = 0.2f;
  float cluster_cell_m = 1.0f;

  // Initial belief: global (MCL), or a Gaussian around a pose.
  bool global = false;
  est::Pose2 initial_pose{};
  float initial_sigma_xy_m = 0.2f;
  float initial_sigma_theta_rad = 0.1f;

  // EKF localization on landmark sightings.
  est::LandmarkNoise landmark_noise{0.05f, 0.02f, 0.0f};
  float landmark_sigma_range_per_m = 0.0f;  // EKF: the range noise grows by this per metre of range (a camera's)
  float ekf_rot_sigma = 0.002f;  // heading noise added per prediction (rad): what the motion model leaves out
  est::MotionProportionalNoise ekf_motion_noise{};  // EKF: noise per metre driven and per radian turned
  std::uint32_t ekf_reopen_after = 0;  // EKF: consecutive gate refusals of known features that re-open the gate
  float ekf_reopen_sigma_xy = 0.5f;
  float ekf_reopen_sigma_theta = 0.3f;
  float lost_sigma_m = 5.0f;
  bool landmark_ids = true;    // false: the sensor's landmark ids are ignored (association by maximum likelihood)
  float ambiguity_nats = 0.0f;  // EKF, maximum likelihood: refuse a feature whose runner-up is this close (nats)
  bool joint_association = false;  // EKF: features without an id associated per frame by JCBB (est/assoc/jcbb.hpp)
  float lone_pairing_sigma_m = 0.0f;  // EKF with JCBB: no lone pairing with a runner-up above this deviation (0: off)
  bool mcl_landmarks = false;  // MCL corrects with landmark sightings on the landmark map, as well as with scans

  // EKF-SLAM (est/loop/ekf_slam_estimator.hpp): the association's gates and the tentative landmarks; the landmark
  // noise, ekf_rot_sigma and lost_sigma_m above are its too.
  float slam_gate_accept = 9.21f;         // chi^2 (2 dof): associate under it
  float slam_gate_new = 30.0f;            // a new landmark above it; discarded in between
  float slam_max_range_m = 30.0f;         // features farther away are not used
  float slam_search_radius_m = 10.0f;     // candidate landmarks within this of where the feature puts it
  std::int32_t slam_confirm = 2;          // sightings in different frames before a new landmark enters the map
  float slam_candidate_radius_m = 1.0f;   // a tentative landmark's sightings agree within this
  std::uint32_t slam_candidate_frames = 10;  // a tentative landmark unseen for this many frames is forgotten
  float slam_noise_step_s = 0.0f;         // > 0: the bicycle's per-step noise is for steps this long, scaled to each

  // The loop and the HAL gate.
  est::loop::LoopTiming timing{};
  hal::InputLimits limits{};
};

// The maps the estimator runs on, owned by the caller and outliving the pipeline: the occupancy grid and its
// distance transform (MCL), the landmarks (EKF).
struct EstimatorMaps {
  est::OccupancyGrid grid;
  est::DistanceTransform edt;
  est::LandmarkMap landmarks;
  std::string description;
};

}  // namespace node
