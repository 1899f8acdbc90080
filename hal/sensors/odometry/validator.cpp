// The odometry validator (hal/sensors/odometry/validator.hpp).
#include "hal/sensors/odometry/validator.hpp"

#include "est/math/fmath.hpp"

namespace hal {

namespace {
// a - b on a circle of period p (p = 0: no wrap).
float wrapped_difference(float a, float b, float p) {
  float d = a - b;
  if (p > 0.0f) {
    d -= p * __builtin_floorf(d / p + 0.5f);
  }
  return d;
}
}  // namespace

Fault OdometryValidator::check(const OdometrySample& s, TimeNs now_ns, OdometryDelta& out) {
  if (!s.pose.is_finite() || !__builtin_isfinite(s.wrap_m)) return reject(Fault::not_finite);
  const float lim = limits_.max_coordinate_m;
  if (!(s.pose.x <= lim && s.pose.x >= -lim && s.pose.y <= lim && s.pose.y >= -lim) || s.wrap_m < 0.0f ||
      s.pose.theta > 7.0f || s.pose.theta < -7.0f)
    return reject(Fault::out_of_range);
  const Fault t = timing_.check(s.stamp_ns, now_ns);
  if (t != Fault::none) return reject(t);

  out = OdometryDelta{};
  out.stamp_ns = s.stamp_ns;
  out.source = s;
  if (!timing_.has_last() || s.stamp_ns - timing_.last_ns() > limits_.max_gap_ns || s.wrap_m != last_.wrap_m) {
    timing_.accept(s.stamp_ns);
    last_ = s;
    return Fault::none;
  }
  const TimeNs dt = s.stamp_ns - timing_.last_ns();
  // The increment in the previous pose's frame: R(-theta_prev) (p - p_prev), theta - theta_prev.
  const float dx = wrapped_difference(s.pose.x, last_.pose.x, s.wrap_m);
  const float dy = wrapped_difference(s.pose.y, last_.pose.y, s.wrap_m);
  float sn = 0.0f, cs = 0.0f;
  est::fmath::sincos(last_.pose.theta, sn, cs);
  const est::Pose2 inc{cs * dx + sn * dy, -sn * dx + cs * dy,
                       est::fmath::normalize_angle(s.pose.theta - last_.pose.theta)};
  const float dt_s = static_cast<float>(dt) * 1.0e-9f;
  const float travel = est::fmath::sqrt(inc.x * inc.x + inc.y * inc.y);
  timing_.accept(s.stamp_ns);
  last_ = s;
  if (travel > limits_.max_speed_mps * dt_s || est::fmath::abs(inc.theta) > limits_.max_turn_rate_rps * dt_s)
    return reject(Fault::out_of_range);
  out.dt_ns = dt;
  out.increment = inc;
  return Fault::none;
}

}  // namespace hal
