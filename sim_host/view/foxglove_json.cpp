// The live view's messages in the Foxglove WebSocket protocol (view/foxglove_json.hpp). The JSON schemas below
// describe the fields this server sends, named after Foxglove's well-known schemas so that Studio recognizes them.
#include "view/foxglove_json.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "hal/status_word.hpp"

namespace view {

using nlohmann::json;

namespace {

// --- JSON schemas -------------------------------------------------------------------------------------------------

json object(json properties) { return {{"type", "object"}, {"properties", std::move(properties)}}; }
json number() { return {{"type", "number"}}; }
json integer() { return {{"type", "integer"}}; }
json string_type() { return {{"type", "string"}}; }
json array_of(json items) { return {{"type", "array"}, {"items", std::move(items)}}; }
json time_schema() { return object({{"sec", integer()}, {"nsec", integer()}}); }
json pose_schema() {
  return object({{"position", object({{"x", number()}, {"y", number()}, {"z", number()}})},
                 {"orientation", object({{"x", number()}, {"y", number()}, {"z", number()}, {"w", number()}})}});
}
json titled(const char* title, json schema) {
  schema["title"] = title;
  return schema;
}

json grid_schema() {
  json data = string_type();
  data["contentEncoding"] = "base64";
  return titled("foxglove.Grid",
                object({{"timestamp", time_schema()},
                        {"frame_id", string_type()},
                        {"pose", pose_schema()},
                        {"column_count", integer()},
                        {"cell_size", object({{"x", number()}, {"y", number()}})},
                        {"row_stride", integer()},
                        {"cell_stride", integer()},
                        {"fields", array_of(object({{"name", string_type()},
                                                    {"offset", integer()},
                                                    {"type", integer()}}))},
                        {"data", data}}));
}
json pose_in_frame_schema() {
  return titled("foxglove.PoseInFrame",
                object({{"timestamp", time_schema()}, {"frame_id", string_type()}, {"pose", pose_schema()}}));
}
json poses_in_frame_schema() {
  // Plus the filter's particle count (the poses are every n-th of them).
  return titled("foxglove.PosesInFrame", object({{"timestamp", time_schema()},
                                                 {"frame_id", string_type()},
                                                 {"poses", array_of(pose_schema())},
                                                 {"total", integer()}}));
}
json scene_update_schema() {
  const json point = object({{"x", number()}, {"y", number()}, {"z", number()}});
  const json color = object({{"r", number()}, {"g", number()}, {"b", number()}, {"a", number()}});
  const json line = object({{"type", integer()},
                            {"pose", pose_schema()},
                            {"thickness", number()},
                            {"scale_invariant", json{{"type", "boolean"}}},
                            {"points", array_of(point)},
                            {"color", color},
                            {"colors", array_of(color)},
                            {"indices", array_of(integer())}});
  const json entity = object({{"timestamp", time_schema()},
                              {"frame_id", string_type()},
                              {"id", string_type()},
                              {"lifetime", time_schema()},
                              {"frame_locked", json{{"type", "boolean"}}},
                              {"lines", array_of(line)}});
  return titled("foxglove.SceneUpdate",
                object({{"deletions", array_of(object({{"timestamp", time_schema()}, {"type", integer()},
                                                       {"id", string_type()}}))},
                        {"entities", array_of(entity)}}));
}
json status_schema() {
  return titled("est.Status", object({{"timestamp", time_schema()},
                                      {"word", integer()},
                                      {"word_hex", string_type()},
                                      {"bits", array_of(string_type())},
                                      {"rejected_inputs", integer()},
                                      {"covariance", array_of(number())},
                                      {"view_dropped", integer()}}));
}

struct ChannelInfo {
  Channel id;
  const char* topic;
  const char* schema_name;
  json (*schema)();
};
constexpr ChannelInfo kInfo[] = {
    {Channel::map, "/map", "foxglove.Grid", grid_schema},
    {Channel::truth, "/truth", "foxglove.PoseInFrame", pose_in_frame_schema},
    {Channel::estimate, "/estimate", "foxglove.PoseInFrame", pose_in_frame_schema},
    {Channel::ellipse, "/estimate/ellipse", "foxglove.SceneUpdate", scene_update_schema},
    {Channel::particles, "/particles", "foxglove.PosesInFrame", poses_in_frame_schema},
    {Channel::status, "/status", "est.Status", status_schema},
};

// --- messages -----------------------------------------------------------------------------------------------------

json stamp(TimeNs ns) {
  if (ns < 0) ns = 0;
  return {{"sec", ns / 1000000000}, {"nsec", ns % 1000000000}};
}
json pose(double x, double y, double theta) {
  return {{"position", {{"x", x}, {"y", y}, {"z", 0.0}}},
          {"orientation", {{"x", 0.0}, {"y", 0.0}, {"z", std::sin(theta / 2.0)}, {"w", std::cos(theta / 2.0)}}}};
}
// Floats as sent: 6 significant digits are a tenth of a millimetre on a 100 m map, and keep the messages small.
double rounded(double v) { return std::isfinite(v) ? std::round(v * 1.0e5) / 1.0e5 : 0.0; }

std::string base64(const std::vector<std::uint8_t>& in) {
  static const char k[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (unsigned{in[i]} << 16) | (unsigned{in[i + 1]} << 8) | in[i + 2];
    out += {k[v >> 18], k[(v >> 12) & 63u], k[(v >> 6) & 63u], k[v & 63u]};
  }
  if (i + 1 == in.size()) {
    const unsigned v = unsigned{in[i]} << 16;
    out += {k[v >> 18], k[(v >> 12) & 63u], '=', '='};
  } else if (i + 2 == in.size()) {
    const unsigned v = (unsigned{in[i]} << 16) | (unsigned{in[i + 1]} << 8);
    out += {k[v >> 18], k[(v >> 12) & 63u], k[(v >> 6) & 63u], '='};
  }
  return out;
}

}  // namespace

std::string advertise_json(int team_robots) {
  json channels = json::array();
  const auto add = [&channels](std::uint32_t id, const std::string& topic, const char* schema_name, json schema) {
    channels.push_back({{"id", id},
                        {"topic", topic},
                        {"encoding", "json"},
                        {"schemaName", schema_name},
                        {"schema", schema.dump()},
                        {"schemaEncoding", "jsonschema"}});
  };
  if (team_robots <= 0) {
    for (const ChannelInfo& c : kInfo) add(static_cast<std::uint32_t>(c.id), c.topic, c.schema_name, c.schema());
  } else {
    for (int a = 0; a < team_robots; ++a) {
      const std::string r = "/robot" + std::to_string(a);
      add(team_channel(a, 0), r + "/truth", "foxglove.PoseInFrame", pose_in_frame_schema());
      add(team_channel(a, 1), r + "/estimate", "foxglove.PoseInFrame", pose_in_frame_schema());
      add(team_channel(a, 2), r + "/estimate/ellipse", "foxglove.SceneUpdate", scene_update_schema());
    }
    add(kLandmarksChannel, "/landmarks", "foxglove.SceneUpdate", scene_update_schema());
    add(static_cast<std::uint32_t>(Channel::status), "/status", "est.Status", status_schema());
  }
  return json{{"op", "advertise"}, {"channels", channels}}.dump();
}

std::vector<std::uint32_t> advertised_ids(int team_robots) {
  std::vector<std::uint32_t> ids;
  if (team_robots <= 0) {
    for (const ChannelInfo& c : kInfo) ids.push_back(static_cast<std::uint32_t>(c.id));
    return ids;
  }
  for (int a = 0; a < team_robots; ++a)
    for (int w = 0; w < 3; ++w) ids.push_back(team_channel(a, w));
  ids.push_back(kLandmarksChannel);
  ids.push_back(static_cast<std::uint32_t>(Channel::status));
  return ids;
}

std::string server_info_json(const std::string& name) {
  return json{{"op", "serverInfo"}, {"name", name}, {"capabilities", json::array()}}.dump();
}

std::string status_json(int level, const std::string& message) {
  return json{{"op", "status"}, {"level", level}, {"message", message}}.dump();
}

std::string map_json(const MapGrid& m) {
  return json{{"timestamp", stamp(0)},
              {"frame_id", kFrame},
              {"pose", pose(m.origin_x, m.origin_y, 0.0)},
              {"column_count", m.width},
              {"cell_size", {{"x", m.resolution_m}, {"y", m.resolution_m}}},
              {"row_stride", m.width},
              {"cell_stride", 1},
              {"fields", {{{"name", "occupancy"}, {"offset", 0}, {"type", 1}}}},  // 1: UINT8
              {"data", base64(m.cells)}}
      .dump();
}

std::string pose_json(TimeNs stamp_ns, const Pose& p) {
  return json{{"timestamp", stamp(stamp_ns)},
              {"frame_id", kFrame},
              {"pose", pose(rounded(p.x), rounded(p.y), p.theta)}}
      .dump();
}

namespace {
json ellipse_entity(const EstimateSample& e, const std::string& id, double r, double g, double b) {
  const std::vector<double> xy = ellipse_points(e, 36);
  json points = json::array();
  for (std::size_t i = 0; i + 1 < xy.size(); i += 2)
    points.push_back({{"x", rounded(xy[i])}, {"y", rounded(xy[i + 1])}, {"z", 0.02}});
  const json line = {{"type", 1},  // LINE_LOOP
                     {"pose", pose(0.0, 0.0, 0.0)},
                     {"thickness", 2.0},
                     {"scale_invariant", true},
                     {"points", points},
                     {"color", {{"r", r}, {"g", g}, {"b", b}, {"a", 1.0}}},
                     {"colors", json::array()},
                     {"indices", json::array()}};
  return {{"timestamp", stamp(e.stamp_ns)}, {"frame_id", kFrame},    {"id", id},
                       {"lifetime", stamp(0)},          {"frame_locked", false}, {"metadata", json::array()},
                       {"arrows", json::array()},       {"cubes", json::array()}, {"spheres", json::array()},
                       {"cylinders", json::array()},    {"lines", {line}},        {"triangles", json::array()},
                       {"texts", json::array()},        {"models", json::array()}};
}
}  // namespace

std::string ellipse_json(const EstimateSample& e) {
  return json{{"deletions", json::array()}, {"entities", {ellipse_entity(e, "estimate_2sigma", 0.9, 0.1, 0.1)}}}.dump();
}

std::string landmarks_json(const LandmarkSet& l) {
  json entities = json::array();
  for (const LandmarkSample& m : l.landmarks) {
    EstimateSample e;
    e.stamp_ns = l.stamp_ns;
    e.pose = {m.x, m.y, 0.0};
    e.covariance[0] = m.covariance[0];
    e.covariance[1] = m.covariance[1];
    e.covariance[3] = m.covariance[2];
    e.covariance[4] = m.covariance[3];
    entities.push_back(ellipse_entity(e, "landmark_" + std::to_string(m.id), 0.5, 0.3, 0.1));
  }
  return json{{"deletions", json::array()}, {"entities", entities}}.dump();
}

std::string particles_json(const ParticleCloud& c) {
  json poses = json::array();
  for (std::size_t i = 0; i < c.xs.size(); ++i)
    poses.push_back(pose(rounded(c.xs[i]), rounded(c.ys[i]), static_cast<double>(c.thetas[i])));
  return json{{"timestamp", stamp(c.stamp_ns)}, {"frame_id", kFrame}, {"poses", poses}, {"total", c.total}}.dump();
}

std::string status_json(const EstimateSample& e, std::uint64_t dropped) {
  char hex[16];
  std::snprintf(hex, sizeof hex, "0x%08x", e.status);
  json cov = json::array();
  for (double v : e.covariance) cov.push_back(std::isfinite(v) ? v : 0.0);
  return json{{"timestamp", stamp(e.stamp_ns)},
              {"word", e.status},
              {"word_hex", hex},
              {"bits", status_bit_names(e.status)},
              {"rejected_inputs", e.rejected_inputs},
              {"covariance", cov},
              {"view_dropped", dropped}}
      .dump();
}

std::vector<std::string> status_bit_names(std::uint32_t word) {
  namespace s = hal::status;
  static const std::pair<std::uint32_t, const char*> kBits[] = {
      {s::kEncoderTimeout, "encoder_timeout"},     {s::kSteeringTimeout, "steering_timeout"},
      {s::kScanTimeout, "scan_timeout"},           {s::kInputRejected, "input_rejected"},
      {s::kFilterDegenerate, "filter_degenerate"}, {s::kDeadlineOverrun, "deadline_overrun"},
      {s::kNotInitialized, "not_initialized"},     {s::kInputTooOld, "input_too_old"},
      {s::kQueueFull, "queue_full"},               {s::kLandmarkTimeout, "landmark_timeout"},
      {s::kTwistTimeout, "twist_timeout"},         {s::kOdometryTimeout, "odometry_timeout"},
      {s::kTeamRobotMissing, "team_robot_missing"}, {s::kCanLinkDown, "can_link_down"},
      {s::kCanBusOff, "can_bus_off"},              {s::kCanErrorPassive, "can_error_passive"},
      {s::kCanErrorWarning, "can_error_warning"},  {s::kCanRxOverflow, "can_rx_overflow"},
      {s::kCanTxFailed, "can_tx_failed"},          {s::kCanProtocolError, "can_protocol_error"},
      {s::kLcmDecodeError, "lcm_decode_error"}};
  std::vector<std::string> names;
  std::uint32_t named = 0;
  for (const auto& [bit, name] : kBits) {
    named |= bit;
    if ((word & bit) != 0u) names.emplace_back(name);
  }
  for (int b = 0; b < 32; ++b)
    if ((word & ~named & (1u << b)) != 0u) names.push_back("bit_" + std::to_string(b));
  return names;
}

std::vector<double> ellipse_points(const EstimateSample& e, int n) {
  // Principal axes of the 2x2 position block: eigenvalues of [[a, b], [b, c]], the major axis at angle phi.
  // A covariance with non-finite entries draws as a point rather than NaNs.
  const auto finite = [](double v) { return std::isfinite(v) ? v : 0.0; };
  const double a = finite(e.covariance[0]), b = finite(0.5 * (e.covariance[1] + e.covariance[3])),
               c = finite(e.covariance[4]);
  const double mean = 0.5 * (a + c), half_diff = 0.5 * (a - c);
  const double r = std::sqrt(half_diff * half_diff + b * b);
  const double l1 = std::max(0.0, mean + r), l2 = std::max(0.0, mean - r);
  const double phi = 0.5 * std::atan2(2.0 * b, a - c);
  const double s1 = 2.0 * std::sqrt(l1), s2 = 2.0 * std::sqrt(l2);
  std::vector<double> xy;
  xy.reserve(static_cast<std::size_t>(2 * n));
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * M_PI * i / n;
    const double u = s1 * std::cos(t), v = s2 * std::sin(t);
    xy.push_back(e.pose.x + u * std::cos(phi) - v * std::sin(phi));
    xy.push_back(e.pose.y + u * std::sin(phi) + v * std::cos(phi));
  }
  return xy;
}

}  // namespace view
