#pragma once
// The live view's messages as the Foxglove WebSocket protocol carries them (subprotocol foxglove.websocket.v1,
// encoding "json", schemas in "jsonschema"): Foxglove's well-known schemas where one fits, so that Foxglove Studio's
// 3D panel draws them, and the project's own where none does (host only).
//
//   /map               foxglove.Grid          the occupancy grid, uint8 percent (255 unknown), once per subscriber
//   /truth             foxglove.PoseInFrame   the ground truth, when the input carries it
//   /estimate          foxglove.PoseInFrame   the estimate's pose
//   /estimate/ellipse  foxglove.SceneUpdate   its 2-sigma position ellipse (a line loop); Foxglove has no pose-with-
//                                             covariance schema, so the covariance itself rides on /status
//   /particles         foxglove.PosesInFrame  MCL's particles, decimated, ~10 Hz
//   /status            est.Status             the status word and its bits by name, the covariance, rejects
// Every message is in frame "map" and stamped with the estimator's time.
//
// A team's view (estimator_node --filter coop-ekf, view/live_view.hpp with team_robots > 0) has instead, per robot a,
//   /robot<a>/truth            foxglove.PoseInFrame   robot a's ground truth, when the input carries it
//   /robot<a>/estimate         foxglove.PoseInFrame   the node's estimate of robot a (point robots: heading 0)
//   /robot<a>/estimate/ellipse foxglove.SceneUpdate   its 2-sigma ellipse
// and /landmarks (foxglove.SceneUpdate: every mapped landmark's 2-sigma ellipse, entity id "landmark_<id>", ~10 Hz)
// and /status (est.Status: the team estimator's status word and the node's own robot's covariance).
#include <cstdint>
#include <string>
#include <vector>

namespace view {

using TimeNs = std::int64_t;

inline constexpr const char* kSubprotocol = "foxglove.websocket.v1";
inline constexpr const char* kFrame = "map";

enum class Channel : std::uint32_t { map = 1, truth, estimate, ellipse, particles, status };
inline constexpr Channel kChannels[] = {Channel::map,     Channel::truth,     Channel::estimate,
                                        Channel::ellipse, Channel::particles, Channel::status};

struct Pose {
  double x = 0.0, y = 0.0, theta = 0.0;
};

// An occupancy grid, row-major from the bottom row (cy = 0 at origin_y), cells in percent or 255 (unknown).
struct MapGrid {
  std::int32_t width = 0, height = 0;
  double resolution_m = 0.0, origin_x = 0.0, origin_y = 0.0;
  std::vector<std::uint8_t> cells;
};

struct EstimateSample {
  TimeNs stamp_ns = 0;
  Pose pose;
  double covariance[9] = {};  // (x, y, theta), row-major
  std::uint32_t status = 0;
  std::uint32_t rejected_inputs = 0;
};

struct ParticleCloud {
  TimeNs stamp_ns = 0;
  std::uint32_t total = 0;  // in the filter; xs.size() of them are sent
  std::vector<float> xs, ys, thetas;
};

// A team view's channel ids: /status keeps Channel::status; robot a's truth, estimate and ellipse are
// team_channel(a, 0..2).
inline constexpr std::uint32_t kLandmarksChannel = 7;
inline constexpr std::uint32_t team_channel(int robot, int which) {
  return 16u + 3u * static_cast<std::uint32_t>(robot) + static_cast<std::uint32_t>(which);
}

struct LandmarkSample {
  std::int32_t id = 0;
  double x = 0.0, y = 0.0;
  double covariance[4] = {};  // (x, y), row-major
};

struct LandmarkSet {
  TimeNs stamp_ns = 0;
  std::vector<LandmarkSample> landmarks;
};

// The advertise message for every channel (ids are the Channel values), or a team's (team_robots > 0).
std::string advertise_json(int team_robots = 0);
// The ids advertise_json(team_robots) advertises.
std::vector<std::uint32_t> advertised_ids(int team_robots);
// The server's info message.
std::string server_info_json(const std::string& name);
// A status message (level 0 info, 1 warning, 2 error).
std::string status_json(int level, const std::string& message);

std::string map_json(const MapGrid& m);
std::string pose_json(TimeNs stamp_ns, const Pose& p);
std::string ellipse_json(const EstimateSample& e);
std::string landmarks_json(const LandmarkSet& l);
std::string particles_json(const ParticleCloud& c);
std::string status_json(const EstimateSample& e, std::uint64_t dropped);

// The status word's bits by name (hal/status_word.hpp), lowest first.
std::vector<std::string> status_bit_names(std::uint32_t word);

// The 2-sigma ellipse of the position covariance as `n` points round it (x, y interleaved).
std::vector<double> ellipse_points(const EstimateSample& e, int n);

}  // namespace view
