// `sim_host run --live --can IFACE --lcm URL` (sim/live_run.hpp): the run's streams in real time as CAN frames to an
// estimator_node reading the bus, its estimates back over LCM, compared with the lockstep run and with the lockstep
// replay of the inputs the node recorded.
#include <time.h>

#include <est_lcm/landmark_sighting_t.hpp>

#include "hal/lcm/channels.hpp"
#include "live_support.hpp"

namespace sim {
using namespace live;
namespace {

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

void sleep_until_monotonic(std::int64_t t_ns) {
  timespec ts{static_cast<time_t>(t_ns / 1000000000), static_cast<long>(t_ns % 1000000000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) != 0) {
  }
}

// The landmark sightings (no CAN frame carries them) on LCM, each at CLOCK_MONOTONIC stamp + offset and stamped so:
// on the node's clock, as a driver on the robot would stamp them. The count published.
std::size_t play_landmarks(const std::string& log_path, const std::string& url, const std::string& channel,
                           std::int64_t offset_ns) {
  ::lcm::LogFile log(log_path, "r");
  if (!log.good()) throw std::runtime_error("--live: cannot read " + log_path);
  ::lcm::LCM lcm(url);
  if (!lcm.good()) throw std::runtime_error("--live: LCM could not start on '" + url + "'");
  std::size_t n = 0;
  while (const ::lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel != channel) continue;
    est_lcm::landmark_sighting_t m;
    if (m.decode(e->data, 0, e->datalen) != e->datalen) continue;
    m.stamp_ns += offset_ns;
    sleep_until_monotonic(m.stamp_ns);
    if (lcm.publish(channel, &m) == 0) ++n;
  }
  return n;
}

// How many messages of `channel` the log holds.
std::size_t count_messages(const std::string& log_path, const std::string& channel) {
  ::lcm::LogFile log(log_path, "r");
  std::size_t n = 0;
  while (const ::lcm::LogEvent* e = log.good() ? log.readNextEvent() : nullptr) if (e->channel == channel) ++n;
  return n;
}

// The run log's first event time (its first message's stamp, to the microsecond of the log).
std::int64_t first_event_ns(const std::string& log_path) {
  ::lcm::LogFile log(log_path, "r");
  const ::lcm::LogEvent* e = log.good() ? log.readNextEvent() : nullptr;
  if (e == nullptr) throw std::runtime_error("--live: " + log_path + " has no event");
  return e->timestamp * 1000;
}

std::vector<est_lcm::pose_estimate_t> estimates_in(const std::string& log_path) {
  std::vector<est_lcm::pose_estimate_t> out;
  ::lcm::LogFile log(log_path, "r");
  if (!log.good()) return out;
  while (const ::lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel != "EST_POSE") continue;
    est_lcm::pose_estimate_t m;
    if (m.decode(e->data, 0, e->datalen) == e->datalen) out.push_back(m);
  }
  return out;
}

// A live estimate and the lockstep estimate of the input it came from, in order: both runs give one estimate per
// input, in the inputs' order, the live one stamped later by the input's delay on the way (its receive time, never
// before its sending). So, walking both in order: lockstep estimates more than `window_ns` older than the live one
// had no live counterpart (an input lost), a live one older than the next lockstep one is one of its own (a step the
// live loop made between inputs), else the two pair.
struct InputPairing {
  std::size_t matched = 0, same_pose = 0;
  double worst_m = 0.0, worst_rad = 0.0, rms_m = 0.0;
  double offset_median_ms = 0.0, offset_worst_ms = 0.0;
  std::vector<std::int64_t> paired_stamp;  // per live estimate: the lockstep stamp it pairs with, -1 when none
};
InputPairing pair_by_input(const std::vector<est_lcm::pose_estimate_t>& lockstep,
                           const std::vector<est_lcm::pose_estimate_t>& live, std::int64_t offset_ns,
                           std::int64_t window_ns) {
  InputPairing p;
  std::vector<double> offset_ms;
  double sum_sq = 0.0;
  std::size_t j = 0;
  for (const est_lcm::pose_estimate_t& l : live) {
    p.paired_stamp.push_back(-1);
    const std::int64_t t = l.stamp_ns - offset_ns;
    while (j < lockstep.size() && lockstep[j].stamp_ns < t - window_ns) ++j;
    if (j == lockstep.size() || lockstep[j].stamp_ns > t) continue;
    const est_lcm::pose_estimate_t& r = lockstep[j++];
    p.paired_stamp.back() = r.stamp_ns;
    ++p.matched;
    if (std::memcmp(&l.x_m, &r.x_m, sizeof(float)) == 0 && std::memcmp(&l.y_m, &r.y_m, sizeof(float)) == 0 &&
        std::memcmp(&l.theta_rad, &r.theta_rad, sizeof(float)) == 0)
      ++p.same_pose;
    const double d = std::hypot(static_cast<double>(l.x_m - r.x_m), static_cast<double>(l.y_m - r.y_m));
    sum_sq += d * d;
    p.worst_m = std::max(p.worst_m, d);
    p.worst_rad = std::max(p.worst_rad, std::fabs(std::remainder(static_cast<double>(l.theta_rad - r.theta_rad),
                                                                 6.283185307179586)));
    offset_ms.push_back(static_cast<double>(t - r.stamp_ns) * 1.0e-6);
  }
  if (p.matched > 0) p.rms_m = std::sqrt(sum_sq / static_cast<double>(p.matched));
  if (!offset_ms.empty()) {
    std::sort(offset_ms.begin(), offset_ms.end());
    p.offset_median_ms = offset_ms[offset_ms.size() / 2];
    p.offset_worst_ms = offset_ms.back();
  }
  return p;
}

