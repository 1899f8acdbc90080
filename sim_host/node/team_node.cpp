// One robot's node of a cooperative EKF-SLAM team (node/team_node.hpp).
#include "node/team_node.hpp"

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>

#include <est_lcm/ground_truth_t.hpp>
#include <est_lcm/pose_estimate_t.hpp>

#include "hal/lcm/lcm_backend.hpp"
#include "hal/lcm/lcm_guard.hpp"
#include "hal/team/lcm.hpp"
#include "hal/team/validator.hpp"
#include "node/pacer.hpp"
#include "node/view_feed.hpp"
#include "view/live_view.hpp"

namespace node {

namespace {
volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

// Whether the publisher drops its message of step seq: a hash of (seed, robot, seq) against the share, so a lossy
// run is reproducible and every node of the team can be told which of its messages the network lost.
bool dropped(std::uint64_t seed, std::int32_t robot, std::uint32_t seq, double share) {
  if (share <= 0.0) return false;
  std::uint64_t z = seed ^ (static_cast<std::uint64_t>(static_cast<std::uint32_t>(robot)) << 32) ^ seq;
  z += 0x9e3779b97f4a7c15ull;  // splitmix64
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53 < share;
}

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

std::string own_team_channel(std::int32_t robot_id) { return "EST_TEAM_OWN_" + std::to_string(robot_id); }
std::string team_pose_channel(std::int32_t robot_id) { return "EST_POSE_" + std::to_string(robot_id); }
std::string team_truth_channel(std::int32_t robot_id) { return "EST_GROUND_TRUTH_" + std::to_string(robot_id); }

void add_team_node_options(CLI::App& app, TeamNodeConfig& c) {
  const char* g = "Team node (--filter coop-ekf)";
  app.add_option("--filter", "coop-ekf: cooperative EKF-SLAM of a team of holonomic point robots")
      ->check(CLI::IsMember({"coop-ekf"}))->required()->group(g);
  app.add_option("--robot-id", c.robot_id, "this robot's id in the team (0..team size - 1)")
      ->capture_default_str()->check(CLI::Range(0, kTeamMaxRobots - 1))->group(g);
  app.add_option("--lcm", c.lcm_url, "LCM URL of the own inputs and the team channel (default: LCM's)")->group(g);
  app.add_option("--ch-team-own", c.own_channel, "the robot's own step messages in (default EST_TEAM_OWN_<id>)")
      ->group(g);
  app.add_option("--ch-team", c.team_channel, "the team channel, out and in")->capture_default_str()->group(g);
  app.add_option("--team-out", c.out_path, "one line per closed step: seq, status, the team's mean (hex floats), "
                                          "a digest of its covariance")->group(g);
  app.add_option("--team-counts", c.counts_path, "every counter at the end, a 'name value' line each")->group(g);
  app.add_option("--replay", c.replay_path,
                 "a team run's LCM log (sim_host run's run.lcmlog): EST_TEAM_OWN_<id> as the own messages, the other "
                 "EST_TEAM_OWN_<b> as the team's, in lockstep; nothing published")->check(CLI::ExistingFile)->group(g);
  app.add_option("--duration", c.duration_s, "stop after this many seconds (0: no limit)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(g);
  app.add_option("--idle-exit", c.idle_exit_s, "stop this many seconds after the own messages stopped (0: never)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(g);
  app.add_option("--drop-share", c.drop_share, "drop this share of the team messages this node publishes")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0))->group(g);
  app.add_option("--drop-seed", c.seed, "seed of the drops")->capture_default_str()->group(g);
  app.add_option_function<std::vector<std::uint32_t>>(
         "--silent-steps",
         [&c](const std::vector<std::uint32_t>& v) {
           c.silent_from = v[0];
           c.silent_to = v[1];
         },
         "FROM,TO: publish nothing for these steps (the robot falls silent to the team, then rejoins)")
      ->delimiter(',')->expected(2)->group(g);
  app.add_flag("--quiet", c.quiet, "no summary on stderr at the end")->group(g);
  add_view_options(app, c.view_port, c.view_wait, c.replay_speed,
                   "every robot's truth and estimate with its 2-sigma ellipse, the landmarks, the status");
  add_team_spec_options(app, c.spec);
}

void finish_team_node_options(TeamNodeConfig& c) {
  try {
    check_team_spec(c.spec);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--team-*", e.what());
  }
  if (c.robot_id >= c.spec.estimator.robots) throw CLI::ValidationError("--robot-id", "outside the team");
  if (c.own_channel.empty()) c.own_channel = own_team_channel(c.robot_id);
  if (c.view_wait && (c.view_port == 0 || c.replay_path.empty()))
    throw CLI::ValidationError("--view-wait", "needs --view PORT and a replay");
  c.replay_speed = replay_speed_default(c.replay_speed, c.view_port);
}

struct TeamNode::Impl {
  TeamNodeConfig cfg;
  ::lcm::LCM lcm;
  hal::lcm::LcmOutputs out;
  hal::team::TeamValidator validator;
  TeamWindow window;
  TeamEstimator est;
  std::ofstream lines;
  est::team::TeamMessage scratch;
  hal::lcm::LcmRejectCounters decode_rejects;
  std::uint32_t own_received = 0, own_refused = 0, published = 0, dropped_out = 0, echoes = 0;
  double last_own_s = -1.0;
  std::string pose_channel;
  std::uint32_t poses_published = 0;
  std::unique_ptr<view::LiveView> view;  // --view

