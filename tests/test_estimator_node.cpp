// estimator_node as a library (sim_host/node/node.hpp), driven in process: a NodeConfig from the same options the
// executable parses, Node::run(), then its counters. Lockstep replay is deterministic (the same log gives the same
// output log, byte for byte) and tracks the truth, with MCL and with the EKF, from an LCM log and from a candump log;
// the inputs a run records replay to its estimates; bad inputs in a log are rejected and counted by reason; every
// motion model runs on the inputs it uses. One case runs the executable: a live node stops cleanly on SIGTERM and
// SIGINT with its exit status and its summary. (Live over CAN: the VM test, tests/test_estimator_hil.cpp.)
#include <catch2/catch.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <vector>

#include <est_lcm/encoder_ticks_t.hpp>
#include <est_lcm/range_scan_t.hpp>
#include <est_lcm/slam_map_t.hpp>
#include <est_lcm/steering_t.hpp>

#include "hal/can/candump.hpp"
#include "hal/can/estimate_frames.hpp"
#include "hal/can/sample_frames.hpp"
#include "hal/lcm/lcm_backend.hpp"
#include "hal/sensors/range_scan/can_frames.hpp"
#include "node/node.hpp"
#include "node/node_config.hpp"
#include "node_harness.hpp"
#include "office_sensor_log.hpp"
#include "est/map/landmark_map.hpp"
#include "world/office_map.hpp"

namespace {

using namespace est::test;
using est::loop::InputKind;

const std::string kNode = ESTIMATOR_NODE_EXE;

// A scratch folder per process (ctest may run the cases in parallel), removed at exit unless EST_KEEP_SCRATCH is set.
struct Scratch {
  std::string dir;
  Scratch() {
    char tmpl[] = "/tmp/est_node_XXXXXX";
    const char* d = mkdtemp(tmpl);
    dir = d != nullptr ? d : "/tmp";
  }
  ~Scratch() {
    if (std::getenv("EST_KEEP_SCRATCH") != nullptr)
      std::fprintf(stderr, "scratch kept in %s\n", dir.c_str());
    else if (dir != "/tmp")
      std::filesystem::remove_all(dir);
  }
};
std::string tmp(const std::string& name) {
  static const Scratch scratch;
  return scratch.dir + "/" + name;
}

std::string pose_arg(const est::Pose2& p) {
  char b[96];
  std::snprintf(b, sizeof b, "%.6f,%.6f,%.6f", static_cast<double>(p.x), static_cast<double>(p.y),
                static_cast<double>(p.theta));
  return b;
}

// The office stream, written once per process; and one with the base's twist and odometry besides.
const OfficeStream& stream() {
  static const OfficeStream s = write_office_stream(tmp("stream.lcmlog"));
  return s;
}
const OfficeStream& base_stream() {
  static const OfficeStream s = [] {
    OfficeStreamSpec spec;
    spec.twist = true;
    spec.odometry = true;
    return write_office_stream(tmp("base.lcmlog"), spec);
  }();
  return s;
}

// A NodeConfig as estimator_node builds it from its command line (the same options, defaults and checks).
node::NodeConfig node_config(const std::vector<std::string>& args) {
  CLI::App app;
  node::NodeConfig c;
  node::add_options(app, c);
  std::vector<const char*> argv{"estimator_node"};
  for (const std::string& a : args) argv.push_back(a.c_str());
  app.parse(static_cast<int>(argv.size()), argv.data());
  node::finish_options(app, c);
  return c;
}

std::vector<std::string> replay_args(const std::string& in, const std::string& out,
                                     const std::vector<std::string>& extra = {}) {
  std::vector<std::string> a = {"--replay", in,     "--out",  out, "--map", "office", "--particles", "500",
                                "--seed",   "3",    "--initial-pose", pose_arg(stream().start)};
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}

// The summary a node prints, as text.
std::string summary_of(const node::Node& n) {
  char* buf = nullptr;
  std::size_t size = 0;
  std::FILE* f = open_memstream(&buf, &size);
  REQUIRE(f != nullptr);
  n.print_summary(f);
  std::fclose(f);
  std::string s(buf, size);
  std::free(buf);
  return s;
}

// What a run did, kept after the node is gone (its output logs are complete only once it is destroyed).
struct Finished {
  std::uint64_t inputs[est::loop::kInputKindCount] = {};
  est::loop::LoopCounters loop;
  std::uint64_t estimates = 0, log_events = 0, log_inputs = 0;
  std::uint32_t rejects = 0;
  std::string summary;
  std::uint64_t to_loop(InputKind k) const { return inputs[est::loop::index_of(k)]; }
};
Finished finish(std::unique_ptr<node::Node>& n) {
  Finished f;
  for (const est::loop::InputKindInfo& k : est::loop::kInputKinds) f.inputs[est::loop::index_of(k.kind)] = n->inputs_to_loop(k.kind);
  f.loop = n->pipeline().loop_counters();
  f.estimates = n->estimates();
  f.log_events = n->log_events();
  f.log_inputs = n->log_inputs();
  f.rejects = n->rejects_total();
  f.summary = summary_of(*n);
  n.reset();
  return f;
}
Finished run_and_close(const node::NodeConfig& c) {
  auto n = std::make_unique<node::Node>(c);
  REQUIRE(n->run() == 0);
  return finish(n);
}

// The largest position and heading errors of the estimates against the truth at their times.
template <typename Estimates>
std::pair<double, double> worst_errors(const Estimates& est, const OfficeStream& s) {
  double worst_m = 0.0, worst_rad = 0.0;
  for (const auto& e : est) {
    const std::size_t k = static_cast<std::size_t>((e.stamp_ns - s.truth_t.front()) / (10 * hal::kNsPerMs));
    REQUIRE(k < s.truth.size());
    worst_m = std::max(worst_m, static_cast<double>(std::hypot(e.x_m - s.truth[k].x, e.y_m - s.truth[k].y)));
    worst_rad = std::max(worst_rad, std::fabs(wrap_angle(static_cast<double>(e.theta_rad - s.truth[k].theta))));
  }
  return {worst_m, worst_rad};
}

// The sensor messages of an LCM log as the frames a bus would carry (hal::can::SampleFrames), into a candump log,
// each frame stamped with its message's stamp_ns (what can_player --write does). Returns the frames written.
struct CandumpWriter final : hal::PortImplementation<CandumpWriter, hal::SensorPort> {
  std::ofstream out;
  hal::can::SampleFrames frames;
  std::vector<hal::can::CanFrame> buf = std::vector<hal::can::CanFrame>(hal::can::scan_frame_count(1081));
  std::size_t written = 0, samples = 0;
  template <typename Raw>
  void handle(const Raw& s) {
    const std::size_t n = frames.encode(s, buf.data(), buf.size());
    if (n > 0) ++samples;
    for (std::size_t i = 0; i < n; ++i) {
      char line[hal::can::kCandumpLineMax];
      out.write(line, static_cast<std::streamsize>(hal::can::format_candump_line(buf[i], s.stamp_ns, "vcan0", line)));
      ++written;
    }
  }
};
std::size_t write_candump(const std::string& lcm_log, const std::string& path, std::size_t* samples = nullptr) {
  CandumpWriter w;
  w.out.open(path);
  ::lcm::LCM memq("memq://");
  hal::lcm::InputConfig ic;
  ic.max_ranges = 4095;
  hal::lcm::LcmInputs in(memq, ic, w);
  ::lcm::LogFile log(lcm_log, "r");
  REQUIRE(log.good());
  while (const ::lcm::LogEvent* ev = log.readNextEvent()) {
    if (!in.is_input_channel(ev->channel)) continue;
    memq.publish(ev->channel, ev->data, static_cast<unsigned>(ev->datalen));
    memq.handle();
  }
  if (samples != nullptr) *samples = w.samples;
  return w.written;
}

}  // namespace

