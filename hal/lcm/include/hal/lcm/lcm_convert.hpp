#pragma once
// LCM conversions (host only): every sensor's (hal/sensors/<sensor>/lcm.hpp, gathered here) and the estimator's
// own messages: estimates, and the team message (hal/team/lcm.hpp).
#include <cstddef>
#include <cstdint>
#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/particle_cloud_t.hpp>
#include <est_lcm/pose_estimate_t.hpp>
#include <est_lcm/status_t.hpp>

#include "hal/estimate.hpp"
#include "hal/fault.hpp"
#include "hal/lcm/lcm_guard.hpp"
#include "hal/sensors/landmarks/lcm.hpp"
#include "hal/sensors/odometry/lcm.hpp"
#include "hal/sensors/range_scan/lcm.hpp"
#include "hal/sensors/steering/lcm.hpp"
#include "hal/sensors/twist/lcm.hpp"
#include "hal/sensors/wheel_ticks/lcm.hpp"
#include "hal/team/lcm.hpp"

namespace hal::lcm {

template <> struct LeadingCount<est_lcm::particle_cloud_t> { static constexpr int bytes = 4; };
template <> struct LeadingCount<est_lcm::status_t> { static constexpr int bytes = 2; };

est_lcm::pose_estimate_t to_lcm(const Estimate& e);
Estimate to_hal(const est_lcm::pose_estimate_t& m);

}  // namespace hal::lcm
