#include "sim/learn_beam_model.hpp"

#include <lcm/lcm-cpp.hpp>

#include <cmath>
#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/range_scan_t.hpp>
#include <iterator>
#include <map>
#include <stdexcept>
#include <vector>

#include "est/map/ray_casting.hpp"
#include "hal/lcm/lcm_log_reader.hpp"
#include "est/sensor/range_scan.hpp"

namespace sim {

LearnBeamModelResult learn_beam_model_from_log(const LearnBeamModelOptions& o) {
  if (o.beam_stride < 1) throw std::invalid_argument("learn-beam-model: --stride must be >= 1");

  // Ground truth by stamp, scans kept whole; the log is small enough to hold (one scan every 100 ms).
  std::map<std::int64_t, est::Pose2> truth;
  std::vector<est_lcm::range_scan_t> scans;
  hal::lcm::read_lcm_log(o.log_path, "learn-beam-model: warning", stderr, [&](const hal::lcm::LcmLogEvent& e) {
    const int n = e.size();
    if (e.channel == "EST_GROUND_TRUTH") {
      est_lcm::ground_truth_t m{};
      if (m.decode(e.data.data(), 0, n) == n) truth[m.stamp_ns] = {m.x_m, m.y_m, m.theta_rad};
    } else if (e.channel == "EST_RANGE_SCAN") {
      est_lcm::range_scan_t m{};
      if (m.decode(e.data.data(), 0, n) == n) scans.push_back(std::move(m));
    }
  });
  if (truth.empty() || scans.empty())
    throw std::runtime_error("learn-beam-model: the log has no EST_GROUND_TRUTH or no EST_RANGE_SCAN messages");

  ScenarioConfig world_config;
  world_config.map_yaml = o.map_yaml;
  const SimWorld world = load_world(world_config);
  const est::GridRayCaster caster(world.grid);

  LearnBeamModelResult r;
  std::vector<est::sim::RangeSample> data;
  float range_max = 0.0f;
  for (const est_lcm::range_scan_t& s : scans) {
    auto it = truth.lower_bound(s.stamp_ns);
    if (it == truth.end() || (it != truth.begin() && s.stamp_ns - std::prev(it)->first < it->first - s.stamp_ns))
      it = std::prev(it);
    const std::int64_t gap = it->first > s.stamp_ns ? it->first - s.stamp_ns : s.stamp_ns - it->first;
    if (gap > o.max_truth_gap_ns || s.num_ranges <= 0 || !(s.range_max_m > 0.0f)) {
      ++r.scans_skipped;
      continue;
    }
    ++r.scans_used;
    range_max = s.range_max_m;
    const est::SensorFrame f = est::sensor_frame(it->second, o.mount);
    for (std::int32_t k = 0; k < s.num_ranges; k += o.beam_stride) {
      const float z = s.ranges_m[static_cast<std::size_t>(k)];
      if (!std::isfinite(z)) {
        ++r.readings_skipped;
        continue;
      }
      const float a = s.angle_min_rad + static_cast<float>(k) * s.angle_increment_rad;
      const float ux = std::cos(a), uy = std::sin(a);
      const float z_star = caster.cast(f.x, f.y, f.c * ux - f.s * uy, f.s * ux + f.c * uy, s.range_max_m);
      data.push_back({std::min(static_cast<double>(z), static_cast<double>(s.range_max_m)), z_star});
      ++r.readings_used;
    }
  }
  if (data.empty()) throw std::runtime_error("learn-beam-model: no scan could be paired with a ground-truth pose");
  est::BeamModelParams init;
  init.range_max = range_max;
  r.learned = est::sim::learn_intrinsic_parameters(data, init);
  return r;
}

}  // namespace sim
