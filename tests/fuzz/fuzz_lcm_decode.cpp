// libFuzzer target: any payload decoded as each est_lcm type through the guarded decoder, converted to HAL types
// and judged by the HAL validators (twists and odometry poses included, team messages by the team validator). A
// payload that decodes re-encodes to the same bytes (LCM is canonical).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "hal/lcm/lcm_convert.hpp"
#include "hal/team/validator.hpp"
#include "hal/validated_inputs.hpp"

using hal::lcm::LcmReject;

namespace {

struct Clock final : hal::Clock {
  hal::TimeNs now = 0;
  hal::TimeNs now_ns() override { return now; }
};

// What passes the gate, checked per sample.
struct Sink final : hal::PortImplementation<Sink, hal::ValidatedSensorPort> {
  void handle(const hal::WheelTickDelta& d) {
    if (d.wheel_count > hal::kMaxWheels) __builtin_trap();
  }
  void handle(const hal::SteeringSample& s) {
    if (!__builtin_isfinite(s.angle_rad)) __builtin_trap();
  }
  void handle(const hal::TwistSample& s) {
    if (!__builtin_isfinite(s.v1_mps) || !__builtin_isfinite(s.v2_mps) || !__builtin_isfinite(s.w_rps)) __builtin_trap();
  }
  void handle(const hal::OdometryDelta& d) {
    if (!d.increment.is_finite() || d.dt_ns < 0) __builtin_trap();
  }
  void handle(const hal::RangeScanView& s) {
    if (!__builtin_isfinite(s.geometry.angle_increment_rad)) __builtin_trap();
  }
  void handle(const hal::LandmarkSightingView& s) {
    for (std::size_t i = 0; i < s.count; ++i)
      if (!__builtin_isfinite(s.features[i].range_m) || !(s.features[i].range_m > 0.0f)) __builtin_trap();
  }
};

bool g_prefix_fingerprint = false;

template <typename M>
bool decode_and_check(const std::uint8_t* raw, std::size_t raw_size, M& m, std::int64_t max_count) {
  // Half the inputs get the type's fingerprint in front, so the fuzzer spends its time past the hash check.
  std::vector<std::uint8_t> buf;
  if (g_prefix_fingerprint) {
    const std::uint64_t hash = static_cast<std::uint64_t>(M::getHash());
    for (int i = 7; i >= 0; --i) buf.push_back(static_cast<std::uint8_t>(hash >> (8 * i)));
  }
  buf.insert(buf.end(), raw, raw + raw_size);
  const std::uint8_t* data = buf.data();
  const std::size_t size = buf.size();
  if (hal::lcm::decode_guarded(data, size, m, max_count) != LcmReject::none) return false;
  std::vector<std::uint8_t> again(static_cast<std::size_t>(m.getEncodedSize()));
  if (m.encode(again.data(), 0, static_cast<int>(again.size())) != static_cast<int>(size) ||
      std::memcmp(again.data(), data, size) != 0)
    __builtin_trap();
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static Clock clock;
  static Sink sink;
  static hal::ValidatedInputs gate(hal::InputLimits{}, clock, sink);
  const std::uint8_t which = data[0] % 11;
  g_prefix_fingerprint = (data[0] & 0x80) != 0;
  ++data;
  --size;
  clock.now += 1000000;
  switch (which) {
    case 0: {
      est_lcm::encoder_ticks_t m;
      hal::WheelTicks w;
      if (decode_and_check(data, size, m, 4) && hal::lcm::to_hal(m, 16, w) == LcmReject::none)
        gate.on(w);
      break;
    }
    case 1: {
      est_lcm::steering_t m;
      if (decode_and_check(data, size, m, 0)) gate.on(hal::lcm::to_hal(m));
      break;
    }
    case 2: {
      est_lcm::range_scan_t m;
      hal::RangeScanView v;
      if (decode_and_check(data, size, m, 2048) && hal::lcm::to_hal(m, v) == LcmReject::none) gate.on(v);
      break;
    }
    case 3: {
      // The conversion is lossless (what it accepts converts back to the same bytes); the validator takes anything.
      est_lcm::team_message_t m;
      static est::team::TeamMessage t;
      static hal::team::TeamValidator team(est::team::kMaxTeamRobots, 0);
      if (decode_and_check(data, size, m, est::team::kMaxTeamMeasurements) &&
          hal::lcm::to_hal(m, t) == LcmReject::none) {
        const est_lcm::team_message_t back = hal::lcm::to_lcm(t);
        std::vector<std::uint8_t> a(static_cast<std::size_t>(m.getEncodedSize()));
        std::vector<std::uint8_t> b(static_cast<std::size_t>(back.getEncodedSize()));
        (void)m.encode(a.data(), 0, static_cast<int>(a.size()));
        (void)back.encode(b.data(), 0, static_cast<int>(b.size()));
        if (a != b) __builtin_trap();
        if (hal::team::TeamValidator::accepted(team.check(t)) &&
            (t.count < 0 || t.count > est::team::kMaxTeamMeasurements || t.robot < 1 ||
             t.robot >= est::team::kMaxTeamRobots))
          __builtin_trap();
      }
      break;
    }
    case 4: {
      est_lcm::pose_estimate_t m;
      if (decode_and_check(data, size, m, 0)) (void)hal::lcm::to_hal(m);
      break;
    }
    case 5: {
      est_lcm::status_t m;
      (void)decode_and_check(data, size, m, 64);
      break;
    }
    case 6: {
      est_lcm::particle_cloud_t m;
      (void)decode_and_check(data, size, m, 100000);
      break;
    }
    case 7: {
      est_lcm::landmark_sighting_t m;
      static hal::LandmarkSighting<hal::kMaxLandmarkFeatures> sighting;
      if (decode_and_check(data, size, m, static_cast<std::int64_t>(hal::kMaxLandmarkFeatures)) &&
          hal::lcm::to_hal(m, sighting) == LcmReject::none)
        gate.on(sighting.view());
      break;
    }
    case 8: {
      est_lcm::twist_t m;
      if (decode_and_check(data, size, m, 0)) gate.on(hal::lcm::to_hal(m));
      break;
    }
    case 9: {
      est_lcm::odometry_t m;
      if (decode_and_check(data, size, m, 0)) gate.on(hal::lcm::to_hal(m));
      break;
    }
    default: {
      est_lcm::ground_truth_t m;
      (void)decode_and_check(data, size, m, 0);
      break;
    }
  }
  return 0;
}
