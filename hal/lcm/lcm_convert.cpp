// LCM <-> HAL conversions and the guarded decoder (hal/lcm/lcm_convert.hpp).
#include "hal/lcm/lcm_convert.hpp"

#include <exception>

namespace hal::lcm {

namespace {

// Width of the array count each type declares first (0: no arrays).
template <typename M> struct LeadingCount { static constexpr int bytes = 0; };
template <> struct LeadingCount<est_lcm::encoder_ticks_t> { static constexpr int bytes = 2; };
template <> struct LeadingCount<est_lcm::range_scan_t> { static constexpr int bytes = 4; };
template <> struct LeadingCount<est_lcm::particle_cloud_t> { static constexpr int bytes = 4; };
template <> struct LeadingCount<est_lcm::status_t> { static constexpr int bytes = 2; };
template <> struct LeadingCount<est_lcm::team_message_t> { static constexpr int bytes = 2; };
template <> struct LeadingCount<est_lcm::landmark_sighting_t> { static constexpr int bytes = 2; };

// Big-endian signed integer of `bytes` bytes after the 8-byte type fingerprint.
bool read_leading_count(const unsigned char* p, std::size_t size, int bytes, std::int64_t& count) {
  if (size < static_cast<std::size_t>(8 + bytes)) return false;
  std::uint32_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[8 + i];
  count = bytes == 2 ? static_cast<std::int64_t>(static_cast<std::int16_t>(v))
                     : static_cast<std::int64_t>(static_cast<std::int32_t>(v));
  return true;
}


}  // namespace

const char* to_string(LcmReject r) {
  switch (r) {
    case LcmReject::none: return "none";
    case LcmReject::malformed: return "malformed";
    case LcmReject::bad_count: return "bad_count";
    case LcmReject::bad_shape: return "bad_shape";
    case LcmReject::bad_value: return "bad_value";
    case LcmReject::kCount: break;
  }
  return "unknown";
}

template <typename Message>
LcmReject decode_guarded(const void* data, std::size_t size, Message& msg, std::int64_t max_count) {
  if (data == nullptr || size > 0x7fffffffu) return LcmReject::malformed;
  constexpr int count_bytes = LeadingCount<Message>::bytes;
  if (count_bytes > 0) {
    std::int64_t n = 0;
    if (!read_leading_count(static_cast<const unsigned char*>(data), size, count_bytes, n)) return LcmReject::malformed;
    if (n < 0 || n > max_count) return LcmReject::bad_count;
  }
  // The later counts of status_t are not bounded above; a negative one makes lcm-gen's resize() throw.
  try {
    const int used = msg.decode(data, 0, static_cast<int>(size));
    if (used < 0 || static_cast<std::size_t>(used) != size) return LcmReject::malformed;
  } catch (const std::exception&) {
    return LcmReject::malformed;
  }
  return LcmReject::none;
}

template LcmReject decode_guarded(const void*, std::size_t, est_lcm::encoder_ticks_t&, std::int64_t);
template LcmReject decode_guarded(const void*, std::size_t, est_lcm::steering_t&, std::int64_t);
template LcmReject decode_guarded(const void*, std::size_t, est_lcm::range_scan_t&, std::int64_t);
template LcmReject decode_guarded(const void*, std::size_t, est_lcm::pose_estimate_t&, std::int64_t);
template LcmReject decode_guarded(const void*, std::size_t, est_lcm::particle_cloud_t&, std::int64_t);
template LcmReject decode_guarded(const void*, std::size_t, est_lcm::status_t&, std::int64_t);
template LcmReject decode_guarded(const void*, std::size_t, est_lcm::ground_truth_t&, std::int64_t);
template LcmReject decode_guarded(const void*, std::size_t, est_lcm::team_message_t&, std::int64_t);
template LcmReject decode_guarded(const void*, std::size_t, est_lcm::landmark_sighting_t&, std::int64_t);

LcmReject to_hal(const est_lcm::encoder_ticks_t& m, unsigned expected_counter_bits, WheelTicks& out) {
  if (m.num_wheels < 1 || static_cast<std::size_t>(m.num_wheels) > kMaxWheels ||
      m.count.size() != static_cast<std::size_t>(m.num_wheels))
    return LcmReject::bad_count;
  if (m.counter_bits < 1 || m.counter_bits > 32 || static_cast<unsigned>(m.counter_bits) != expected_counter_bits)
    return LcmReject::bad_shape;
  out = WheelTicks{};
  out.stamp_ns = m.stamp_ns;
  out.wheel_count = static_cast<std::uint8_t>(m.num_wheels);
  for (std::size_t i = 0; i < out.wheel_count; ++i) out.count[i] = static_cast<std::uint32_t>(m.count[i]);
  return LcmReject::none;
}

SteeringSample to_hal(const est_lcm::steering_t& m) { return {m.stamp_ns, m.angle_rad}; }

LcmReject to_hal(const est_lcm::range_scan_t& m, RangeScanView& out) {
  if (m.num_ranges < 0 || m.ranges_m.size() != static_cast<std::size_t>(m.num_ranges)) return LcmReject::bad_count;
  out.stamp_ns = m.stamp_ns;
  out.geometry = {m.angle_min_rad, m.angle_increment_rad, m.range_min_m, m.range_max_m, m.scan_time_s};
  out.ranges = m.ranges_m.data();
  out.count = m.ranges_m.size();
  return LcmReject::none;
}

LcmReject to_hal(const est_lcm::team_message_t& m, TeamMessage& out, Fault& content) {
  content = Fault::none;
  if (m.num_measurements < 0 || static_cast<std::size_t>(m.num_measurements) > kMaxTeamMeasurements ||
      m.measurements.size() != static_cast<std::size_t>(m.num_measurements))
    return LcmReject::bad_count;
  out.stamp_ns = m.stamp_ns;
  out.robot_id = m.robot_id;
  out.v_mps = m.v_mps;
  out.omega_rps = m.omega_rps;
  out.dt_s = m.dt_s;
  out.count = m.measurements.size();
  for (std::size_t i = 0; i < out.count; ++i) {
    const est_lcm::team_measurement_t& z = m.measurements[i];
    if (z.type != est_lcm::team_measurement_t::LANDMARK && z.type != est_lcm::team_measurement_t::ROBOT)
      return LcmReject::bad_shape;
    out.measurements[i] = {z.type == est_lcm::team_measurement_t::ROBOT ? TeamTarget::robot : TeamTarget::landmark,
                           z.range_m, z.bearing_rad, z.target_id};
  }
  content = check_team_message(out);
  return content == Fault::none ? LcmReject::none : LcmReject::bad_value;
}

LcmReject to_hal(const est_lcm::landmark_sighting_t& m, LandmarkSighting<kMaxLandmarkFeatures>& out) {
  const auto n = static_cast<std::size_t>(m.num_features < 0 ? 0 : m.num_features);
  if (m.num_features < 0 || n > kMaxLandmarkFeatures || m.range_m.size() != n || m.bearing_rad.size() != n ||
      m.signature.size() != n || m.id.size() != n)
    return LcmReject::bad_count;
  out.stamp_ns = m.stamp_ns;
  out.count = n;
  for (std::size_t i = 0; i < n; ++i) out.features[i] = {m.range_m[i], m.bearing_rad[i], m.signature[i], m.id[i]};
  return LcmReject::none;
}

est_lcm::landmark_sighting_t to_lcm(const LandmarkSightingView& s) {
  est_lcm::landmark_sighting_t m{};
  m.stamp_ns = s.stamp_ns;
  const std::size_t n = s.count < kMaxLandmarkFeatures ? s.count : kMaxLandmarkFeatures;
  for (std::size_t i = 0; i < n; ++i) {
    m.range_m.push_back(s.features[i].range_m);
    m.bearing_rad.push_back(s.features[i].bearing_rad);
    m.signature.push_back(s.features[i].signature);
    m.id.push_back(s.features[i].id);
  }
  m.num_features = static_cast<std::int16_t>(n);
  return m;
}

est_lcm::encoder_ticks_t to_lcm(const WheelTicks& s, unsigned counter_bits) {
  est_lcm::encoder_ticks_t m{};
  m.num_wheels = static_cast<std::int16_t>(s.wheel_count);
  m.stamp_ns = s.stamp_ns;
  m.counter_bits = static_cast<std::int8_t>(counter_bits);
  for (std::size_t i = 0; i < s.wheel_count && i < kMaxWheels; ++i)
    m.count.push_back(static_cast<std::int32_t>(s.count[i]));
  m.num_wheels = static_cast<std::int16_t>(m.count.size());
  return m;
}

est_lcm::steering_t to_lcm(const SteeringSample& s) {
  est_lcm::steering_t m{};
  m.stamp_ns = s.stamp_ns;
  m.angle_rad = s.angle_rad;
  return m;
}

est_lcm::range_scan_t to_lcm(const RangeScanView& s) {
  est_lcm::range_scan_t m{};
  m.stamp_ns = s.stamp_ns;
  m.angle_min_rad = s.geometry.angle_min_rad;
  m.angle_increment_rad = s.geometry.angle_increment_rad;
  m.range_min_m = s.geometry.range_min_m;
  m.range_max_m = s.geometry.range_max_m;
  m.scan_time_s = s.geometry.scan_time_s;
  if (s.ranges != nullptr) m.ranges_m.assign(s.ranges, s.ranges + s.count);
  m.num_ranges = static_cast<std::int32_t>(m.ranges_m.size());
  return m;
}

est_lcm::team_message_t to_lcm(const TeamMessage& t) {
  est_lcm::team_message_t m{};
  m.stamp_ns = t.stamp_ns;
  m.robot_id = t.robot_id;
  m.v_mps = t.v_mps;
  m.omega_rps = t.omega_rps;
  m.dt_s = t.dt_s;
  for (std::size_t i = 0; i < t.count && i < kMaxTeamMeasurements; ++i) {
    est_lcm::team_measurement_t z;
    z.type = t.measurements[i].type == TeamTarget::robot ? est_lcm::team_measurement_t::ROBOT
                                                          : est_lcm::team_measurement_t::LANDMARK;
    z.range_m = t.measurements[i].range_m;
    z.bearing_rad = t.measurements[i].bearing_rad;
    z.target_id = t.measurements[i].target_id;
    m.measurements.push_back(z);
  }
  m.num_measurements = static_cast<std::int16_t>(m.measurements.size());
  return m;
}

est_lcm::pose_estimate_t to_lcm(const Estimate& e) {
  est_lcm::pose_estimate_t m{};
  m.stamp_ns = e.stamp_ns;
  m.x_m = e.pose.x;
  m.y_m = e.pose.y;
  m.theta_rad = e.pose.theta;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.covariance[3 * r + c] = e.covariance(r, c);
  m.status = static_cast<std::int32_t>(e.status);
  m.rejected_inputs = static_cast<std::int32_t>(e.rejected_inputs > 0x7fffffffu ? 0x7fffffffu : e.rejected_inputs);
  return m;
}

Estimate to_hal(const est_lcm::pose_estimate_t& m) {
  Estimate e;
  e.stamp_ns = m.stamp_ns;
  e.pose = {m.x_m, m.y_m, m.theta_rad};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) e.covariance(r, c) = m.covariance[3 * r + c];
  e.status = static_cast<std::uint32_t>(m.status);
  e.rejected_inputs = static_cast<std::uint32_t>(m.rejected_inputs < 0 ? 0 : m.rejected_inputs);
  return e;
}

}  // namespace hal::lcm
