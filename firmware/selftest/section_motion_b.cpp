#include "est/motion/bicycle_model.hpp"
#include "est/motion/diff_drive_model.hpp"
#include "est/motion/holonomic_pose_model.hpp"
#include "est/motion/omni_model.hpp"
#include "est/random/xoshiro128.hpp"
#include "est/util/trace.hpp"
#include "selftest.hpp"

namespace est::selftest {
namespace {

// A chain of 200 sampled steps through one model: every pose, its log density and the Jacobians along the way.
template <typename Model>
void run_chain(Trace& d, const char* name, const typename Model::Control* controls, int n_controls,
               const typename Model::Params& p, std::uint64_t seed) {
  Rng rng(seed);
  Pose2 x{0.1f, -0.2f, 0.3f};
  d.scope(name);
  for (int k = 0; k < 200; ++k) {
    d.step(static_cast<std::uint32_t>(k));
    const typename Model::Control& u = controls[k % n_controls];
    const Pose2 next = Model::sample(x, u, p, rng);
    d.add("x", next.x);
    d.add("y", next.y);
    d.add("theta", next.theta);
    d.add("log_p", Model::log_likelihood(next, u, x, p));
    d.add("log_p_mode", Model::log_likelihood(Model::predict(x, u, p), u, x, p));
    if (k % 20 == 0) {
      const auto j = Model::jacobians(x, u, p);
      d.add_matrix("G", j.G);
      d.add_matrix("V", j.V);
      d.add_matrix("M", j.M);
    }
    x = next;
  }
  d.step(200);
  d.add_u32("check", static_cast<std::uint32_t>(Model::check(controls[0], p)));
}

}  // namespace

// Bicycle (front wheel), differential drive (ticks), omnidirectional and holonomic (with a heading) models:
// sampling, exact densities, Jacobians, including the steering stop (clamped command, folded noise) and straight and
// spin-in-place steps.
void section_motion_b(Trace& d) {
  BicycleParams bp;
  bp.frame_length = 1.0f;
  bp.steer_sigma = 0.0872664626f;  // 5 deg
  bp.speed_var_per_speed = 0.5f;
  bp.final_rot_sigma = 0.01f;
  bp.dt = 1.0f;
  const BicycleControl bc[] = {{0.2f, 0.436332313f}, {0.2f, -0.436332313f}, {0.9f, 0.436332313f},
                               {0.1f, 1.39626340f},  {0.9f, 1.48352986f},   {0.5f, 0.0f}};
  run_chain<BicycleMotionModel>(d, "bicycle", bc, 6, bp, 101u);
  d.add_u32("check_stop", static_cast<std::uint32_t>(BicycleMotionModel::check(bc[4], bp)));

  DiffDriveParams dp;
  dp.wheel_radius = 0.05f;
  dp.track_width = 0.5f;
  dp.ticks_per_rev = 1024u;
  dp.travel_sigma_per_m = 0.05f;
  dp.travel_sigma_floor = 0.01f;
  dp.final_rot_sigma = 0.02f;
  const DiffDriveControl dc[] = {{2900, 3500}, {3000, 3000}, {-500, 500}, {-1200, -1000}, {0, 0}};
  run_chain<DiffDriveMotionModel>(d, "diff_drive", dc, 5, dp, 202u);

  OmniParams op;
  const float alpha[9] = {0.1f, 0.02f, 0.02f, 0.02f, 0.15f, 0.02f, 0.02f, 0.02f, 0.15f};
  for (int i = 0; i < 9; ++i) op.alpha[i] = alpha[i];
  op.dt = 0.5f;
  const OmniControl oc[] = {{1.0f, 0.5f, 0.8f}, {0.0f, -0.8f, 0.0f}, {0.3f, 0.0f, 2.5f}, {-0.5f, 0.1f, 1e-6f}};
  run_chain<OmniMotionModel>(d, "omni", oc, 4, op, 303u);

  // The holonomic robot carrying a heading it never steers (the loop's holonomic model), with a slow heading drift.
  HolonomicPoseParams hp;
  hp.point.B << 0.5f, 0.1f, 0.0f, 0.5f;
  hp.point.Q << 0.01f, 0.003f, 0.003f, 0.0025f;
  hp.heading_sigma = 0.01f;
  const Eigen::Vector2f hc[] = {Eigen::Vector2f(0.3f, 0.0f), Eigen::Vector2f(0.0f, 0.3f), Eigen::Vector2f(-0.2f, 0.1f),
                                Eigen::Vector2f(0.0f, 0.0f)};
  run_chain<HolonomicPoseMotionModel>(d, "holonomic_pose", hc, 4, hp, 404u);
}

}  // namespace est::selftest
