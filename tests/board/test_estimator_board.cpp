// estimator-board.elf (firmware/target/mps2/estimator_board_main.cpp) under qemu against estimator_node's lockstep
// replay of the same CAN frames on the same map: the board's estimate frames must equal the node's, byte for byte,
// and so must every estimate's float bits (the board's trace against the node's --out log). The stream is the
// office stream of tests/support/office_sensor_log.hpp (a diff drive on the office route, 100 Hz encoders, 10 Hz
// 360-beam scans), turned into estimator.dbc frames by can_player --write; the map is the office written as
// map_server files (office_map_files.hpp). The node's options come from the image's own configuration header
// (firmware/target/mps2/estimator_board_config.hpp), so the two rigs cannot drift apart.
//
// One binary for both boards: ctest gives the board, its qemu machine and the image through the environment
// (EST_BOARD, EST_QEMU_MACHINE, EST_BOARD_ELF) and runs it in a folder of its own, where the files stay for a look
// after a failure. Without the board's build the test is skipped (exit 77) with a message saying how to build it.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <sys/stat.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "est/loop/input_kinds.hpp"
#include "board_ros_map.hpp"
#include "estimator_board_config.hpp"
#include "hal/maps/ros_map_loader.hpp"
#include "node_harness.hpp"
#include "office_map_files.hpp"
#include "office_sensor_log.hpp"
#include "world/office_map.hpp"

namespace {

using namespace est::test;
using board::EstimatorBoardConfig;

const std::string kNode = ESTIMATOR_NODE_EXE;
const std::string kPlayer = CAN_PLAYER_EXE;
const std::string kSize = ARM_SIZE_EXE;  // empty when arm-none-eabi-size was not found

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr ? v : "";
}

bool exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

// A float as the node reads it back (9 significant digits: the same float after any correct decimal conversion).
std::string num(float v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", static_cast<double>(v));
  return b;
}
std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}
std::string ms(hal::TimeNs ns) { return num(static_cast<double>(ns) / 1.0e6); }  // the node's duration options
std::string pose(const est::Pose2& p) { return num(p.x) + "," + num(p.y) + "," + num(p.theta); }

// estimator_node's options for the rig of estimator_board_config.hpp (each constant's comment names its option).
std::string node_options() {
  using namespace board::rig;
  static_assert(std::is_same_v<EstimatorBoardConfig::Model, est::DiffDriveMotionModel> &&
                    EstimatorBoardConfig::kFilter == est::loop::Filter::mcl &&
                    std::is_same_v<EstimatorBoardConfig::ScanModel, est::loop::LikelihoodFieldScan>,
                "the rig's model, filter and range model are given to the node by name below: update them");
  const est::loop::LoopTiming& t = EstimatorBoardConfig::kTiming;
  using est::loop::InputKind;
  std::string o = "--model diff-drive --filter mcl --sensor-model likelihood-field";
  o += " --particles " + std::to_string(kParticles) + " --seed " + std::to_string(kSeed);
  o += " --beam-stride " + std::to_string(kBeamStride);
  o += " --initial-pose " + pose(kInitialPose) + " --initial-sigma " + num(kInitialSigmaXy) + "," +
       num(kInitialSigmaTheta);
  o += " --wheel-radius " + num(kDiffDrive.wheel_radius) + " --track-width " + num(kDiffDrive.track_width);
  o += " --ticks-per-rev " + std::to_string(kDiffDrive.ticks_per_rev);
  o += " --travel-sigma-per-m " + num(kDiffDrive.travel_sigma_per_m) + " --travel-sigma-floor " +
       num(kDiffDrive.travel_sigma_floor) + " --rot-sigma " + num(kDiffDrive.final_rot_sigma);
  o += " --z-hit " + num(kField.z_hit) + " --z-max " + num(kField.z_max) + " --z-rand " + num(kField.z_rand);
  o += " --sigma-hit " + num(kField.sigma_hit) + " --range-max " + num(kField.range_max) + " --max-distance " +
       num(kField.max_distance);
  o += " --sensor-mount " + pose(kSensorMount) + " --clearance " + num(kClearance) + " --cluster-cell " +
       num(kClusterCell);
  o += " --alpha-slow " + num(kMcl.alpha_slow) + " --alpha-fast " + num(kMcl.alpha_fast) + " --max-injection " +
       num(kMcl.max_injection_fraction);
  if (!kMcl.recovery) o += " --no-recovery";
  o += " --predict-hz " + num(1.0e9 / static_cast<double>(t.predict_period_ns));
  o += " --reorder-window " + ms(t.reorder_window_ns) + " --step-deadline " + ms(t.step_deadline_ns);
  o += " --encoder-timeout " + ms(t.staleness[InputKind::wheel_ticks]) + " --scan-timeout " +
       ms(t.staleness[InputKind::scan]);
  o += " --wheel-count " + std::to_string(kWheelCount) + " --max-age " + ms(kTimingLimits.max_age_ns) +
       " --max-future " + ms(kTimingLimits.max_future_ns);
  return o;
}