  static hal::lcm::Channels channels(const TeamNodeConfig& c) {
    hal::lcm::Channels ch;
    ch.team = c.team_channel;
    return ch;
  }

  // A replay publishes nothing: its LCM is the in-process one.
  explicit Impl(const TeamNodeConfig& c)
      : cfg(c), lcm(c.replay_path.empty() ? c.lcm_url : "memq://"), out(lcm, channels(c)),
        validator(c.spec.estimator.robots, c.robot_id), pose_channel(team_pose_channel(c.robot_id)) {
    if (!lcm.good()) throw std::invalid_argument("LCM could not start on '" + c.lcm_url + "'");
    start_team(cfg.spec, window, est);
    if (!cfg.out_path.empty()) {
      lines.open(cfg.out_path);
      if (!lines) throw std::invalid_argument("cannot write " + cfg.out_path);
      lines << team_estimate_header() << "\n";
    }
    lcm.subscribe(cfg.own_channel, &Impl::on_own, this);
    lcm.subscribe(cfg.team_channel, &Impl::on_team, this);
    if (cfg.view_port != 0) {
      view = open_view(cfg.view_port, "estimator_node coop-ekf", cfg.spec.estimator.robots);
      for (std::int32_t a = 0; a < cfg.spec.estimator.robots; ++a)
        lcm.subscribe(team_truth_channel(a), &Impl::on_truth, this);
    }
  }

  // EST_GROUND_TRUTH_<a> to the view (a team run's log, or live when the simulator publishes it).
  void on_truth(const ::lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    const std::string prefix = "EST_GROUND_TRUTH_";
    if (!view || channel.compare(0, prefix.size(), prefix) != 0) return;
    char* end = nullptr;
    const long a = std::strtol(channel.c_str() + prefix.size(), &end, 10);
    if (end == nullptr || *end != '\0' || a < 0 || a >= cfg.spec.estimator.robots) return;
    est_lcm::ground_truth_t g;
    if (g.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) < 0) return;
    view->publish_team_truth(static_cast<int>(a), g.stamp_ns,
                             {static_cast<double>(g.x_m), static_cast<double>(g.y_m), static_cast<double>(g.theta_rad)});
  }

  bool decode(const ::lcm::ReceiveBuffer* rbuf) {
    est_lcm::team_message_t m{};
    hal::lcm::LcmReject r =
        hal::lcm::decode_guarded(rbuf->data, rbuf->data_size, m, std::int64_t{est::team::kMaxTeamMeasurements});
    if (r == hal::lcm::LcmReject::none) r = hal::lcm::to_hal(m, scratch);
    if (r != hal::lcm::LcmReject::none) decode_rejects.add(r);
    return r == hal::lcm::LcmReject::none;
  }

