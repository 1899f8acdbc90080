// `record`: the sensor stream and the ground truth as an LCM log.
#include "sim/record.hpp"

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "hal/lcm/lcm_backend.hpp"
#include "hal/lcm/lcm_convert.hpp"
#include "node/node_config.hpp"
#include "sim/simulate.hpp"

namespace sim {
namespace {

class Writer {
 public:
  explicit Writer(const std::string& path) : file_(path, "w") {
    if (!file_.good()) throw std::runtime_error("cannot create the LCM log " + path);
  }
  template <typename Message>
  void write(const std::string& channel, hal::TimeNs t_ns, const Message& m, RecordSummary& summary) {
    const int n = m.getEncodedSize();
    buffer_.resize(static_cast<std::size_t>(n));
    if (m.encode(buffer_.data(), 0, n) != n) throw std::runtime_error("LCM encoding failed on " + channel);
    ::lcm::LogEvent e;
    e.eventnum = 0;  // set by LCM
    e.timestamp = t_ns / 1000;
    e.channel = channel;
    e.datalen = n;
    e.data = buffer_.data();
    if (file_.writeEvent(&e) != 0) throw std::runtime_error("writing the LCM log failed on " + channel);
    ++summary.messages[channel];
    ++summary.events;
  }

 private:
  ::lcm::LogFile file_;
  std::vector<std::uint8_t> buffer_;
};

}  // namespace

RecordSummary record_lcm_log(const SensorStream& s, const std::string& path,
                             const std::vector<hal::Estimate>* estimates) {
  const hal::lcm::Channels ch;
  Writer w(path);
  RecordSummary summary;
  std::size_t k = 0;
  const auto truth_until = [&](hal::TimeNs t) {
    for (; k < s.truth.size() && s.truth[k].t_ns <= t; ++k) {
      const TruthSample& x = s.truth[k];
      est_lcm::ground_truth_t g{};
      g.stamp_ns = x.t_ns;
      g.x_m = x.pose.x;
      g.y_m = x.pose.y;
      g.theta_rad = x.pose.theta;
      g.v_mps = x.v_mps;
      g.omega_rps = x.omega_rps;
      w.write(ch.ground_truth, x.t_ns, g, summary);
    }
  };
  std::size_t j = 0;
  const auto estimates_until = [&](hal::TimeNs t) {
    for (; estimates != nullptr && j < estimates->size() && (*estimates)[j].stamp_ns <= t; ++j)
      w.write(ch.pose, (*estimates)[j].stamp_ns, hal::lcm::to_lcm((*estimates)[j]), summary);
  };
  for (const StreamEvent& e : s.events) {
    truth_until(e.arrival_ns);
    estimates_until(e.arrival_ns);
    switch (e.kind) {
      case StreamKind::wheel_ticks:
        w.write(ch.wheel_ticks, e.arrival_ns, hal::lcm::to_lcm(e.ticks, kEncoderCounterBits), summary);
        break;
      case StreamKind::steering: w.write(ch.steering, e.arrival_ns, hal::lcm::to_lcm(e.steering), summary); break;
      case StreamKind::twist: w.write(ch.twist, e.arrival_ns, hal::lcm::to_lcm(e.twist), summary); break;
      case StreamKind::odometry: w.write(ch.odometry, e.arrival_ns, hal::lcm::to_lcm(e.odometry), summary); break;
      case StreamKind::scan: w.write(ch.range_scan, e.arrival_ns, hal::lcm::to_lcm(s.scans[e.scan].view()), summary); break;
      case StreamKind::landmarks:
        w.write(ch.landmarks, e.arrival_ns, hal::lcm::to_lcm(s.sightings[e.sighting].view()), summary);
        break;
    }
  }
  truth_until(s.end_ns);
  estimates_until(std::numeric_limits<hal::TimeNs>::max());
  return summary;
}

std::string record_sidecar_json(const SensorStream& s, const ScenarioConfig& sc, const SimWorld& world,
                                const RecordSummary& summary, const std::string& log_path,
                                const FilterOptions* filter) {
  nlohmann::ordered_json j;
  const hal::lcm::Channels ch;
  j["log"] = log_path;
  j["scenario"] = {{"world", world.name},
                   {"robot", to_string(sc.robot)},
                   {"seed", sc.seed},
                   {"duration_s", sc.duration_s},
                   {"start_pose", {s.truth.front().pose.x, s.truth.front().pose.y, s.truth.front().pose.theta}},
                   {"kidnap_at_s", s.kidnap_ns >= 0 ? static_cast<double>(s.kidnap_ns - kSimStartNs) * 1e-9 : -1.0}};
  j["channels"] = {{"wheel_ticks", ch.wheel_ticks}, {"steering", ch.steering},   {"twist", ch.twist},
                   {"odometry", ch.odometry},       {"range_scan", ch.range_scan}, {"landmarks", ch.landmarks},
                   {"ground_truth", ch.ground_truth}};
  j["messages"] = summary.messages;
  j["events"] = summary.events;
  j["encoder"] = {{"counter_bits", kEncoderCounterBits},
                  {"metres_per_tick", s.metres_per_tick},
                  {"wheels", "bicycle: 0 the front (traction) wheel, 1 the rear; diff drive: 0 left, 1 right; omni: "
                             "mecanum front-left, front-right, rear-left, rear-right"},
                  {"max_ticks_per_s", s.limits.wheels.max_ticks_per_s}};
  j["rangefinder_mount"] = {s.mount.x, s.mount.y, s.mount.theta};
  j["steering_max_angle_rad"] = s.limits.steering.max_angle_rad;
  j["landmark_sensor"] = {{"landmarks_in_map", s.landmark_count},
                          {"rate_hz", s.landmark_count > 0 ? sc.landmark_hz : 0},
                          {"ids", sc.landmark_ids_known ? "known" : "unknown"},
                          {"max_range_m", sc.landmark_sensor.max_range},
                          {"sigma_range_m", sc.landmark_sensor.noise.sigma_range},
                          {"sigma_bearing_rad", sc.landmark_sensor.noise.sigma_bearing},
                          {"sigma_signature", sc.landmark_sensor.noise.sigma_signature},
                          {"hal_max_range_m", s.limits.landmarks.max_range_m}};
  nlohmann::ordered_json faults = nlohmann::ordered_json::array();
  for (const InjectedFault& f : s.faults)
    faults.push_back({{"t_s", static_cast<double>(f.t_ns - kSimStartNs) * 1e-9}, {"fault", f.key},
                      {"expected_counter", f.expected}, {"amount", f.amount}});
  j["injected_faults"] = faults;
  j["expected_reject_counts"] = s.expected_counts();
  // estimator_node options that model this robot as the simulation's filter does (node/node_config.cpp).
  FilterOptions mcl;
  mcl.start = StartKind::tracking;
  const std::string map = sc.map_yaml.empty() ? "office" : sc.map_yaml;
  const std::string landmarks = sc.landmarks_csv.empty() ? "office" : sc.landmarks_csv;
  const std::string tail = " --wheel-counter-bits " + std::to_string(kEncoderCounterBits);
  j["estimator_node_options"] = "--replay " + log_path + " " +
                                node::command_line(estimator_spec(sc, filter != nullptr ? *filter : mcl, s), map,
                                                   landmarks) +
                                tail;
  if (filter == nullptr && s.landmark_count > 0 && has_landmarks(sc)) {
    FilterOptions ekf;
    ekf.filter = est::loop::Filter::ekf;
    ekf.start = StartKind::tracking;
    node::EstimatorSpec e = estimator_spec(sc, ekf, s);
    if (sc.landmark_ids_known) e.landmark_noise.sigma_signature = 0.0f;
    j["estimator_node_options_ekf"] = "--replay " + log_path + " " + node::command_line(e, map, landmarks) + tail;
  }
  j["note"] = "expected_reject_counts hold when the log is replayed through hal::ValidatedInputs with the HAL clock at "
              "each event's time (the arrival) and the loop's 20 ms reorder window; hal.* keys are hal::Fault reasons "
              "per input kind, loop.too_old the FilterLoop's counter. A replay that takes each message's own stamp as the HAL "
              "clock (estimator_node --replay) cannot see staleness or stamps from the future: record with those fault "
              "classes at 0 (--fault wheel_ticks.stale=0 ...) or --faults none for such a replay";
  return j.dump(2) + "\n";
}

}  // namespace sim