// The first line where two texts differ (1-based), with both lines; 0 when they are equal.
struct LineDifference {
  std::size_t line = 0;
  std::string a, b;
};
LineDifference first_line_difference(const std::string& a, const std::string& b) {
  std::istringstream sa(a), sb(b);
  std::string la, lb;
  for (std::size_t n = 1;; ++n) {
    const bool ga = static_cast<bool>(std::getline(sa, la)), gb = static_cast<bool>(std::getline(sb, lb));
    if (!ga && !gb) return {};
    if (!ga) la = "(end of file)";
    if (!gb) lb = "(end of file)";
    if (!ga || !gb || la != lb) return {n, la, lb};
  }
}

std::uint32_t bits(float f) {
  std::uint32_t v = 0;
  std::memcpy(&v, &f, sizeof v);
  return v;
}

// The node's estimates in the board trace's format (estimator_board_main.cpp, top of the file).
std::string trace_of(const std::vector<est_lcm::pose_estimate_t>& estimates) {
  std::string out;
  char b[16];
  for (const auto& e : estimates) {
    out += std::to_string(e.stamp_ns);
    for (float f : {e.x_m, e.y_m, e.theta_rad}) {
      std::snprintf(b, sizeof b, " %08x", bits(f));
      out += b;
    }
    for (float f : e.covariance) {
      std::snprintf(b, sizeof b, " %08x", bits(f));
      out += b;
    }
    std::snprintf(b, sizeof b, " %08x", static_cast<std::uint32_t>(e.status));
    out += b;
    std::snprintf(b, sizeof b, " %08x", static_cast<std::uint32_t>(e.rejected_inputs));
    out += b;
    out += "\n";
  }
  return out;
}

// The qemu command line of the board image with its arguments over semihosting (qemu reads ",," as a comma).
std::string board_command(const std::string& args) {
  std::string escaped;
  for (char c : args) escaped += c == ',' ? std::string(",,") : c == ' ' ? std::string(",arg=") : std::string(1, c);
  return "qemu-system-arm -M " + env("EST_QEMU_MACHINE") +
         " -nographic -monitor none -serial none -icount shift=10 -semihosting-config enable=on,target=native,arg=" +
         "estimator-board.elf,arg=" + escaped + " -kernel " + env("EST_BOARD_ELF");
}

// The hex value of `key=0x...` in the image's output, 0 when absent.
std::uint64_t hex_value(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(" " + key + "=0x");
  return at == std::string::npos ? 0u : std::strtoull(text.c_str() + at + key.size() + 4, nullptr, 16);
}

std::uint64_t host_grid_digest(const std::string& yaml) {
  auto grid = std::make_unique<est::OccupancyGridStorage<board::kMapMaxSide, board::kMapMaxSide>>();
  hal::maps::load_ros_map(yaml, *grid);
  return board::grid_digest(grid->grid());
}

std::size_t count_lines(const std::string& s) {
  std::size_t n = 0;
  for (char c : s) n += c == '\n' ? 1u : 0u;
  return n;
}

}  // namespace