TEST_CASE("replaying the same log twice gives byte-identical output logs that track the truth", "[node]") {
  const OfficeStream& s = stream();
  auto a = std::make_unique<node::Node>(node_config(replay_args(tmp("stream.lcmlog"), tmp("a.lcmlog"))));
  REQUIRE(a->run() == 0);
  run_and_close(node_config(replay_args(tmp("stream.lcmlog"), tmp("b.lcmlog"))));
  const Finished done = finish(a);  // its counters, and its output logs closed
  const std::string bytes = read_text(tmp("a.lcmlog"));
  REQUIRE(bytes.size() > 10000u);
  CHECK(bytes == read_text(tmp("b.lcmlog")));

  // And the estimates are worth replaying: every one within 0.3 m and 0.15 rad of the truth at its time (the
  // tracking error of this 500-particle filter is ~0.05 m; the bound leaves room for its spread, not for a failure).
  const auto est = read_estimates(tmp("a.lcmlog"));
  REQUIRE(est.size() >= 590u);  // 6 s at 100 Hz, plus one per scan
  CHECK(done.estimates == est.size());
  const auto [worst_m, worst_rad] = worst_errors(est, s);
  INFO("worst position error " << worst_m << " m, heading " << worst_rad << " rad");
  CHECK(worst_m < 0.3);
  CHECK(worst_rad < 0.15);
  CHECK(done.to_loop(InputKind::wheel_ticks) == s.encoder_messages);
  CHECK(done.to_loop(InputKind::scan) == s.scan_messages);
  CHECK(done.to_loop(InputKind::landmark) == s.landmark_messages);  // validated, then unused by MCL
  CHECK(done.log_inputs == s.encoder_messages + s.scan_messages + s.landmark_messages);
  CHECK(done.log_events == done.log_inputs + s.truth.size());  // the ground truth is no input
  const est::loop::LoopCounters& lc = done.loop;
  CHECK(lc.corrections == s.scan_messages);
  CHECK(lc.overruns == 0u);  // replay does not time its steps
  CHECK(lc.unused == s.landmark_features);
  CHECK(done.rejects == 0u);
  // The summary says the same.
  const std::string& summary = done.summary;
  CHECK(summary_value(summary, "  inputs:", "wheel_ticks") == static_cast<long long>(s.encoder_messages));
  CHECK(summary_value(summary, "  inputs:", "scan") == static_cast<long long>(s.scan_messages));
  CHECK(summary_value(summary, "  loop:", "corrections") == static_cast<long long>(s.scan_messages));
  CHECK(summary.find("estimator_node summary (replay)") != std::string::npos);
}

