#pragma once
// Particle storage for Monte Carlo localization, ETL style: ParticleSetView is the runtime-capacity interface the
// algorithms take, ParticleSet<NMax> owns the static arrays. Structure of arrays, so per-particle loops vectorize
// across particles without changing any particle's own arithmetic.
//
// Beside the pose each particle carries a mode: a discrete part of the state that a measurement model may estimate
// per particle (the handlebar's position of the steered rangefinder, est/loop/steered_scan.hpp). kUnknownMode for
// a particle that never had one (initialized or injected); resampling copies it with the pose, and a filter whose
// models carry none never looks at it.
#include <cstdint>

#include "est/geometry/pose2.hpp"

namespace est {

inline constexpr std::uint8_t kUnknownMode = 0xFFu;

struct ParticleSetView {
  float* x;
  float* y;
  float* theta;
  float* log_w;  // log weights; normalized (log-sum-exp = 0) after every correction
  std::uint32_t capacity;
  std::uint32_t count;
  std::uint8_t* mode = nullptr;  // per particle, or null (a set without modes)

  Pose2 pose(std::uint32_t i) const { return {x[i], y[i], theta[i]}; }
  void set_pose(std::uint32_t i, const Pose2& p) {
    x[i] = p.x;
    y[i] = p.y;
    theta[i] = p.theta;
  }
  // A new particle: its pose, and no mode yet.
  void set_new(std::uint32_t i, const Pose2& p) {
    set_pose(i, p);
    if (mode != nullptr) mode[i] = kUnknownMode;
  }
  // Particle `to` becomes a copy of particle `from` (pose and mode).
  void copy(std::uint32_t to, std::uint32_t from) {
    x[to] = x[from];
    y[to] = y[from];
    theta[to] = theta[from];
    if (mode != nullptr) mode[to] = mode[from];
  }
};

struct ConstParticleSetView {
  const float* x;
  const float* y;
  const float* theta;
  const float* log_w;
  std::uint32_t count;
  const std::uint8_t* mode;  // or null

  ConstParticleSetView(const ParticleSetView& v)  // NOLINT: a view converts to its read-only form
      : x(v.x), y(v.y), theta(v.theta), log_w(v.log_w), count(v.count), mode(v.mode) {}
  Pose2 pose(std::uint32_t i) const { return {x[i], y[i], theta[i]}; }
};

template <std::uint32_t NMax>
class ParticleSet {
  static_assert(NMax >= 1u, "a particle set holds at least one particle");

 public:
  static constexpr std::uint32_t kCapacity = NMax;

  ParticleSetView view() { return buffer(cur_); }
  ConstParticleSetView view() const { return const_cast<ParticleSet*>(this)->buffer(cur_); }
  // The second buffer that resampling writes into; swap_with_scratch() makes it current.
  ParticleSetView scratch() { return buffer(1 - cur_); }
  void swap_with_scratch(std::uint32_t new_count) {
    cur_ = 1 - cur_;
    set_count(new_count);
  }

  std::uint32_t count() const { return count_; }
  void set_count(std::uint32_t n) { count_ = n < NMax ? n : NMax; }

 private:
  ParticleSetView buffer(int b) { return {x_[b], y_[b], theta_[b], log_w_[b], NMax, count_, mode_[b]}; }

  float x_[2][NMax];
  float y_[2][NMax];
  float theta_[2][NMax];
  float log_w_[2][NMax];
  std::uint8_t mode_[2][NMax];
  int cur_ = 0;
  std::uint32_t count_ = 0;
};

}  // namespace est