TEST_CASE("the board image's estimate frames equal estimator_node's replay of the same frames, bit for bit",
          "[board]") {
  const std::string board = env("EST_BOARD"), machine = env("EST_QEMU_MACHINE"), elf = env("EST_BOARD_ELF");
  INFO("board " << board << " (qemu " << machine << "), image " << elf << ", in "
                 << std::filesystem::current_path().string());

  // The stream: 4 s of the office run (400 encoder samples, 41 scans), and its frames.
  OfficeStreamSpec spec;
  spec.duration_s = 4.0;
  const OfficeStream s = write_office_stream("stream.lcmlog", spec);
  REQUIRE(std::fabs(s.start.x - board::rig::kInitialPose.x) < 1e-4f);  // the rig starts where the stream does
  REQUIRE(std::fabs(s.start.y - board::rig::kInitialPose.y) < 1e-4f);
  REQUIRE(std::fabs(s.start.theta - board::rig::kInitialPose.theta) < 1e-4f);
  {
    const int rc = run_command(kPlayer + " stream.lcmlog --write in.candump --wheel-counter-bits 32", "player.txt");
    INFO(read_text("player.txt"));
    REQUIRE(rc == 0);
    REQUIRE(summary_value(read_text("player.txt"), "can_player:", "messages") ==
            static_cast<long long>(s.encoder_messages + s.scan_messages));
  }

  // The map, as files both read; loaded back by the host's loader it is the office, cell for cell.
  const MapFiles map = write_office_map_files(".", "office");
  {
    auto office = std::make_unique<est::OccupancyGridStorage<est::sim::kOfficeWidth, est::sim::kOfficeHeight>>();
    auto loaded = std::make_unique<est::OccupancyGridStorage<est::sim::kOfficeWidth, est::sim::kOfficeHeight>>();
    est::sim::make_office_map(*office);
    hal::maps::load_ros_map(map.yaml, *loaded);
    const est::OccupancyGrid a = office->grid(), b = loaded->grid();
    REQUIRE(a.width() == b.width());
    REQUIRE(a.height() == b.height());
    REQUIRE(a.resolution() == b.resolution());
    const std::size_t cells = static_cast<std::size_t>(a.width()) * static_cast<std::size_t>(a.height());
    REQUIRE(std::memcmp(a.cells(), b.cells(), cells) == 0);
  }

  // The node's lockstep replay, with the rig's options.
  const std::string node_cmd = kNode + " --replay-can in.candump --out-can node.candump --out node.lcmlog --map " +
                               map.yaml + " " + node_options();
  INFO("node: " << node_cmd);
  const int node_rc = run_command(node_cmd, "node.txt");
  const std::string node_summary = read_text("node.txt");
  {
    INFO(node_summary);
    REQUIRE(node_rc == 0);
  }

  // The board image under qemu.
  const std::string qemu = board_command("office.yaml in.candump board.candump board_trace.txt");
  INFO("board: " << qemu);
  const int board_rc = run_command(qemu, "board.txt");
  const std::string board_out = read_text("board.txt");
  {
    INFO(board_out);
    REQUIRE(board_rc == 0);
    REQUIRE(board_out.find("estimator-board: PASS") != std::string::npos);
  }
  CHECK(hex_value(board_out, "digest") == host_grid_digest(map.yaml));  // the same grid as the node's loader

  // Byte for byte: the estimate frames, then the estimates' float bits.
  const std::string node_frames = read_text("node.candump"), board_frames = read_text("board.candump");
  const LineDifference frames = first_line_difference(node_frames, board_frames);
  if (frames.line != 0u)
    FAIL_CHECK("node.candump and board.candump differ first at line " << frames.line << ":\n  node:  " << frames.a
               << "\n  board: " << frames.b);
  CHECK(node_frames.size() == board_frames.size());
  const auto estimates = read_estimates("node.lcmlog");
  const std::string node_trace = trace_of(estimates), board_trace = read_text("board_trace.txt");
  const LineDifference trace = first_line_difference(node_trace, board_trace);
  if (trace.line != 0u)
    FAIL_CHECK("the estimates differ first at estimate " << trace.line
               << " (stamp_ns x y theta covariance[9] status rejected; floats as IEEE bits):\n  node (node.lcmlog): "
               << trace.a << "\n  board (board_trace.txt): " << trace.b);

  // And worth comparing: an estimate per prediction (100 Hz) and per scan, four frames each, every scan a
  // correction, nothing beyond the board's capacities, and the estimates tracking the truth.
  CHECK(estimates.size() >= 400u);
  CHECK(count_lines(node_frames) == 4u * estimates.size());
  CHECK(summary_value(board_out, "estimator-board: output", "estimates") == static_cast<long long>(estimates.size()));
  CHECK(summary_value(board_out, "estimator-board: loop", "corrections") == static_cast<long long>(s.scan_messages));
  CHECK(summary_value(board_out, "estimator-board: loop", "queue_full") == 0);
  CHECK(summary_value(board_out, "estimator-board: input", "bad_lines") == 0);
  CHECK(summary_value(board_out, "estimator-board: rejects", "total") == 0);
  CHECK(summary_value(node_summary, "  loop:", "corrections") == static_cast<long long>(s.scan_messages));
  double worst_m = 0.0, worst_rad = 0.0;
  for (const auto& e : estimates) {
    const std::size_t k = static_cast<std::size_t>((e.stamp_ns - s.truth_t.front()) / (10 * hal::kNsPerMs));
    REQUIRE(k < s.truth.size());
    worst_m = std::max(worst_m, static_cast<double>(std::hypot(e.x_m - s.truth[k].x, e.y_m - s.truth[k].y)));
    worst_rad = std::max(worst_rad, std::fabs(wrap_angle(static_cast<double>(e.theta_rad - s.truth[k].theta))));
  }
  // 512 particles on 60 beams track the office run to ~3 cm; the bound leaves room for the spread, not a failure.
  INFO("worst position error " << worst_m << " m, heading " << worst_rad << " rad");
  CHECK(worst_m < 0.3);
  CHECK(worst_rad < 0.15);

  std::printf("estimator_board %s: %zu estimates, %zu frames, bit-identical to estimator_node; worst error %.3f m, "
              "%.3f rad\n", board.c_str(), estimates.size(), count_lines(node_frames), worst_m, worst_rad);
  const std::size_t at = board_out.find("estimator-board: instructions");
  if (at != std::string::npos) std::printf("%s", board_out.substr(at, board_out.find('\n', at) + 1 - at).c_str());
  if (!kSize.empty() && run_command(kSize + " " + elf, "size.txt") == 0)
    std::printf("%s", read_text("size.txt").c_str());
}