TEST_CASE("a replay refuses a file that is not an LCM log, and replays a cut log up to the cut, counting it",
          "[node]") {
  stream();
  const std::string junk = tmp("junk.lcmlog");
  {
    std::ofstream o(junk, std::ios::binary);
    std::uint32_t x = 7;
    for (int i = 0; i < 5000; ++i) {
      x = x * 1664525u + 1013904223u;
      o.put(static_cast<char>(x >> 24));
    }
  }
  auto bad = std::make_unique<node::Node>(node_config(replay_args(junk, tmp("junk_out.lcmlog"))));
  CHECK(bad->run() != 0);
  CHECK(bad->log_events() == 0);
  CHECK(bad->log_problems() == 1);
  bad.reset();

  std::ifstream in(tmp("stream.lcmlog"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  REQUIRE(bytes.size() > 1000u);
  std::ofstream(tmp("cut.lcmlog"), std::ios::binary) << bytes.substr(0, bytes.size() / 2 + 7);
  auto cut = std::make_unique<node::Node>(node_config(replay_args(tmp("cut.lcmlog"), tmp("cut_out.lcmlog"))));
  REQUIRE(cut->run() == 0);
  CHECK(cut->log_problems() == 1);
  CHECK(cut->log_events() > 100u);
  CHECK(cut->estimates() > 0u);
  CHECK(summary_of(*cut).find("problems=1") != std::string::npos);
}

TEST_CASE("a beam-model table no host has room for is refused before it is allocated, naming the option", "[node]") {
  // The office map (400 x 300 cells) at 65 536 headings: the cone caster's 7500 MiB, the range table's 15 000 MiB.
  for (const char* cast : {"cone", "table"}) {
    INFO(cast);
    const node::NodeConfig c = node_config(replay_args(
        tmp("stream.lcmlog"), tmp("huge_out.lcmlog"),
        {"--sensor-model", "beam", "--beam-cast", cast, "--heading-bins", "65536"}));
    CHECK_THROWS_WITH(node::Node(c), Catch::Contains("MiB") && Catch::Contains("lower --heading-bins"));
  }
}

TEST_CASE("with the EKF (--filter ekf) a replay of landmark sightings is deterministic and tracks the truth", "[node]") {
  const OfficeStream& s = stream();
  REQUIRE(s.landmark_messages > 20u);
  const std::vector<std::string> ekf = {"--filter", "ekf", "--landmarks", "office", "--initial-sigma", "0.05,0.02"};
  auto a = std::make_unique<node::Node>(node_config(replay_args(tmp("stream.lcmlog"), tmp("ekf_a.lcmlog"), ekf)));
  REQUIRE(a->run() == 0);
  REQUIRE(a->pipeline().ekf_counters() != nullptr);
  CHECK(a->pipeline().mcl_counters() == nullptr);
  CHECK(a->pipeline().description().find("EKF localization") != std::string::npos);
  const Finished done = finish(a);
  run_and_close(node_config(replay_args(tmp("stream.lcmlog"), tmp("ekf_b.lcmlog"), ekf)));
  CHECK(read_text(tmp("ekf_a.lcmlog")) == read_text(tmp("ekf_b.lcmlog")));
  const auto est = read_estimates(tmp("ekf_a.lcmlog"));
  REQUIRE(est.size() >= 595u);  // 6 s at 100 Hz (sightings fall on prediction times)
  const auto [worst_m, worst_rad] = worst_errors(est, s);
  // Posts 5 cm / 1.1 deg apart from the truth seen at 5 Hz: the EKF stays within centimetres (worst measured 0.03 m,
  // 0.053 rad; the heading is the weaker, with the node's odometry noise larger than the robot's).
  INFO("worst position error " << worst_m << " m, heading " << worst_rad << " rad");
  CHECK(worst_m < 0.1);
  CHECK(worst_rad < 0.1);
  const est::loop::LoopCounters& lc = done.loop;
  CHECK(done.to_loop(InputKind::landmark) == s.landmark_messages);
  CHECK(lc.unused == s.scan_messages);  // scans: not used
  CHECK(lc.corrections + lc.rejected == s.landmark_features);
  CHECK(lc.rejected <= 2u);  // gate misses only
  CHECK(lc.of(InputKind::landmark).accepted == s.landmark_features);
}

TEST_CASE("with the EKF and joint association (--joint-association) a replay pairs the posts without their ids, "
          "tracks the truth and says where every feature went", "[node]") {
  const OfficeStream& s = stream();
  REQUIRE(s.landmark_features > 40u);
  const std::vector<std::string> jcbb = {"--filter", "ekf", "--landmarks", "office", "--initial-sigma", "0.05,0.02",
                                         "--landmark-association", "ml", "--joint-association",
                                         "--lone-pairing-sigma", "0.3"};
  auto a = std::make_unique<node::Node>(node_config(replay_args(tmp("stream.lcmlog"), tmp("jcbb_a.lcmlog"), jcbb)));
  REQUIRE(a->run() == 0);
  REQUIRE(a->pipeline().joint_counters() != nullptr);
  const est::loop::JointAssociationCounters n = *a->pipeline().joint_counters();
  const Finished done = finish(a);
  INFO(done.summary);
  const auto est = read_estimates(tmp("jcbb_a.lcmlog"));
  REQUIRE(est.size() >= 595u);
  const auto [worst_m, worst_rad] = worst_errors(est, s);
  INFO("worst position error " << worst_m << " m, heading " << worst_rad << " rad");
  CHECK(worst_m < 0.1);
  CHECK(worst_rad < 0.1);
  // Every feature of every frame in one counter; from the true start nearly all paired, none refused as lone.
  CHECK(n.frames == s.landmark_messages);
  CHECK(n.features == s.landmark_features);
  CHECK(n.paired + n.unpaired == n.features);
  CHECK(n.paired * 10u >= n.features * 9u);
  CHECK(n.lone_refused == 0u);
  CHECK(summary_value(done.summary, "  jcbb:", "frames") == static_cast<long long>(n.frames));
  CHECK(summary_value(done.summary, "  jcbb:", "paired") == static_cast<long long>(n.paired));
  CHECK(summary_value(done.summary, "  jcbb:", "lone_refused") == 0);
  // Without joint association there is no such line (nor counters).
  auto plain = std::make_unique<node::Node>(node_config(replay_args(
      tmp("stream.lcmlog"), tmp("jcbb_b.lcmlog"), {"--filter", "ekf", "--landmarks", "office", "--initial-sigma",
                                                    "0.05,0.02", "--landmark-association", "ml"})));
  REQUIRE(plain->run() == 0);
  CHECK(plain->pipeline().joint_counters() == nullptr);
  CHECK(finish(plain).summary.find("  jcbb:") == std::string::npos);
}

TEST_CASE("with EKF-SLAM (--filter ekf-slam) a replay maps the posts it sees without a map or their ids, "
          "deterministically, and says where every feature went", "[node]") {
  const OfficeStream& s = stream();
  REQUIRE(s.landmark_features > 40u);
  const std::vector<std::string> slam = {"--filter", "ekf-slam", "--initial-sigma", "0.01,0.01"};
  auto a = std::make_unique<node::Node>(node_config(replay_args(tmp("stream.lcmlog"), tmp("slam_a.lcmlog"), slam)));
  REQUIRE(a->run() == 0);
  REQUIRE(a->pipeline().slam_counters() != nullptr);
  CHECK(a->pipeline().mcl_counters() == nullptr);
  CHECK(a->pipeline().description().find("EKF-SLAM") != std::string::npos);
  const est::loop::SlamAssociationCounters counters = *a->pipeline().slam_counters();
  const int landmarks = a->pipeline().slam_landmarks();
  const Finished done = finish(a);
  run_and_close(node_config(replay_args(tmp("stream.lcmlog"), tmp("slam_b.lcmlog"), slam)));
  CHECK(read_text(tmp("slam_a.lcmlog")) == read_text(tmp("slam_b.lcmlog")));
  const auto est = read_estimates(tmp("slam_a.lcmlog"));
  REQUIRE(est.size() >= 595u);
  const auto [worst_m, worst_rad] = worst_errors(est, s);
  INFO(done.summary);
  // From the true start, with no map: the map's frame drifts with the robot while it explores (6 landmarks mapped
  // in 3.6 m of travel, the node's odometry noise larger than the robot's). Measured 0.26 m and 0.12 rad at worst.
  INFO("worst position error " << worst_m << " m, heading " << worst_rad << " rad");
  CHECK(worst_m < 0.4);
  CHECK(worst_rad < 0.2);
  // Every feature in one counter; none refused; a post is mapped once it is seen in two frames.
  const est::loop::SlamAssociationCounters& n = counters;
  CHECK(n.features() == s.landmark_features);
  CHECK(n.frames == s.landmark_messages);
  CHECK(n.update_refused + n.insert_refused + n.map_full + n.tentative_full + n.bad_input == 0u);
  CHECK(n.created == static_cast<std::uint32_t>(landmarks));
  CHECK(landmarks >= 3);
  CHECK(n.associated > 10u * n.created);
  CHECK(done.to_loop(InputKind::landmark) == s.landmark_messages);
  CHECK(done.loop.unused == s.scan_messages);
  // The summary and the output log carry the map and the counters: the log's last slam_map_t is the final map.
  CHECK(summary_value(done.summary, "  slam:", "landmarks") == landmarks);
  CHECK(summary_value(done.summary, "  slam:", "associated") == static_cast<long long>(n.associated));
  est_lcm::slam_map_t m{};
  int maps = 0;
  ::lcm::LogFile log(tmp("slam_a.lcmlog"), "r");
  REQUIRE(log.good());
  while (const ::lcm::LogEvent* ev = log.readNextEvent())
    if (ev->channel == "EST_SLAM_MAP" && m.decode(ev->data, 0, static_cast<int>(ev->datalen)) > 0) ++maps;
  REQUIRE(maps >= 1);
  REQUIRE(m.num_landmarks == landmarks);
  CHECK(m.associated == n.associated);
  CHECK(m.tentative_forgotten == n.tentative_forgotten);
  // The map is consistent with the robot: carried by the rigid motion that puts the final estimate on the final true
  // pose, each landmark is within 0.15 m of a post (measured 0.05 m at worst; 0.5 m without that motion).
  est::LandmarkMapStorage<16> posts;
  est::sim::make_office_landmarks(posts);
  const auto& last = est.back();
  const est::Pose2& truth =
      s.truth[static_cast<std::size_t>((last.stamp_ns - s.truth_t.front()) / (10 * hal::kNsPerMs))];
  const double dtheta = static_cast<double>(truth.theta - last.theta_rad);
  const double c = std::cos(dtheta), sn = std::sin(dtheta);
  double worst_post_m = 0.0;
  for (int k = 0; k < m.num_landmarks; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const double dx = static_cast<double>(m.x_m[i] - last.x_m), dy = static_cast<double>(m.y_m[i] - last.y_m);
    const double x = static_cast<double>(truth.x) + c * dx - sn * dy, y = static_cast<double>(truth.y) + sn * dx + c * dy;
    double nearest = 1e9;
    for (std::int32_t j = 0; j < posts.size(); ++j)
      nearest = std::min(nearest, std::hypot(x - static_cast<double>(posts.view()[j].x),
                                             y - static_cast<double>(posts.view()[j].y)));
    worst_post_m = std::max(worst_post_m, nearest);
  }
  INFO("worst landmark from its post, in the robot's frame: " << worst_post_m << " m");
  CHECK(worst_post_m < 0.15);
}

TEST_CASE("the inputs a run records replay to its estimates, bit for bit", "[node]") {
  stream();
  const Finished first =
      run_and_close(node_config(replay_args(tmp("stream.lcmlog"), tmp("first.lcmlog"), {"--record-inputs", tmp("rec.lcmlog")})));
  const std::uint64_t first_inputs = first.log_inputs;
  const Finished again = run_and_close(node_config(replay_args(tmp("rec.lcmlog"), tmp("again.lcmlog"))));
  const auto a = read_estimates(tmp("first.lcmlog"));
  const auto b = read_estimates(tmp("again.lcmlog"));
  REQUIRE(a.size() > 500u);
  CHECK(first_difference(a, b) == -1);
  // The recording holds the validated inputs only (not the ground truth of the stream).
  CHECK(again.log_events == first_inputs);
  CHECK(again.log_inputs == first_inputs);
}

TEST_CASE("bad inputs in a log are rejected, counted by reason, and flagged in the next estimate", "[node]") {
  const std::string path = tmp("bad.lcmlog");
  {
    ::lcm::LogFile log(path, "w");
    std::vector<std::uint8_t> buf;
    auto put = [&](const std::string& ch, hal::TimeNs t, const auto& m) {
      buf.resize(static_cast<std::size_t>(m.getEncodedSize()));
      m.encode(buf.data(), 0, static_cast<int>(buf.size()));
      ::lcm::LogEvent e{};
      e.timestamp = t / 1000;
      e.channel = ch;
      e.datalen = static_cast<std::int32_t>(buf.size());
      e.data = buf.data();
      log.writeEvent(&e);
    };
    auto ticks = [](hal::TimeNs t, std::int32_t c) {
      est_lcm::encoder_ticks_t m{};
      m.num_wheels = 2;
      m.stamp_ns = t;
      m.counter_bits = 32;
      m.count = {c, c};
      return m;
    };
    auto steer = [](hal::TimeNs t, float a) {
      est_lcm::steering_t m{};
      m.stamp_ns = t;
      m.angle_rad = a;
      return m;
    };
    auto scan = [](hal::TimeNs t, float range_min, float fill) {
      est_lcm::range_scan_t m{};
      m.stamp_ns = t;
      m.angle_min_rad = -3.14159f;
      m.angle_increment_rad = 0.0174533f;
      m.range_min_m = range_min;
      m.range_max_m = 12.0f;
      m.scan_time_s = 0.1f;
      m.ranges_m.assign(360, fill);
      m.num_ranges = 360;
      return m;
    };
    const hal::TimeNs ms = hal::kNsPerMs;
    for (int k = 0; k <= 100; ++k) {
      const hal::TimeNs t = hal::kNsPerS + k * 10 * ms;
      put("EST_WHEEL_TICKS", t, ticks(t, 10 * k));
      if (k == 20) put("EST_WHEEL_TICKS", t, ticks(t, 10 * k));                // duplicate
      if (k == 30) put("EST_WHEEL_TICKS", t - 5 * ms, ticks(t - 5 * ms, 0));  // time backwards
      if (k == 40) put("EST_STEERING", t, steer(t, std::nanf("")));          // not finite
      if (k == 41) put("EST_STEERING", t, steer(t, 1.5f));                   // beyond the 0.7 rad stop
      if (k == 50) put("EST_RANGE_SCAN", t, scan(t, 20.0f, 3.0f));           // range_min above range_max
      if (k == 60) put("EST_RANGE_SCAN", t, scan(t, 0.05f, std::nanf("")));  // no usable beam
      if (k == 70) {
        const std::uint8_t garbage[5] = {1, 2, 3, 4, 5};
        ::lcm::LogEvent e{};
        e.timestamp = t / 1000;
        e.channel = "EST_WHEEL_TICKS";
        e.datalen = 5;
        e.data = const_cast<std::uint8_t*>(garbage);
        log.writeEvent(&e);
      }
    }
  }
  auto n = std::make_unique<node::Node>(node_config({"--replay", path, "--out", tmp("bad_out.lcmlog"), "--map",
                                                     "office", "--particles", "200", "--initial-pose", "5.5,7.3,0"}));
  REQUIRE(n->run() == 0);
  const std::string s = summary_of(*n);
  INFO(s);
  const hal::ValidatedInputs& gate = n->pipeline().gate();
  CHECK(gate.wheels().faults()[hal::Fault::duplicate] == 1u);
  CHECK(gate.wheels().faults()[hal::Fault::time_backwards] == 1u);
  CHECK(gate.steering().faults()[hal::Fault::not_finite] == 1u);
  CHECK(gate.steering().faults()[hal::Fault::out_of_range] == 1u);
  CHECK(gate.scan().faults()[hal::Fault::bad_geometry] == 1u);
  CHECK(gate.scan().faults()[hal::Fault::too_few_valid_beams] == 1u);
  CHECK(gate.faults().total() == 6u);
  CHECK(summary_value(s, "  rejects.lcm:", "malformed") == 1);  // the transport's own, in the summary
  CHECK(summary_value(s, "  rejects.wheel_ticks:", "duplicate") == 1);
  CHECK(n->rejects_total() == 7u);
  CHECK(summary_value(s, "  rejects:", "total") == 7);
  CHECK(n->inputs_to_loop(InputKind::wheel_ticks) == 101u);
  n.reset();  // closes the output log

  const auto est = read_estimates(tmp("bad_out.lcmlog"));
  REQUIRE(!est.empty());
  int flagged = 0;
  for (const auto& e : est) {
    CHECK(std::isfinite(e.x_m));
    CHECK(std::isfinite(e.y_m));
    CHECK(std::isfinite(e.theta_rad));
    if ((static_cast<std::uint32_t>(e.status) & hal::status::kInputRejected) != 0u) ++flagged;
  }
  CHECK(est.back().rejected_inputs == 7);
  // Each reject shows in the next estimate (the two steering rejects 10 ms apart fall in different estimates).
  CHECK(flagged == 7);
}

TEST_CASE("a candump log of the stream's bus frames replays (--replay-can) to estimates that track the truth, and "
          "--out-can writes the estimate frames",
          "[node]") {
  const OfficeStream& s = stream();
  std::size_t samples = 0;
  const std::size_t frames = write_candump(tmp("stream.lcmlog"), tmp("stream.candump"), &samples);
  REQUIRE(samples == s.encoder_messages + s.scan_messages);  // landmark sightings have no frame
  const std::vector<std::string> args = {"--replay-can", tmp("stream.candump"), "--out", tmp("can.lcmlog"),
                                         "--out-can", tmp("out.candump"), "--map", "office", "--particles", "500",
                                         "--seed", "3", "--initial-pose", pose_arg(s.start)};
  const Finished a = run_and_close(node_config(args));
  CHECK(a.log_events == frames);
  CHECK(a.log_inputs == frames);
  CHECK(a.to_loop(InputKind::wheel_ticks) == s.encoder_messages);  // 16-bit counters, unwrapped
  CHECK(a.to_loop(InputKind::scan) == s.scan_messages);
  CHECK(a.rejects == 0u);
  CHECK(summary_value(a.summary, "  rejects.can_frame:", "accepted") == static_cast<long long>(frames));
  CHECK(summary_value(a.summary, "  rejects.can_scan:", "completed") == static_cast<long long>(s.scan_messages));
  const auto est = read_estimates(tmp("can.lcmlog"));
  REQUIRE(est.size() >= 590u);
  const auto [worst_m, worst_rad] = worst_errors(est, s);
  INFO("worst position error " << worst_m << " m, heading " << worst_rad << " rad");
  CHECK(worst_m < 0.3);
  CHECK(worst_rad < 0.15);

  // Four frames per estimate, each line a candump line, decoding to the estimate's pose.
  std::ifstream in(tmp("out.candump"));
  std::string line;
  std::vector<hal::can::PoseEstimateMsg> poses;
  std::size_t lines = 0;
  while (std::getline(in, line)) {
    ++lines;
    hal::can::CanFrame f;
    hal::TimeNs stamp = 0;
    REQUIRE(hal::can::parse_candump_line(line.data(), line.size(), f, stamp) == hal::can::CandumpStatus::ok);
    hal::can::PoseEstimateMsg p;
    if (f.id == hal::can::dbc::kPoseEstimateId) {
      REQUIRE(hal::can::decode(f, p) == hal::can::CodecStatus::ok);
      poses.push_back(p);
    }
  }
  CHECK(lines == 4u * est.size());
  REQUIRE(poses.size() == est.size());
  for (std::size_t i = 0; i < est.size(); i += 97) {
    CHECK(poses[i].x_m == Approx(est[i].x_m).margin(6e-4));
    CHECK(poses[i].y_m == Approx(est[i].y_m).margin(6e-4));
  }
  // And deterministic, as the LCM replay is.
  std::vector<std::string> again = args;
  again[3] = tmp("can_b.lcmlog");
  again[5] = tmp("out_b.candump");
  run_and_close(node_config(again));
  CHECK(read_text(tmp("out.candump")) == read_text(tmp("out_b.candump")));
  CHECK(read_text(tmp("can.lcmlog")) == read_text(tmp("can_b.lcmlog")));
}

TEST_CASE("each motion model runs on the inputs it uses: velocity and omni on the twist, odometry on the odometry "
          "poses, diff-drive on the encoders",
          "[node]") {
  const OfficeStream& s = base_stream();
  REQUIRE(s.twist_messages == s.encoder_messages - 1);
  REQUIRE(s.odometry_messages == s.encoder_messages);
  struct Case {
    const char* model;
    InputKind motion;
  };
  for (const Case c : {Case{"velocity", InputKind::twist}, Case{"omni", InputKind::twist},
                       Case{"odometry", InputKind::odometry}, Case{"diff-drive", InputKind::wheel_ticks}}) {
    INFO("--model " << c.model);
    const std::string out = tmp(std::string("model_") + c.model + ".lcmlog");
    auto n = std::make_unique<node::Node>(node_config({"--replay", tmp("base.lcmlog"), "--out", out, "--model",
                                                       c.model, "--map", "office", "--particles", "500", "--seed", "3",
                                                       "--initial-pose", pose_arg(s.start)}));
    REQUIRE(n->run() == 0);
    CHECK(n->pipeline().inputs() == (c.motion | InputKind::scan));
    CHECK(n->pipeline().description().find(std::string(c.model) + " model") == 0u);
    const Finished done = finish(n);
    const est::loop::LoopCounters& lc = done.loop;
    const std::size_t motion_messages = c.motion == InputKind::twist      ? s.twist_messages
                                        : c.motion == InputKind::odometry ? s.odometry_messages
                                                                          : s.encoder_messages;
    CHECK(lc.of(c.motion).accepted == motion_messages);
    CHECK(lc.corrections == s.scan_messages);
    // Every other motion kind (and the landmark features) was validated and then counted unused, not rejected.
    const std::size_t all_motion = s.twist_messages + s.odometry_messages + s.encoder_messages;
    CHECK(lc.unused == all_motion - motion_messages + s.landmark_features);
    CHECK(lc.rejected == 0u);
    CHECK(done.rejects == 0u);
    const auto est = read_estimates(out);
    REQUIRE(est.size() >= 590u);
    const auto [worst_m, worst_rad] = worst_errors(est, s);
    INFO("worst position error " << worst_m << " m, heading " << worst_rad << " rad");
    CHECK(worst_m < 0.3);
    CHECK(worst_rad < 0.15);
  }
}

TEST_CASE("the options document every input, model and filter, and a configuration the node cannot run is refused",
          "[node]") {
  CLI::App app;
  node::NodeConfig c;
  node::add_options(app, c);
  const std::string h = app.help();
  for (const char* opt : {"--can", "--lcm", "--can-out", "--replay", "--replay-can", "--out", "--out-can",
                          "--record-inputs", "--model", "--sensor-model", "--track-width", "--frame-length",
                          "--velocity-noise", "--odometry-noise", "--omni-noise", "--omni-wheels", "--holonomic-noise",
                          "--map", "--initial-pose", "--global", "--particles", "--beam-stride", "--predict-hz",
                          "--twist-timeout", "--odometry-timeout", "--ch-twist", "--ch-odometry", "--ch-pose"})
    CHECK(h.find(opt) != std::string::npos);
  stream();
  const std::string log = tmp("stream.lcmlog");
  CHECK_THROWS_AS(node_config({"--map", "office", "--global"}), CLI::ValidationError);  // no input
  CHECK_THROWS_AS(node_config({"--replay", log, "--map", "office", "--global"}), CLI::ValidationError);  // no --out
  CHECK_THROWS_AS(node_config({"--replay", log, "--out", tmp("x.lcmlog"), "--filter", "ekf", "--global"}),
                  CLI::ValidationError);
  CHECK_THROWS_AS(node_config({"--replay", log, "--out", tmp("x.lcmlog"), "--initial-pose", "1,2,0", "--model",
                               "diff-drive", "--sensor-model", "steered"}),
                  CLI::ValidationError);
  CHECK_THROWS_AS(node_config({"--replay", log, "--out", tmp("x.lcmlog"), "--initial-pose", "1,2,0", "--model",
                               "tricycle"}),
                  CLI::ValidationError);
  // What the options set: the model, the per-kind staleness, the encoders of an omni base.
  const node::NodeConfig omni = node_config({"--replay", log, "--out", tmp("x.lcmlog"), "--initial-pose", "1,2,0",
                                             "--model", "omni", "--omni-wheels", "kiwi3", "--twist-timeout", "250"});
  CHECK(omni.spec.model == node::RobotModel::omni);
  CHECK(omni.spec.motion.omni_control.wheels.count == 3u);
  CHECK(omni.spec.limits.wheels.wheel_count == 3u);
  CHECK(omni.spec.timing.staleness[InputKind::twist] == 250 * hal::kNsPerMs);
  CHECK(omni.replay());
}

TEST_CASE("a live node stops cleanly on SIGTERM and SIGINT with exit status 0 and its summary", "[node][process]") {
  for (int sig : {SIGTERM, SIGINT}) {
    const std::string out = tmp("live_" + std::to_string(sig) + ".txt");
    const pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
      const std::string cmd = "exec " + kNode + " --lcm memq:// --map office --particles 100 --initial-pose 5.5,7.3,0 >" +
                              out + " 2>&1";
      execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    // The node has no inputs: it idles in poll() until the signal, whenever it comes (the summary must be there
    // however long it ran). Signalled once it says it is running, so that the handlers are installed.
    for (int i = 0; i < 500 && read_text(out).find("estimator_node: running") == std::string::npos; ++i)
      usleep(10000);
    REQUIRE(kill(pid, sig) == 0);
    int status = 0;
    REQUIRE(waitpid(pid, &status, 0) == pid);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    const std::string s = read_text(out);
    INFO(s);
    CHECK(s.find(sig == SIGTERM ? "stopped by SIGTERM" : "stopped by SIGINT") != std::string::npos);
    CHECK(summary_value(s, "  loop:", "inputs") == 0);
    CHECK(summary_value(s, "  rejects:", "total") == 0);
    CHECK(summary_value(s, "  inputs:", "wheel_ticks") == 0);
  }
}