  void close(std::uint32_t seq, const est::team::TeamMessage* const* msgs) {
    est.step(seq, msgs);
    if (lines.is_open()) lines << team_estimate_line(seq, est) << "\n";
    // The step's stamp (its messages all carry it).
    est_lcm::pose_estimate_t p{};
    for (std::int32_t a = 0; a < cfg.spec.estimator.robots; ++a)
      if (msgs[a] != nullptr) {
        p.stamp_ns = msgs[a]->stamp_ns;
        break;
      }
    if (view) feed_team(*view, est, cfg.robot_id, p.stamp_ns);
    if (!cfg.replay_path.empty()) return;
    // The own robot's estimate.
    const auto& slam = est.slam();
    p.x_m = slam.robot(cfg.robot_id)(0);
    p.y_m = slam.robot(cfg.robot_id)(1);
    p.covariance[0] = slam.covariance()(2 * cfg.robot_id, 2 * cfg.robot_id);
    p.covariance[1] = p.covariance[3] = slam.covariance()(2 * cfg.robot_id, 2 * cfg.robot_id + 1);
    p.covariance[4] = slam.covariance()(2 * cfg.robot_id + 1, 2 * cfg.robot_id + 1);
    if (lcm.publish(pose_channel, &p) == 0) ++poses_published;
  }

  void push(const est::team::TeamMessage& m) {
    window.push(m, [this](std::uint32_t seq, const est::team::TeamMessage* const* msgs) { close(seq, msgs); });
  }

  // The log's EST_TEAM_OWN_<b>, each as it would have come in live: the own robot's, or a teammate's.
  void replay() {
    ::lcm::LogFile log(cfg.replay_path, "r");
    if (!log.good()) throw std::invalid_argument("cannot read the LCM log " + cfg.replay_path);
    const std::string prefix = "EST_TEAM_OWN_", truth = "EST_GROUND_TRUTH_";
    Pacer pacer(cfg.replay_speed);  // with --view: the log's receive times, scaled
    while (const ::lcm::LogEvent* e = log.readNextEvent()) {
      if (g_stop != 0) break;
      const bool is_truth = view && e->channel.compare(0, truth.size(), truth) == 0;
      if (!is_truth && e->channel.compare(0, prefix.size(), prefix) != 0) continue;
      pacer.at(e->timestamp * 1000);  // us
      ::lcm::ReceiveBuffer b{e->data, static_cast<std::uint32_t>(e->datalen), e->timestamp};
      if (is_truth) {
        on_truth(&b, e->channel);
        continue;
      }
      if (e->channel == cfg.own_channel)
        on_own(&b, e->channel);
      else
        on_team(&b, e->channel);
    }
  }

  // The robot's own message: into its window, and out to the team (unless the lossy network drops it).
  void on_own(const ::lcm::ReceiveBuffer* rbuf, const std::string&) {
    if (!decode(rbuf)) return;
    last_own_s = now_s();
    if (scratch.robot != cfg.robot_id ||
        est::team::check(scratch, cfg.spec.estimator.robots) != est::team::TeamReject::none) {
      ++own_refused;
      return;
    }
    ++own_received;
    const bool silent = scratch.seq >= cfg.silent_from && scratch.seq <= cfg.silent_to && cfg.silent_to > 0;
    if (silent || dropped(cfg.seed, cfg.robot_id, scratch.seq, cfg.drop_share)) {
      ++dropped_out;
    } else if (!cfg.replay_path.empty()) {
      // a replay: the team's messages are in the log
    } else {
      out.publish_team(scratch);
      ++published;
    }
    push(scratch);
  }

