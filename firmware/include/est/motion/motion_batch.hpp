#pragma once
// Motion sampling for a whole particle set at once: x_i ~ p(x | u, x_i) for every particle, as Model::sample does
// one particle at a time, but with the noise drawn in bulk (fill_standard_normals: the inverse CDF by a table, one
// uniform per value) and the arc evaluated with inline trigonometry (est/math/inline_math.hpp; on a host four
// particles at a time, est/math/lanes.hpp, the same bits). The same distribution as the model's own sampler, NOT
// the same bits (different normal draws; kernels within 2 ULP of fmath): the particle filter's batched prediction
// (AugmentedMcl::predict_batch) uses it; tests/test_motion_batch.cpp compares the two samplers' distributions
// (two-sample KS).
//
// Models without a batched form fall back to their own sampler, one particle at a time (the generic overload).
// Noise buffers: three arrays of n floats (MCL passes its idle scratch set). Non-finite particles and angles beyond
// the inline range take fmath's path, so the result is never worse than the scalar sampler's.
#include <cstdint>

#include "est/geometry/pose2.hpp"
#include "est/math/fmath.hpp"
#include "est/math/inline_math.hpp"
#include "est/math/lanes.hpp"
#include "est/motion/bicycle_model.hpp"
#include "est/motion/circular_arc.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/motion/motion_model.hpp"
#include "est/random/normal_batch.hpp"
#include "est/random/xoshiro128.hpp"

