// The team message on LCM: est::team::TeamMessage -> team_message_t -> bytes -> team_message_t -> TeamMessage is
// lossless, bit for bit, for every control kind and measurement flavour; bytes that convert convert back to the
// same bytes; counts negative or over the capacity are refused before and after decoding; truncated, padded,
// garbage or another type's payloads are refused without a crash.
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "hal/team/lcm.hpp"
#include "hal/team/validator.hpp"

using est::team::ControlKind;
using est::team::TargetKind;
using est::team::TeamMessage;
using hal::lcm::LcmReject;

namespace {

std::uint32_t bits(float x) {
  std::uint32_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

float from_bits(std::uint32_t b) {
  float x = 0.0f;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

std::vector<std::uint8_t> encode(const est_lcm::team_message_t& m) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  REQUIRE(m.encode(b.data(), 0, static_cast<int>(b.size())) == static_cast<int>(b.size()));
  return b;
}

// Every field, floats by their bits; the measurements up to the count.
void require_same(const TeamMessage& a, const TeamMessage& b) {
  CHECK(a.robot == b.robot);
  CHECK(a.seq == b.seq);
  CHECK(a.stamp_ns == b.stamp_ns);
  CHECK(a.control.kind == b.control.kind);
  CHECK(bits(a.control.dt_s) == bits(b.control.dt_s));
  CHECK(bits(a.control.v1) == bits(b.control.v1));
  CHECK(bits(a.control.v2) == bits(b.control.v2));
  CHECK(bits(a.control.w) == bits(b.control.w));
  for (int i = 0; i < est::loop::kMaxWheels; ++i) CHECK(a.control.ticks[i] == b.control.ticks[i]);
  CHECK(a.control.wheel_count == b.control.wheel_count);
  CHECK(bits(a.control.steering_rad) == bits(b.control.steering_rad));
  REQUIRE(a.count == b.count);
  for (std::int32_t i = 0; i < a.count; ++i) {
    INFO("measurement " << i);
    CHECK(a.measurements[i].target == b.measurements[i].target);
    CHECK(a.measurements[i].has_bearing == b.measurements[i].has_bearing);
    CHECK(bits(a.measurements[i].range_m) == bits(b.measurements[i].range_m));
    CHECK(bits(a.measurements[i].bearing_rad) == bits(b.measurements[i].bearing_rad));
    CHECK(a.measurements[i].id == b.measurements[i].id);
  }
}

// Through the bytes and back, as a receiver decodes them.
TeamMessage over_the_wire(const TeamMessage& t) {
  const std::vector<std::uint8_t> b = encode(hal::lcm::to_lcm(t));
  est_lcm::team_message_t m;
  REQUIRE(hal::lcm::decode_guarded(b.data(), b.size(), m, est::team::kMaxTeamMeasurements) == LcmReject::none);
  TeamMessage out;
  REQUIRE(hal::lcm::to_hal(m, out) == LcmReject::none);
  return out;
}

// The four flavours of measurement: landmark or robot, with or without bearing, known or anonymous.
TeamMessage with_every_measurement(TeamMessage m) {
  m.count = 4;
  m.measurements[0] = {TargetKind::landmark, true, 4.25f, 0.5f, 12};
  m.measurements[1] = {TargetKind::landmark, false, 7.0f, 0.0f, est::team::kAnonymous};
  m.measurements[2] = {TargetKind::robot, true, 2.5f, -3.14159274f, 2};
  m.measurements[3] = {TargetKind::robot, false, 1.0e-3f, 0.0f, est::team::kAnonymous};
  return m;
}

TeamMessage base(ControlKind kind) {
  TeamMessage m;
  m.robot = 1;
  m.seq = 0x80000001u;  // the top bit set: carried as an int32's bits
  m.stamp_ns = -1234567890123456789;
  m.control.kind = kind;
  m.control.dt_s = 0.1f;
  return m;
}

}  // namespace

TEST_CASE("every control kind and measurement flavour survives LCM bit for bit", "[team][lcm]") {
  std::vector<TeamMessage> cases;
  TeamMessage none = base(ControlKind::none);
  none.control.dt_s = 0.0f;
  cases.push_back(none);
  TeamMessage ticks = base(ControlKind::wheel_ticks);
  ticks.control.wheel_count = 4;
  ticks.control.ticks[0] = std::numeric_limits<std::int32_t>::min();
  ticks.control.ticks[1] = -7;
  ticks.control.ticks[2] = 0;
  ticks.control.ticks[3] = std::numeric_limits<std::int32_t>::max();
  ticks.control.steering_rad = -0.35f;
  cases.push_back(ticks);
  TeamMessage velocity = base(ControlKind::velocity);
  velocity.control.v1 = 0.1f;
  velocity.control.w = -1.0e-38f;  // subnormal
  cases.push_back(velocity);
  TeamMessage omni = base(ControlKind::omni);
  omni.control.v1 = 1.0f / 3.0f;
  omni.control.v2 = -0.0f;
  omni.control.w = 2.75f;
  cases.push_back(omni);
  TeamMessage holonomic = base(ControlKind::holonomic);
  holonomic.control.v1 = -0.2f;
  holonomic.control.v2 = std::numeric_limits<float>::denorm_min();
  cases.push_back(holonomic);

  hal::team::TeamValidator v(3, 0);
  for (const TeamMessage& c : cases) {
    INFO("control kind " << static_cast<int>(c.control.kind));
    for (const TeamMessage& t : {c, with_every_measurement(c)}) {
      const TeamMessage back = over_the_wire(t);
      require_same(t, back);
      CHECK(v.check(back) != est::team::TeamReject::malformed);  // what is sent well-formed arrives well-formed
    }
  }
  CHECK(bits(over_the_wire(omni).control.v2) == 0x80000000u);  // -0 stays -0
}

TEST_CASE("the full measurement capacity and bad values are carried as they are, NaN payloads included",
          "[team][lcm]") {
  TeamMessage t = base(ControlKind::omni);
  t.count = est::team::kMaxTeamMeasurements;
  for (std::int32_t i = 0; i < t.count; ++i)
    t.measurements[i] = {i % 2 ? TargetKind::robot : TargetKind::landmark, i % 3 == 0, 0.5f * static_cast<float>(i),
                         0.01f * static_cast<float>(i), i % 5 == 0 ? est::team::kAnonymous : i};
  t.control.v1 = from_bits(0x7fc01234u);  // a quiet NaN with a payload
  t.control.w = -std::numeric_limits<float>::infinity();
  t.measurements[5].range_m = from_bits(0xffc00001u);
  t.control.kind = static_cast<ControlKind>(200);          // unknown: the validator's to refuse, not the wire's
  t.measurements[7].target = static_cast<TargetKind>(9);
  t.control.wheel_count = 255;
  require_same(t, over_the_wire(t));
  hal::team::TeamValidator v(8, 0);
  CHECK(v.check(over_the_wire(t)) == est::team::TeamReject::malformed);
}

TEST_CASE("team_message_t bytes that convert convert back to the same bytes", "[team][lcm]") {
  est_lcm::team_message_t m{};
  m.robot_id = -5;
  m.seq = -1;
  m.stamp_ns = std::numeric_limits<std::int64_t>::max();
  m.control_kind = -3;
  m.dt_s = 0.05f;
  m.v1 = 1.0f;
  m.v2 = 2.0f;
  m.w = 3.0f;
  m.wheel_count = -1;
  for (int i = 0; i < 4; ++i) m.ticks[i] = 1000 * i - 1;
  m.steering_rad = 0.25f;
  m.measurements.resize(3);
  for (std::size_t i = 0; i < 3; ++i) {
    m.measurements[i].target = static_cast<std::int8_t>(i) - 1;
    m.measurements[i].has_bearing = static_cast<std::int8_t>(i % 2);
    m.measurements[i].range_m = 1.5f * static_cast<float>(i);
    m.measurements[i].bearing_rad = -0.5f;
    m.measurements[i].id = static_cast<std::int32_t>(i) - 1;
  }
  m.num_measurements = 3;
  TeamMessage t;
  REQUIRE(hal::lcm::to_hal(m, t) == LcmReject::none);
  CHECK(t.seq == 0xffffffffu);
  CHECK(t.control.wheel_count == 255u);
  CHECK(encode(hal::lcm::to_lcm(t)) == encode(m));
}

TEST_CASE("a count negative, over the capacity or not the array's length is refused", "[team][lcm]") {
  est_lcm::team_message_t m = hal::lcm::to_lcm(with_every_measurement(base(ControlKind::velocity)));
  TeamMessage t;
  m.num_measurements = -1;
  CHECK(hal::lcm::to_hal(m, t) == LcmReject::bad_count);
  m.num_measurements = 3;  // four in the array
  CHECK(hal::lcm::to_hal(m, t) == LcmReject::bad_count);
  m.measurements.resize(est::team::kMaxTeamMeasurements + 1);
  m.num_measurements = est::team::kMaxTeamMeasurements + 1;
  CHECK(hal::lcm::to_hal(m, t) == LcmReject::bad_count);

  // On the wire the guard refuses the count before anything is allocated.
  std::vector<std::uint8_t> b = encode(m);
  est_lcm::team_message_t d;
  CHECK(hal::lcm::decode_guarded(b.data(), b.size(), d, est::team::kMaxTeamMeasurements) == LcmReject::bad_count);
  b[8] = 0xff;
  b[9] = 0xff;  // -1
  CHECK(hal::lcm::decode_guarded(b.data(), b.size(), d, est::team::kMaxTeamMeasurements) == LcmReject::bad_count);
  b[8] = 0x7f;  // 32767
  CHECK(hal::lcm::decode_guarded(b.data(), b.size(), d, est::team::kMaxTeamMeasurements) == LcmReject::bad_count);

  // Sending clamps what cannot be sent.
  TeamMessage over = base(ControlKind::none);
  over.count = est::team::kMaxTeamMeasurements + 5;
  CHECK(hal::lcm::to_lcm(over).num_measurements == est::team::kMaxTeamMeasurements);
  over.count = -3;
  CHECK(hal::lcm::to_lcm(over).measurements.empty());
}

TEST_CASE("a has_bearing byte other than 0 and 1 is refused as bad_shape", "[team][lcm]") {
  est_lcm::team_message_t m = hal::lcm::to_lcm(with_every_measurement(base(ControlKind::velocity)));
  m.measurements[2].has_bearing = 2;
  TeamMessage t;
  CHECK(hal::lcm::to_hal(m, t) == LcmReject::bad_shape);
  m.measurements[2].has_bearing = -1;
  CHECK(hal::lcm::to_hal(m, t) == LcmReject::bad_shape);
}

TEST_CASE("truncated, padded, garbage and another type's payloads are refused without a crash", "[team][lcm]") {
  const std::vector<std::uint8_t> good = encode(hal::lcm::to_lcm(with_every_measurement(base(ControlKind::omni))));
  est_lcm::team_message_t m;
  for (std::size_t n = 0; n < good.size(); ++n) {
    INFO("first " << n << " bytes");
    CHECK(hal::lcm::decode_guarded(good.data(), n, m, est::team::kMaxTeamMeasurements) == LcmReject::malformed);
  }
  std::vector<std::uint8_t> padded = good;
  padded.push_back(0);
  CHECK(hal::lcm::decode_guarded(padded.data(), padded.size(), m, est::team::kMaxTeamMeasurements) ==
        LcmReject::malformed);
  std::vector<std::uint8_t> wrong_type = good;
  wrong_type[0] ^= 0x01;  // the fingerprint
  CHECK(hal::lcm::decode_guarded(wrong_type.data(), wrong_type.size(), m, est::team::kMaxTeamMeasurements) ==
        LcmReject::malformed);

  // Bytes of a good message changed at random after the fingerprint, and some cut short: every outcome is a value,
  // and what decodes converts or is refused as bad_shape.
  std::uint32_t state = 12345u;
  auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return state >> 8;
  };
  int decoded = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::vector<std::uint8_t> b = good;
    for (int k = 0; k < 1 + trial % 4; ++k) b[8 + next() % (b.size() - 8)] = static_cast<std::uint8_t>(next());
    if (trial % 5 == 0) b.resize(8 + next() % (b.size() - 8));
    const LcmReject r = hal::lcm::decode_guarded(b.data(), b.size(), m, est::team::kMaxTeamMeasurements);
    CHECK((r == LcmReject::none || r == LcmReject::malformed || r == LcmReject::bad_count));
    if (r != LcmReject::none) continue;
    ++decoded;
    TeamMessage t;
    const LcmReject c = hal::lcm::to_hal(m, t);
    CHECK((c == LcmReject::none || c == LcmReject::bad_shape));
    if (c == LcmReject::none) CHECK(encode(hal::lcm::to_lcm(t)) == b);
  }
  CHECK(decoded > 1000);
  // Garbage without the fingerprint.
  const std::uint8_t junk[7] = {0xde, 0xad, 0xbe, 0xef, 0, 1, 2};
  CHECK(hal::lcm::decode_guarded(junk, sizeof junk, m, est::team::kMaxTeamMeasurements) == LcmReject::malformed);
  CHECK(hal::lcm::decode_guarded(nullptr, 16, m, est::team::kMaxTeamMeasurements) == LcmReject::malformed);
}