  // A teammate's message: validated (own echoes, duplicates, unknown robots refused; out of order counted) first.
  void on_team(const ::lcm::ReceiveBuffer* rbuf, const std::string&) {
    if (!decode(rbuf)) return;
    if (scratch.robot == cfg.robot_id) {  // UDP multicast loops the node's own publication back: not a teammate's
      ++echoes;
      return;
    }
    if (hal::team::TeamValidator::accepted(validator.check(scratch))) push(scratch);
  }
};

TeamNode::TeamNode(const TeamNodeConfig& config) : impl_(std::make_unique<Impl>(config)) {}
TeamNode::~TeamNode() = default;

int TeamNode::run() {
  Impl& m = *impl_;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const double t0 = now_s();
  if (m.view && m.cfg.view_wait) {
    std::fprintf(stderr, "estimator_node coop-ekf: waiting for a viewer\n");
    wait_for_viewer(*m.view, [] { return g_stop != 0; });
  }
  if (!m.cfg.replay_path.empty())
    m.replay();
  else if (!m.cfg.quiet)
    std::fprintf(stderr, "estimator_node coop-ekf robot %d: running (own %s, team %s, estimates %s)\n", m.cfg.robot_id,
                 m.cfg.own_channel.c_str(), m.cfg.team_channel.c_str(), m.pose_channel.c_str());
  while (g_stop == 0 && m.cfg.replay_path.empty()) {
    m.lcm.handleTimeout(20);
    const double t = now_s();
    if (m.cfg.duration_s > 0.0 && t - t0 >= m.cfg.duration_s) break;
    if (m.cfg.idle_exit_s > 0.0 && m.last_own_s >= 0.0 && t - m.last_own_s >= m.cfg.idle_exit_s) break;
  }
  // Let the teammates' last messages in, then close what is open.
  for (int i = 0; i < 10 && m.cfg.replay_path.empty(); ++i) m.lcm.handleTimeout(20);
  m.window.flush([&m](std::uint32_t seq, const est::team::TeamMessage* const* msgs) { m.close(seq, msgs); });
  m.lines.flush();
  if (m.view) m.view->stop();
  if (!m.cfg.counts_path.empty()) {
    std::ofstream c(m.cfg.counts_path);
    const auto& w = m.window.counters();
    const auto& v = m.validator.counts();
    using est::team::TeamReject;
    c << "own_received " << m.own_received << "\nown_refused " << m.own_refused << "\npublished " << m.published
      << "\ndropped_out " << m.dropped_out << "\nin_order " << v[TeamReject::none] << "\nout_of_order "
      << v[TeamReject::out_of_order] << "\nmalformed " << v[TeamReject::malformed] << "\nunknown_robot "
      << v[TeamReject::unknown_robot] << "\nduplicate " << v[TeamReject::duplicate] << "\nundecodable "
      << m.decode_rejects.total() << "\nlate " << w.of(TeamReject::late) << "\nsteps_closed " << w.steps_closed
      << "\nsteps_complete " << w.steps_complete << "\n";
    for (int a = 0; a < m.cfg.spec.estimator.robots; ++a) c << "missing_" << a << " " << w.missing[a] << "\n";
    if (!c) return 1;
  }
  return m.lines.is_open() && !m.lines ? 1 : 0;
}

void TeamNode::print_summary(std::FILE* f) const {
  const Impl& m = *impl_;
  const auto& w = m.window.counters();
  const auto& v = m.validator.counts();
  using est::team::TeamReject;
  std::fprintf(f, "estimator_node coop-ekf robot %d of %d%s: %u own messages (%u refused), %u published, %u dropped by "
                  "--drop-share or --silent-steps, %u came back (multicast loop); %u estimates on %s\n",
               m.cfg.robot_id, m.cfg.spec.estimator.robots, m.cfg.replay_path.empty() ? "" : " (replay)",
               m.own_received, m.own_refused, m.published, m.dropped_out, m.echoes, m.poses_published,
               m.pose_channel.c_str());
  std::fprintf(f, "  team messages in: %u in order, %u out of order; refused: %u malformed, %u unknown robot, %u "
                  "duplicate; %u undecodable\n", v[TeamReject::none], v[TeamReject::out_of_order],
               v[TeamReject::malformed], v[TeamReject::unknown_robot], v[TeamReject::duplicate],
               m.decode_rejects.total());
  std::fprintf(f, "  window: %u steps closed, %u complete, %u late messages refused; missing per robot:",
               w.steps_closed, w.steps_complete, w.of(TeamReject::late));
  for (int a = 0; a < m.cfg.spec.estimator.robots; ++a) std::fprintf(f, " %u", w.missing[a]);
  const auto& c = m.est.slam().counters();
  std::fprintf(f, "\n  estimator: %u measurements fused, %u gated out, %u pending, %u refused otherwise\n",
               c.accepted, c.gated_out, c.pending, c.rejected() - c.gated_out);
  if (m.view) std::fprintf(f, "  view: %s\n", view_counters_line(*m.view).c_str());
}

}  // namespace node
