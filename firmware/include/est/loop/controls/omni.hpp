#pragma once
// Omnidirectional base: (v1, v2, w) over dt, from the twist (commanded or measured) or from the encoders of its
// three or four wheels (est/motion/omni_wheels.hpp: the body displacement of the tick increments, over dt).
#include "est/loop/control_assembler.hpp"
#include "est/motion/omni_model.hpp"
#include "est/motion/omni_wheels.hpp"

namespace est::loop {

template <>
struct ControlAssembler<OmniMotionModel> {
  enum class Source : std::uint8_t { twist, wheels };
  struct Config {
    Source source = Source::twist;
    OmniWheels wheels{};  // with Source::wheels (configure_omni_wheels)
  };
  static InputKinds inputs(const Config& c) {
    return c.source == Source::wheels ? InputKind::wheel_ticks : InputKind::twist;
  }
  static ControlStatus make(const MotionInput& m, const Config& c, OmniParams& p, OmniControl& u) {
    if (c.source == Source::twist) {
      if (!m.twist_known || (m.twist.v1_mps == 0.0f && m.twist.v2_mps == 0.0f && m.twist.w_rps == 0.0f))
        return ControlStatus::still;
      if (!(m.dt_s > 0.0f)) return ControlStatus::rejected;
      u = {m.twist.v1_mps, m.twist.v2_mps, m.twist.w_rps};
    } else {
      bool moved = false;
      for (std::int32_t i = 0; i < kMaxWheels; ++i) moved = moved || m.ticks[i] != 0;
      if (!moved) return ControlStatus::still;
      if (c.wheels.count < 3u || m.wheel_count != c.wheels.count || !(m.dt_s > 0.0f)) return ControlStatus::rejected;
      const Eigen::Vector3f d = omni_body_displacement(c.wheels, m.ticks);
      u = {d(0) / m.dt_s, d(1) / m.dt_s, d(2) / m.dt_s};
    }
    p.dt = m.dt_s;
    return ControlStatus::ok;
  }
};

}  // namespace est::loop