namespace {

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f << bytes;
  REQUIRE(f.good());
}

// A P5 image of w x h pixels v(x, y) (top row first), 8 or 16 bit by maxval, with comments in its header.
std::string pgm(int w, int h, unsigned maxval, unsigned (*v)(int, int)) {
  std::string out = "P5\n# written by test_estimator_board\n" + std::to_string(w) + " # width\n" +
                    std::to_string(h) + "\n" + std::to_string(maxval) + "\n";
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const unsigned p = v(x, y) % (maxval + 1u);
      if (maxval > 255u) out += static_cast<char>(p >> 8);
      out += static_cast<char>(p & 0xFFu);
    }
  return out;
}

}  // namespace

TEST_CASE("the board image reads a map_server map into the grid the host's loader makes of it", "[board]") {
  INFO("board " << env("EST_BOARD") << ", image " << env("EST_BOARD_ELF") << ", in "
                 << std::filesystem::current_path().string());
  write_file("empty.candump", "");
  struct Case {
    const char* name;
    std::string yaml;
    std::string image;
  };
  const Case cases[] = {
      {"scale_negate",
       "name: a gradient # ignored, as map_server does\nimage: \"scale_negate.pgm\"\nresolution: 0.1\n"
       "origin: [-1.25, 2.5, 0]\nnegate: 1\noccupied_thresh: 0.6\nfree_thresh: 0.2\nmode: scale\n",
       pgm(37, 23, 255, [](int x, int y) { return static_cast<unsigned>(x * 7 + y * 13); })},
      {"trinary200",
       "image: trinary200.pgm\nresolution: 0.05\norigin: [3.0, -2.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
       "free_thresh: 0.196\n",
       pgm(31, 19, 200, [](int x, int y) { return static_cast<unsigned>(x * 5 + y * 3); })},
      {"raw16",
       "image: raw16.pgm\nresolution: 0.025\norigin: [0.1, -0.3, 0.0]\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
       "mode: raw\n",
       pgm(29, 17, 1000, [](int x, int y) { return static_cast<unsigned>((x * 37 + y * 11) % 130); })},
  };
  for (const Case& c : cases) {
    const std::string name = c.name;
    INFO("map " << name);
    write_file(name + ".yaml", c.yaml);
    write_file(name + ".pgm", c.image);
    REQUIRE(run_command(board_command(name + ".yaml empty.candump " + name + ".candump"), name + ".txt") == 0);
    const std::string out = read_text(name + ".txt");
    INFO(out);
    CHECK(hex_value(out, "digest") == host_grid_digest(name + ".yaml"));
    CHECK(summary_value(out, "estimator-board: output", "estimates") == 0);
  }

  // A map the host refuses, the board refuses too, with the reason, before replaying anything.
  write_file("no_free.yaml", "image: raw16.pgm\nresolution: 0.025\norigin: [0, 0, 0]\noccupied_thresh: 0.65\n");
  CHECK_THROWS_AS(host_grid_digest("no_free.yaml"), hal::maps::MapLoadError);
  CHECK(run_command(board_command("no_free.yaml empty.candump no_free.candump"), "no_free.txt") == 1);
  CHECK(read_text("no_free.txt").find("missing_key") != std::string::npos);
}

int main(int argc, char** argv) {
  const std::string board = env("EST_BOARD"), elf = env("EST_BOARD_ELF");
  if (board.empty() || elf.empty() || env("EST_QEMU_MACHINE").empty()) {
    std::fprintf(stderr, "test_estimator_board: set EST_BOARD, EST_QEMU_MACHINE and EST_BOARD_ELF (ctest does)\n");
    return 1;
  }
  if (!exists(elf)) {
    std::printf("SKIP: %s is missing: build the %s preset first (cmake --preset %s && cmake --build --preset %s)\n",
                elf.c_str(), board.c_str(), board.c_str(), board.c_str());
    return 77;
  }
  if (std::system("command -v qemu-system-arm >/dev/null 2>&1") != 0) {
    std::printf("SKIP: qemu-system-arm is not installed (scripts/setup installs it)\n");
    return 77;
  }
  return Catch::Session().run(argc, argv);
}