// Counts every sample handed to the loop and every one rejected with a reason, from the node's summary.
long long summary_total(const std::string& summary, const std::string& line, std::initializer_list<const char*> keys) {
  long long n = 0;
  for (const char* k : keys) {
    const long long v = summary_value(summary, line, k);
    if (v > 0) n += v;
  }
  return n;
}

}  // namespace

LiveResult run_live_robot_can(const SimResult& lockstep, const ScenarioConfig& sc, const FilterOptions& fo,
                              const std::string& out, const LiveOptions& o) {
  const fs::path dir = fs::path(out) / "live";
  fs::create_directories(dir);
  const std::string log = (fs::path(out) / "run.lcmlog").string();
  const nlohmann::json sidecar = nlohmann::json::parse(read_text(log + ".json"));
  const std::string options = live_node_options(sidecar, log, o);
  const std::string player_exe = beside_exe(o.can_player_exe, "can_player");
  const fs::path recorded = dir / "inputs.lcmlog";
  fs::remove(recorded);

  std::printf("live: the run again in real time (%.1f s): its sensor streams as CAN frames on %s to estimator_node, "
              "the estimates back on LCM %s\n",
              sc.duration_s, o.can_interface.c_str(), o.lcm_url.c_str());
  std::fflush(stdout);
  LiveResult result;
  const fs::path written = dir / "node_out.lcmlog";  // the estimates as the node wrote them
  NodeProcess node(node_exe(o) + " --can '" + o.can_interface + "' --lcm '" + o.lcm_url + "' --record-inputs '" +
                       recorded.string() + "' --out '" + written.string() + "'" + options,
                   dir / "node.txt");
  if (!node.wait_for("estimator_node: running", o.start_timeout_s))
    throw std::runtime_error("--live: estimator_node did not start: " + read_text(dir / "node.txt"));
  Collector heard(o.lcm_url);
  // Every message goes out at CLOCK_MONOTONIC stamp + offset: the first 0.5 s from now.
  const std::int64_t offset_ns = monotonic_ns() + 500000000 - first_event_ns(log);
  const auto t0 = Clock::now();
  NodeProcess player(player_exe + " '" + log + "' --can '" + o.can_interface + "' --clock-offset " +
                         std::to_string(offset_ns),
                     dir / "can_player.txt");
  const std::size_t landmarks = play_landmarks(log, o.lcm_url, hal::lcm::Channels{}.landmarks, offset_ns);
  const int player_exit = player.wait(sc.duration_s + 60.0);
  const double played_s = std::chrono::duration<double>(Clock::now() - t0).count() - 0.5;
  // A node slower than real time (an emulated machine) has frames queued in its socket still: wait until it has
  // published the estimate of the run's last input, or published nothing new for 2 s (up to 30 s), then the drain.
  const std::int64_t last_ns = lockstep.estimates.empty() ? 0 : lockstep.estimates.back().stamp_ns;
  const auto give_up = Clock::now() + std::chrono::seconds(30);
  const auto behind = [&] {
    const std::int64_t latest = heard.latest_stamp_ns();
    return latest == INT64_MIN || latest - offset_ns < last_ns;
  };
  std::size_t count = heard.heard();
  auto changed = Clock::now();
  while (behind() && Clock::now() < give_up && Clock::now() - changed < std::chrono::seconds(2)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (heard.heard() != count) {
      count = heard.heard();
      changed = Clock::now();
    }
  }
  const double caught_up_s = std::chrono::duration<double>(Clock::now() - t0).count() - 0.5 - played_s;
  std::this_thread::sleep_for(std::chrono::duration<double>(o.drain_s));
  result.node_exit = node.stop();
  heard.finish();
  const std::string summary = read_text(dir / "node.txt"), played = read_text(dir / "can_player.txt");
  if (player_exit != 0)
    throw std::runtime_error("--live: can_player exited with status " + std::to_string(player_exit) + ": " + played);

  const auto found = heard.estimates().find("EST_POSE");
  const std::vector<est_lcm::pose_estimate_t> live =
      found != heard.estimates().end() ? found->second : std::vector<est_lcm::pose_estimate_t>{};
  write_estimates(dir / "live.lcmlog", heard.estimates());
  std::vector<est_lcm::pose_estimate_t> ref;
  for (const hal::Estimate& e : lockstep.estimates) ref.push_back(hal::lcm::to_lcm(e));
  // A delay of up to 200 ms on the way (a stalled sender, an emulated machine) still pairs.
  const InputPairing p = pair_by_input(ref, live, offset_ns, 200000000);

  // The live estimates scored as the lockstep's: each at the time of the input it came from.
  std::vector<OutputRow> rows;
  for (std::size_t i = 0; i < live.size(); ++i) {
    est_lcm::pose_estimate_t m = live[i];
    m.stamp_ns = p.paired_stamp[i] >= 0 ? p.paired_stamp[i] : m.stamp_ns - offset_ns;
    rows.push_back(output_row(lockstep.stream, hal::lcm::to_hal(m)));
  }
  std::stable_sort(rows.begin(), rows.end(), [](const OutputRow& a, const OutputRow& b) { return a.t_ns < b.t_ns; });
  const SimMetrics lm = compute_metrics(lockstep.stream, rows, fo);

  // The lockstep replay of the inputs the node recorded (receive stamps, the bus's bits): its estimates bit for bit.
  const fs::path replayed = dir / "replay_of_inputs.lcmlog";
  const std::string replay_cmd = node_exe(o) + " --replay '" + recorded.string() + "' --out '" + replayed.string() +
                                 "'" + options + " > '" + (dir / "replay_of_inputs.txt").string() + "' 2>&1";
  const int replay_rc = std::system(replay_cmd.c_str());
  const std::vector<est_lcm::pose_estimate_t> again = estimates_in(replayed.string());
  const std::vector<est_lcm::pose_estimate_t> wrote = estimates_in(written.string());
  std::size_t identical = 0;
  for (std::size_t i = 0; i < wrote.size() && i < again.size(); ++i)
    if (same_bits(wrote[i], again[i])) ++identical;
  // And what came over LCM is what the node wrote (the k-th estimate of a stamp with the k-th).
  const Pairing over_lcm = pair_by_stamp(wrote, live);
  result.replay_identical = identical;

  // Every message sent: handed to the loop or rejected with a reason (by the CAN decoder, the scan reassembler or
  // the HAL gate).
  const long long sent = summary_value(played, "can_player:", "messages");
  const long long frames = summary_value(played, "can_player:", "frames");
  const long long rx_frames = summary_value(summary, "  can:", "rx_frames");
  const long long taken = summary_total(summary, "  inputs:", {"wheel_ticks", "steering", "twist", "odometry", "scan"});
  long long rejected = 0;
  for (const char* kind : {"wheel_ticks", "steering", "twist", "odometry", "scan"})
    rejected += summary_total(summary, std::string("  rejects.") + kind + ":",
                              {"not_finite", "out_of_range", "time_backwards", "duplicate", "stale", "from_future",
                               "bad_geometry", "too_few_valid_beams"});
  const long long landmarks_taken = summary_value(summary, "  inputs:", "landmark");
  // A scan is 122 frames: one the reassembler could not complete (a frame late past its timeout under load, say) is
  // rejected there, with its reason on the node's rejects.can_scan line.
  const long long scans_sent = static_cast<long long>(count_messages(log, hal::lcm::Channels{}.range_scan));
  const long long scans_completed = summary_value(summary, "  rejects.can_scan:", "completed");
  const long long scans_lost = scans_sent - scans_completed;
  const long long scan_rejects =
      summary_total(summary, "  rejects.can_scan:",
                    {"wrong_dlc", "orphan_frame", "sequence_gap", "truncated", "duplicate_frame", "interleaved",
                     "extra_frame", "exceeds_capacity", "bad_header", "bad_checksum", "timeout"});
  result.inputs_published = static_cast<std::size_t>(std::max(0LL, sent)) + landmarks;
  result.estimates = live.size();
  result.matched = p.matched;
  result.identical = p.same_pose;
  result.inputs_all_accounted = sent >= 0 && rx_frames == frames && taken + rejected + scans_lost == sent &&
                                (scans_lost == 0 || scan_rejects > 0) &&
                                landmarks_taken == static_cast<long long>(landmarks);

  const SimMetrics& km = lockstep.metrics;
  int lockstep_rejects = 0;
  for (const auto& kv : lockstep.observed_counts()) lockstep_rejects += kv.second;
  std::printf("live over CAN against lockstep (%s, %.1f s of inputs played in %.1f s, the node's last estimate %.2f s "
              "later):\n",
              lockstep.description.c_str(), sc.duration_s, played_s, caught_up_s);
  row("", "lockstep", "live (CAN)");
  row("estimates", std::to_string(lockstep.estimates.size()), std::to_string(live.size()));
  metric_rows(km, lm, lockstep_rejects, rejected);
  std::printf("  live estimates paired with the lockstep's by their input: %zu of %zu (%zu with the same pose to the "
              "bit); difference RMS %.4f m, worst %.4f m, %.4f rad; live stamps later (the input's delay) by "
              "median %.3f ms, worst %.3f ms\n",
              p.matched, lockstep.estimates.size(), p.same_pose, p.rms_m, p.worst_m, p.worst_rad, p.offset_median_ms,
              p.offset_worst_ms);
  std::printf("  lockstep replay of the node's recorded inputs: %zu of the %zu estimates the node published identical "
              "to the bit (%zu replayed, exit status %d); %zu of them heard on LCM, %zu identical\n",
              identical, wrote.size(), again.size(), replay_rc, live.size(), over_lcm.identical);
  std::printf("  inputs: %lld messages sent as %lld CAN frames, %lld frames received; %lld handed to the loop, %lld "
              "rejected by the HAL with a reason, %lld scans left incomplete by the reassembler (%lld counted "
              "rejects) (%s); %zu landmark sightings on LCM, %lld taken\n",
              sent, frames, rx_frames, taken, rejected, scans_lost, scan_rejects,
              result.inputs_all_accounted ? "every one accounted for" : "SOME LOST", landmarks, landmarks_taken);
  std::printf("  estimator_node: exit status %d; its summary in %s, its estimates in %s\n", result.node_exit,
              (dir / "node.txt").string().c_str(), (dir / "live.lcmlog").string().c_str());

  nlohmann::json j;
  j["can_interface"] = o.can_interface;
  j["lcm_url"] = o.lcm_url;
  j["played_s"] = played_s;
  j["node_behind_s"] = caught_up_s;
  j["clock_offset_ns"] = offset_ns;
  j["lockstep"] = metrics_of(km, lockstep.estimates.size());
  j["lockstep"]["inputs_rejected"] = lockstep_rejects;
  j["live"] = metrics_of(lm, live.size());
  j["live"]["inputs_rejected"] = rejected;
  j["paired"] = {{"matched", p.matched},
                 {"same_pose", p.same_pose},
                 {"rms_difference_m", p.rms_m},
                 {"worst_position_m", p.worst_m},
                 {"worst_heading_rad", p.worst_rad},
                 {"offset_median_ms", p.offset_median_ms},
                 {"offset_worst_ms", p.offset_worst_ms}};
  j["replay_of_recorded_inputs"] = {
      {"exit_status", replay_rc},
      {"published", wrote.size()},
      {"replayed", again.size()},
      {"identical", identical},
      {"all_identical", !wrote.empty() && identical == wrote.size() && again.size() == wrote.size()}};
  j["heard_on_lcm"] = {{"estimates", live.size()}, {"paired", over_lcm.matched}, {"identical", over_lcm.identical}};
  j["inputs"] = {{"messages_sent", sent},   {"frames_sent", frames},         {"frames_received", rx_frames},
                 {"taken", taken},          {"rejected", rejected},          {"scans_sent", scans_sent},
                 {"scans_incomplete", scans_lost}, {"scan_reassembly_rejects", scan_rejects},
                 {"landmarks_on_lcm", landmarks},
                 {"landmarks_taken", landmarks_taken}, {"all_accounted", result.inputs_all_accounted}};
  j["nodes"] = nlohmann::json::array({{{"exit_status", result.node_exit}, {"summary", (dir / "node.txt").string()}}});
  std::ofstream(dir / "live.json") << j.dump(2) << "\n";
  return result;
}

}  // namespace sim