namespace est {

struct NoiseBuffers {
  float* a;
  float* b;
  float* c;
};

// Any model: its own sample(), particle by particle (bit-identical to a loop over Model::sample).
template <class Model>
void sample_motion_batch(const Model&, const typename Model::Control& u, const typename Model::Params& p, float* x,
                         float* y, float* theta, std::uint32_t n, Rng& rng, NoiseBuffers) {
  for (std::uint32_t i = 0; i < n; ++i) {
    const Pose2 q = Model::sample({x[i], y[i], theta[i]}, u, p, rng);
    x[i] = q.x;
    y[i] = q.y;
    theta[i] = q.theta;
  }
}

namespace motion_batch_detail {

// x += chord (cos, sin)(theta + turn), theta <- wrap(wrap(theta + 2h) + gamma): the chord form shared by the arc
// models, inline where |theta + turn| <= 64 and |2h + gamma| stays within one wrap; fmath otherwise (and for NaN).
inline void move_on_arc(float& x, float& y, float& theta, float turn, float chord, float h, float gamma) {
  const float dir = theta + turn;
  float sn = 0.0f, cs = 0.0f;
  if (fmath::abs(dir) <= 64.0f) {
    imath::sincos_moderate(dir, sn, cs);
  } else {
    fmath::sincos(dir, sn, cs);
  }
  x += chord * cs;
  y += chord * sn;
  const float t = theta + 2.0f * h;
  if (fmath::abs(theta) <= kPi && fmath::abs(2.0f * h) <= kPi && fmath::abs(gamma) <= kPi) {
    theta = imath::wrap_angle_near(imath::wrap_angle_near(t) + gamma);
  } else {
    theta = fmath::normalize_angle(fmath::normalize_angle(t) + gamma);
  }
}

// The first passes' common case for one particle (T = float) or for lanes::kLanes particles at once (T = lanes::F):
// the same operations in the same order either way, so the same bits per particle (the board's loops in
// sample_motion_batch are these operations written out for one particle). Moves the particles it can, marks their
// noise `a` with NaN, and returns how many it left.
struct BicycleFast {
  float a_cmd, steer_sigma, v_cmd, v_sigma, rot_sigma, dt, half_dt_over_l, a_fast;
};
template <class T>
inline std::uint32_t bicycle_fast(const BicycleFast& k, T& x, T& y, T& theta, T& na, T nb, T nc) {
  using M = decltype(T{} < T{});
  // Inside the stops the steering is a_raw itself (no fold), and sin a is the kernel alone (one polynomial, no
  // quadrant logic) where |a| <= pi/4, every steering a car's stops allow in practice; the rest: the second pass.
  const T a = k.a_cmd + k.steer_sigma * na;
  const T v = k.v_cmd + k.v_sigma * nb;
  const T gamma = k.rot_sigma * nc;
  const T th = theta;
  const T sa = lanes::sin_kernel(a);
  const T h = v * sa * k.half_dt_over_l;
  const M ok = static_cast<M>((lanes::abs(a) <= k.a_fast) & (lanes::abs(h) < arc::kSeriesBelow) &
                              (lanes::abs(th) <= kPi));
  const T h2 = h * h;
  const T chord = v * k.dt * (1.0f - h2 * (1.0f / 6.0f) + h2 * h2 * (1.0f / 120.0f));  // arc::sinc's series
  T sn{}, cs{};
  lanes::sincos_moderate(lanes::select(ok, th + a + h, T{}), sn, cs);
  const T t = lanes::wrap_angle_near((th + 2.0f * h) + gamma);  // |.| < 3 pi (a_fast): one wrap suffices
  x = lanes::select(ok, x + chord * cs, x);
  y = lanes::select(ok, y + chord * sn, y);
  theta = lanes::select(ok, t, th);
  na = lanes::select(ok, lanes::broadcast<T>(__builtin_nanf("")), na);
  return lanes::count_false(ok);
}

struct DiffDriveFast {
  float left, right, sl, sr, rot_sigma, half_over_b;
};
template <class T>
inline std::uint32_t diff_drive_fast(const DiffDriveFast& k, T& x, T& y, T& theta, T& na, T nb, T nc) {
  using M = decltype(T{} < T{});
  const T left = k.left + k.sl * na;
  const T right = k.right + k.sr * nb;
  const T gamma = k.rot_sigma * nc;
  const T th = theta;
  const T s = 0.5f * (left + right);
  const T h = (right - left) * k.half_over_b;
  const M ok = static_cast<M>((lanes::abs(h) < arc::kSeriesBelow) & (lanes::abs(th) <= kPi) &
                              (lanes::abs(gamma) <= kPi));
  const T h2 = h * h;
  const T chord = s * (1.0f - h2 * (1.0f / 6.0f) + h2 * h2 * (1.0f / 120.0f));  // arc::sinc's series
  T sn{}, cs{};
  lanes::sincos_moderate(lanes::select(ok, th + h, T{}), sn, cs);
  const T t = lanes::wrap_angle_near((th + 2.0f * h) + gamma);  // |.| < 3 pi: one wrap suffices
  x = lanes::select(ok, x + chord * cs, x);
  y = lanes::select(ok, y + chord * sn, y);
  theta = lanes::select(ok, t, th);
  na = lanes::select(ok, lanes::broadcast<T>(__builtin_nanf("")), na);
  return lanes::count_false(ok);
}

// The host's first pass: `fast` over particles [0, n), kLanes at a time, the remainder one at a time.
template <class Step>
inline std::uint32_t first_pass(const Step& fast, float* __restrict x, float* __restrict y, float* __restrict theta,
                                float* __restrict na, const float* __restrict nb, const float* __restrict nc,
                                std::uint32_t n) {
  std::uint32_t pending = 0, i = 0;
  for (; i + lanes::kLanes <= n; i += lanes::kLanes) {
    lanes::F vx = lanes::load(x + i), vy = lanes::load(y + i), vt = lanes::load(theta + i), va = lanes::load(na + i);
    pending += fast(vx, vy, vt, va, lanes::load(nb + i), lanes::load(nc + i));
    lanes::store(x + i, vx);
    lanes::store(y + i, vy);
    lanes::store(theta + i, vt);
    lanes::store(na + i, va);
  }
  for (; i < n; ++i) {
    float xi = x[i], yi = y[i], ti = theta[i], ai = na[i];
    pending += fast(xi, yi, ti, ai, nb[i], nc[i]);
    x[i] = xi;
    y[i] = yi;
    theta[i] = ti;
    na[i] = ai;
  }
  return pending;
}

}  // namespace motion_batch_detail

// Bicycle (sample_motion_model_bicycle): steering, speed and final-rotation noise, then the exact arc.
// Two passes: the common case (steering inside the stops, |h| < 0.1 where sinc is its series, heading and final
// rotation within (-pi, pi]) without a branch, lanes::kLanes particles at a time on a host; it marks the noise it
// consumed with NaN, and the second pass takes the few particles left (folded steering, long arcs, NaN poses)
// through the general path.
inline void sample_motion_batch(const BicycleMotionModel&, const BicycleControl& u, const BicycleParams& p, float* x,
                                float* y, float* theta, std::uint32_t n, Rng& rng, NoiseBuffers noise) {
  if (!usable(check_motion_bicycle(u, p))) return;
  fill_standard_normals(rng, noise.a, n);
  fill_standard_normals(rng, noise.b, n);
  fill_standard_normals(rng, noise.c, n);
  const float a_cmd = bicycle_detail::clamp_steer(u.steer, p.steer_max);
  // min(a_max, pi/4); -1 (no particle takes the first pass) unless every final rotation keeps the heading's one
  // wrap valid: |theta + 2h + gamma| < 3 pi for |theta| <= pi, |2h| < 0.2 and |gamma| <= sigma kNormalBatchMax.
  const bool gamma_bounded = p.final_rot_sigma * kNormalBatchMax < 2.0f * kPi - 0.2f;
  const float a_fast = !gamma_bounded ? -1.0f : p.steer_max < 0.7853981f ? p.steer_max : 0.7853981f;
  const float v_sigma = bicycle_detail::speed_sigma(u.v, p);
  const float half_dt_over_l = 0.5f * p.dt / p.frame_length;
  float* __restrict px = x;
  float* __restrict py = y;
  float* __restrict pt = theta;
  float* __restrict na = noise.a;
  const float* __restrict nb = noise.b;
  const float* __restrict nc = noise.c;
#if defined(__arm__)
  // The board: bicycle_fast's operations written out for one particle (the same bits; as a template instance it
  // costs the M4F one instruction more per particle).
  const float done = __builtin_nanf("");
  const float steer_sigma = p.steer_sigma, rot_sigma = p.final_rot_sigma, dt = p.dt, v_cmd = u.v;
  std::uint32_t pending = 0;  // particles the first pass left to the second
  for (std::uint32_t i = 0; i < n; ++i) {
    // Inside the stops the steering is a_raw itself (no fold), and sin a is the kernel alone (one polynomial, no
    // quadrant logic) where |a| <= pi/4, every steering a car's stops allow in practice; the rest: the second pass.
    const float a = a_cmd + steer_sigma * na[i];
    const float v = v_cmd + v_sigma * nb[i];
    const float gamma = rot_sigma * nc[i];
    const float th = pt[i];
    const float sa = imath::sin_kernel(a);
    const float h = v * sa * half_dt_over_l;
    const bool ok = (fmath::abs(a) <= a_fast) & (fmath::abs(h) < arc::kSeriesBelow) & (fmath::abs(th) <= kPi);
    const float h2 = h * h;
    const float chord = v * dt * (1.0f - h2 * (1.0f / 6.0f) + h2 * h2 * (1.0f / 120.0f));  // arc::sinc's series
    float sn = 0.0f, cs = 0.0f;
    imath::sincos_moderate(imath::select(ok, th + a + h, 0.0f), sn, cs);
    const float t = imath::wrap_angle_near((th + 2.0f * h) + gamma);  // |.| < 3 pi (a_fast): one wrap suffices
    px[i] = imath::select(ok, px[i] + chord * cs, px[i]);
    py[i] = imath::select(ok, py[i] + chord * sn, py[i]);
    pt[i] = imath::select(ok, t, th);
    na[i] = imath::select(ok, done, na[i]);
    pending += ok ? 0u : 1u;
  }
#else
  const motion_batch_detail::BicycleFast k{a_cmd, p.steer_sigma, u.v, v_sigma, p.final_rot_sigma, p.dt,
                                           half_dt_over_l, a_fast};
  std::uint32_t pending = motion_batch_detail::first_pass(  // particles the first pass left to the second
      [&k](auto& xi, auto& yi, auto& ti, auto& ai, auto bi, auto ci) {
        return motion_batch_detail::bicycle_fast(k, xi, yi, ti, ai, bi, ci);
      },
      px, py, pt, na, nb, nc, n);
#endif
  for (std::uint32_t i = 0; i < n && pending > 0u; ++i) {  // none left: no second pass
    if (na[i] != na[i]) continue;  // moved by the first pass
    --pending;
    const float a = bicycle_detail::fold_steer(a_cmd + p.steer_sigma * na[i], p.steer_max);
    const float v = u.v + v_sigma * nb[i];
    const float gamma = p.final_rot_sigma * nc[i];
    float sa = 0.0f, ca = 0.0f;
    imath::sincos_moderate(a, sa, ca);  // |a| <= a_max < pi/2
    const float h = v * sa * half_dt_over_l;
    const float chord = v * p.dt * arc::sinc(h);
    motion_batch_detail::move_on_arc(px[i], py[i], pt[i], a + h, chord, h, gamma);
  }
}

// Differential drive (sample_motion_model_diff_drive): per-wheel travel noise and final rotation, then the arc.
// The same two passes as the bicycle (the common case: |h| < 0.1, heading and final rotation within (-pi, pi]).
inline void sample_motion_batch(const DiffDriveMotionModel&, const DiffDriveControl& u, const DiffDriveParams& p,
                                float* x, float* y, float* theta, std::uint32_t n, Rng& rng, NoiseBuffers noise) {
  if (!usable(check_motion_diff_drive(u, p))) return;
  const WheelTravel d = wheel_travel_from_ticks(u, p);
  fill_standard_normals(rng, noise.a, n);
  fill_standard_normals(rng, noise.b, n);
  fill_standard_normals(rng, noise.c, n);
  const float sl = diff_drive_detail::travel_sigma(d.left, p), sr = diff_drive_detail::travel_sigma(d.right, p);
  const float half_over_b = 0.5f / p.track_width;
  float* __restrict px = x;
  float* __restrict py = y;
  float* __restrict pt = theta;
  float* __restrict na = noise.a;
  const float* __restrict nb = noise.b;
  const float* __restrict nc = noise.c;
#if defined(__arm__)
  // The board: diff_drive_fast's operations written out for one particle, as for the bicycle.
  const float done = __builtin_nanf("");
  std::uint32_t pending = 0;  // particles the first pass left to the second
  for (std::uint32_t i = 0; i < n; ++i) {
    const float left = d.left + sl * na[i];
    const float right = d.right + sr * nb[i];
    const float gamma = p.final_rot_sigma * nc[i];
    const float th = pt[i];
    const float s = 0.5f * (left + right);
    const float h = (right - left) * half_over_b;
    const bool ok = (fmath::abs(h) < arc::kSeriesBelow) & (fmath::abs(th) <= kPi) & (fmath::abs(gamma) <= kPi);
    const float h2 = h * h;
    const float chord = s * (1.0f - h2 * (1.0f / 6.0f) + h2 * h2 * (1.0f / 120.0f));  // arc::sinc's series
    float sn = 0.0f, cs = 0.0f;
    imath::sincos_moderate(imath::select(ok, th + h, 0.0f), sn, cs);
    const float t = imath::wrap_angle_near((th + 2.0f * h) + gamma);  // |.| < 3 pi (a_fast): one wrap suffices
    px[i] = imath::select(ok, px[i] + chord * cs, px[i]);
    py[i] = imath::select(ok, py[i] + chord * sn, py[i]);
    pt[i] = imath::select(ok, t, th);
    na[i] = imath::select(ok, done, na[i]);
    pending += ok ? 0u : 1u;
  }
#else
  const motion_batch_detail::DiffDriveFast k{d.left, d.right, sl, sr, p.final_rot_sigma, half_over_b};
  std::uint32_t pending = motion_batch_detail::first_pass(  // particles the first pass left to the second
      [&k](auto& xi, auto& yi, auto& ti, auto& ai, auto bi, auto ci) {
        return motion_batch_detail::diff_drive_fast(k, xi, yi, ti, ai, bi, ci);
      },
      px, py, pt, na, nb, nc, n);
#endif
  for (std::uint32_t i = 0; i < n && pending > 0u; ++i) {  // none left: no second pass
    if (na[i] != na[i]) continue;
    --pending;
    const float left = d.left + sl * na[i];
    const float right = d.right + sr * nb[i];
    const float gamma = p.final_rot_sigma * nc[i];
    const float s = 0.5f * (left + right);
    const float h = (right - left) * half_over_b;
    motion_batch_detail::move_on_arc(px[i], py[i], pt[i], h, s * arc::sinc(h), h, gamma);
  }
}

}  // namespace est
