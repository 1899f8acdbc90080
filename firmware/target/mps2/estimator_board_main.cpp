// estimator-board.elf: the estimator's pipeline on the board, as the host composes it (sim_host/node: estimator_node
// --replay-can), over a recorded stream of CAN frames read through semihosting:
//
//   candump lines -> hal::can::CanInput (ScanReassembler in front) -> hal::Pipeline<Estimator> (the HAL gate
//   hal::ValidatedInputs -> hal::LoopPort -> the firmware's filter loop) -> hal::can::CanEstimateSink -> candump lines
//
// with the estimator of the static configuration (estimator_board_config.hpp) on a ROS map_server map (YAML + PGM,
// board_ros_map.hpp). A lockstep replay, as the node's: the HAL gate judges each frame at its own stamp, steps take
// no time (no deadline is measured), the loop is flushed at the end. Same frames and same map, same output bytes.
//
// Command line (qemu -semihosting-config enable=on,target=native,arg=estimator-board.elf,arg=MAP.yaml,arg=IN,arg=OUT):
//   estimator-board.elf MAP.yaml IN.candump OUT.candump [TRACE.txt]
// TRACE.txt, if given, gets one line per estimate with the bits the CAN frames round away, for a bit-for-bit
// comparison with the node's --out log (pose_estimate_t): "stamp_ns x y theta c0 .. c8 status rejected_inputs", the
// stamp in decimal, the eleven floats as the 8 hex digits of their IEEE bits (covariance row-major), status and
// rejected_inputs (saturated at 2^31 - 1, as in pose_estimate_t) in hex.
// Paths are the host's, relative to qemu's working directory, without spaces (a comma is doubled in qemu's option).
// The image prints a summary on qemu's stderr: the map (its size and grid_digest, board_ros_map.hpp), the input, the
// loop's counters, the rejects, the output, instruction counts, then PASS or FAIL. Exit status: 0 the replay
// ran and every line and frame was handled; 1 nothing was replayed (usage, map, or a file that cannot be opened);
// 2 the replay ran with errors (malformed candump lines, output that could not be written or encoded, a full input
// queue: a stream the board's capacities do not fit). Rejected inputs (faults in the stream) are counted, not errors.
// Instruction counts (SysTick, instruction_counter.hpp) are exact under qemu -icount shift=10 only.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "board_ros_map.hpp"
#include "est/filter/free_space_sampler.hpp"
#include "est/loop/configured_loop.hpp"
#include "est/map/distance_transform.hpp"
#include "est/map/occupancy_grid.hpp"
#include "est/sensor/likelihood_field_grid.hpp"
#include "estimator_board_config.hpp"
#include "hal/can/can_estimate_sink.hpp"
#include "hal/can/can_input.hpp"
#include "hal/can/candump.hpp"
#include "hal/pipeline.hpp"
#include "hal/sensors/range_scan/can_reassembler.hpp"
#include "instruction_counter.hpp"
#include "semihosting.hpp"
#include "semihosting_file.hpp"
#include "static_object.hpp"

#ifndef EST_BOARD_NAME
#error "EST_BOARD_NAME must name the board"
#endif

namespace {

using Rig = est::loop::ConfiguredLoop<board::EstimatorBoardConfig>;
using Estimator = Rig::Estimator;
using hal::TimeNs;

constexpr std::size_t kMaxArgs = 8;
constexpr std::uint64_t kMaxLines = 50000000;  // the replay's bound: ~2 GB of candump text

// The maps and their models (~1.8 MB at 512 x 512).
est::OccupancyGridStorage<board::kMapMaxSide, board::kMapMaxSide> g_grid;
est::DistanceTransformStorage<board::kMapMaxSide, board::kMapMaxSide> g_edt;
est::LikelihoodFieldGridStorage<board::kMapMaxSide, board::kMapMaxSide> g_field_grid;
est::LikelihoodField g_field;
board::Static<Estimator> g_estimator;
board::Static<Rig::Loop> g_loop;
hal::can::ScanReassembler<static_cast<std::size_t>(board::EstimatorBoardConfig::kMaxBeams)> g_scans;
board::FileReader g_in;
board::FileWriter g_out;
board::FileWriter g_trace;

// Replay clocks, as the node's: the gate sees each frame at its own stamp; steps take no time.
struct StampClock final : hal::Clock {
  TimeNs now = 0;
  TimeNs now_ns() override { return now; }
};
struct FrozenClock final : hal::Clock {
  TimeNs now_ns() override { return 0; }
};

// Frames to the output candump log, stamped with the estimate they carry.
struct CandumpTx final : hal::can::CanTx {
  TimeNs stamp_ns = 0;
  std::uint64_t frames = 0;
  bool send(const hal::can::CanFrame& frame) override {
    char line[hal::can::kCandumpLineMax];
    const std::size_t n = hal::can::format_candump_line(frame, stamp_ns, board::rig::kOutputInterface, line);
    if (!g_out.write(line, n)) return false;
    ++frames;
    return true;
  }
};
// One trace line per estimate (see the top of the file).
void write_trace(const hal::Estimate& e) {
  static constexpr char kHex[] = "0123456789abcdef";
  char text[16 * 10 + 24];
  std::size_t n = 0;
  const auto hex = [&](std::uint32_t v) {
    text[n++] = ' ';
    for (int shift = 28; shift >= 0; shift -= 4) text[n++] = kHex[(v >> shift) & 0xFu];
  };
  const auto bits = [&](float f) {
    std::uint32_t v = 0;
    std::memcpy(&v, &f, sizeof v);
    hex(v);
  };
  char digits[20];
  int d = 0;
  std::uint64_t t = e.stamp_ns < 0 ? 0u : static_cast<std::uint64_t>(e.stamp_ns);
  do {
    digits[d++] = static_cast<char>('0' + t % 10u);
    t /= 10u;
  } while (t != 0u && d < 20);
  while (d > 0) text[n++] = digits[--d];
  bits(e.pose.x);
  bits(e.pose.y);
  bits(e.pose.theta);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) bits(e.covariance(r, c));
  hex(e.status);
  hex(e.rejected_inputs > 0x7fffffffu ? 0x7fffffffu : e.rejected_inputs);
  text[n++] = '\n';
  g_trace.write(text, n);
}

struct StampedSink final : hal::EstimateSink {
  CandumpTx& tx;
  hal::can::CanEstimateSink& can;
  std::uint32_t published = 0;
  StampedSink(CandumpTx& t, hal::can::CanEstimateSink& c) : tx(t), can(c) {}
  void publish(const hal::Estimate& e) override {
    tx.stamp_ns = e.stamp_ns;
    can.publish(e);
    if (g_trace.is_open()) write_trace(e);
    ++published;
  }
};

std::uint32_t saturate(std::uint64_t v) { return v > UINT32_MAX ? UINT32_MAX : static_cast<std::uint32_t>(v); }

void line(const char* a) { board::write(a); }
void field(const char* name, std::uint64_t v) {
  board::write(" ");
  board::write(name);
  board::write("=");
  board::write_dec(v);
}

int fail(const char* why) {
  line("estimator-board: ");
  line(why);
  line("\n");
  return 1;
}

int usage(const char* why) {
  line("estimator-board: ");
  line(why);
  line("\nusage: estimator-board.elf MAP.yaml IN.candump OUT.candump [TRACE.txt] (qemu -semihosting-config "
       "enable=on,target=native,arg=estimator-board.elf,arg=MAP.yaml,arg=IN.candump,arg=OUT.candump"
       "[,arg=TRACE.txt])\n");
  return 1;
}

// Splits the semihosting command line at spaces, in place.
std::size_t split_args(char* cmdline, const char* (&argv)[kMaxArgs]) {
  std::size_t argc = 0;
  for (std::size_t i = 0; cmdline[i] != '\0' && argc < kMaxArgs;) {  // each pass moves past one argument
    while (cmdline[i] == ' ') cmdline[i++] = '\0';
    if (cmdline[i] == '\0') break;
    argv[argc++] = &cmdline[i];
    while (cmdline[i] != '\0' && cmdline[i] != ' ') ++i;
  }
  return argc;
}

// The HAL gate's limits, as estimator_node sets them (node_config.cpp, finish_options) for --replay-can.
hal::InputLimits input_limits() {
  hal::InputLimits l;
  l.set_timing(board::rig::kTimingLimits);
  l.odometry.max_speed_mps = l.twist.max_speed_mps;
  l.odometry.max_turn_rate_rps = l.twist.max_turn_rate_rps;
  l.wheels.wheel_count = board::rig::kWheelCount;
  l.wheels.counter_bits = board::rig::kCounterBits;
  l.scan.max_beams = static_cast<std::size_t>(board::EstimatorBoardConfig::kMaxBeams);  // the node: 1440
  return l;
}

}  // namespace

int main() {
  static char cmdline[1024];
  const char* argv[kMaxArgs] = {};
  if (!board::command_line(cmdline, sizeof cmdline)) return usage("no command line (or longer than 1023 bytes)");
  const std::size_t argc = split_args(cmdline, argv);
  if (argc != 4 && argc != 5) return usage("expected three or four arguments");
  const char* map_path = argv[1];
  const char* in_path = argv[2];
  const char* out_path = argv[3];
  const char* trace_path = argc == 5 ? argv[4] : nullptr;

  // The map and its models, as node::detail::build_map_models builds them for MCL.
  board::instruction_counter_start();
  const board::MapLoadResult map = board::load_ros_map(map_path, g_grid);
  if (map.error != board::MapError::none) {
    line("estimator-board: map ");
    line(map_path);
    line(": ");
    line(board::to_string(map.error));
    if (map.yaml_line != 0u) field("line", map.yaml_line);
    line("\n");
    return 1;
  }
  const est::OccupancyGrid grid = g_grid.grid();
  const std::uint64_t map_digest = board::grid_digest(grid);
  if (g_edt.build(grid) != est::MapStatus::ok) return fail("map: distance transform failed");
  if (g_field.configure(board::rig::kField, grid, g_edt.view()) != est::SensorModelStatus::ok)
    return fail("likelihood field: bad parameters");
  if (g_field_grid.build(g_field, grid) != est::MapStatus::ok) return fail("likelihood field: cannot tabulate it");
  const est::LikelihoodFieldGrid field_grid = g_field_grid.view();
  const est::FreeSpaceSampler free_space(grid, g_edt.view(), board::rig::kClearance);
  if (!free_space.valid()) return fail("map: no usable free space");
  const std::uint64_t map_instructions = board::instruction_counter_read();

  // The estimator, as node::detail::PipelineImpl constructs and initializes it.
  Rig::EstimatorConfig config;
  config.motion = board::rig::kDiffDrive;
  config.mcl = board::rig::kMcl;
  config.beam_stride = board::rig::kBeamStride;
  config.cluster_cell = board::rig::kClusterCell;
  Estimator& estimator = g_estimator.emplace(
      config, board::rig::kSeed, est::loop::LikelihoodFieldScan(g_field, board::rig::kSensorMount, &field_grid),
      free_space);
  estimator.initialize_at(board::rig::kInitialPose, board::rig::kInitialSigmaXy, board::rig::kInitialSigmaTheta,
                          board::rig::kParticles);
  Rig::Loop& loop = g_loop.emplace(estimator, Rig::kTiming);

  if (!g_in.open(in_path)) return fail("cannot open the input candump log");
  if (!g_out.open(out_path)) return fail("cannot create the output candump log");
  if (trace_path != nullptr && !g_trace.open(trace_path)) return fail("cannot create the trace");
  CandumpTx tx;
  hal::can::CanEstimateSink can_sink(tx);
  StampedSink sink(tx, can_sink);
  StampClock sample_clock;
  FrozenClock step_clock;
  const hal::InputLimits limits = input_limits();
  hal::Pipeline<Estimator> pipeline(loop, limits, sample_clock, step_clock, sink);
  hal::can::CanInput can_input(g_scans, pipeline.input());
  const auto transport_rejects = [&] {
    return saturate(std::uint64_t{can_input.rejects().total()} + can_input.scans().rejects().total());
  };

  // The replay, line by line as estimator_node's run_replay_can.
  board::instruction_counter_start();
  pipeline.refresh(0u, transport_rejects());
  std::uint64_t lines = 0, frames = 0, bad_lines = 0;
  const char* text = nullptr;
  std::size_t length = 0;
  while (lines < kMaxLines && g_in.next_line(text, length)) {
    ++lines;
    hal::can::CanFrame frame;
    TimeNs stamp = 0;
    const hal::can::CandumpStatus st = hal::can::parse_candump_line(text, length, frame, stamp);
    if (st == hal::can::CandumpStatus::blank) continue;
    if (st != hal::can::CandumpStatus::ok) {
      if (++bad_lines <= 5u) {
        line("estimator-board: ");
        line(in_path);
        field("line", lines);
        line(": ");
        line(hal::can::to_string(st));
        line(", skipped\n");
      }
      continue;
    }
    ++frames;
    sample_clock.now = stamp;
    can_input.on_frame(frame, stamp);
    can_input.poll(stamp);
    pipeline.refresh(0u, transport_rejects());
  }
  const bool input_cut = lines == kMaxLines;
  pipeline.flush();
  const std::uint64_t replay_instructions = board::instruction_counter_read();
  const std::uint32_t long_lines = g_in.long_lines();
  g_in.close();
  const bool frames_written = g_out.close();
  const bool trace_written = g_trace.close();
  const bool output_ok = frames_written && trace_written;

  const est::loop::LoopCounters& c = loop.counters();
  const std::uint32_t gate_rejects = pipeline.gate().faults().total();
  const std::uint32_t port_rejects = pipeline.port().rejects().total();
  line("estimator-board " EST_BOARD_NAME ": map");
  field("width", static_cast<std::uint64_t>(map.width));
  field("height", static_cast<std::uint64_t>(map.height));
  line(" digest=");
  board::write_hex(map_digest, 16);
  line("\nestimator-board: input");
  field("lines", lines);
  field("frames", frames);
  field("bad_lines", bad_lines);
  field("long_lines", long_lines);
  field("frames_accepted", can_input.frames_accepted());
  field("scans_completed", can_input.scans().scans_completed());
  line("\nestimator-board: loop");
  field("inputs", c.inputs);
  field("too_old", c.too_old);
  field("queue_full", c.queue_full);
  field("rejected", c.rejected);
  field("predictions", c.predictions);
  field("corrections", c.corrections);
  field("degenerate", c.degenerate);
  field("unused", c.unused);
  line("\nestimator-board: rejects");
  field("total", std::uint64_t{transport_rejects()} + gate_rejects + port_rejects);
  field("can_frame", can_input.rejects().total());
  field("can_scan", can_input.scans().rejects().total());
  field("gate", gate_rejects);
  field("loop_port", port_rejects);
  line("\nestimator-board: output");
  field("estimates", sink.published);
  field("frames", tx.frames);
  field("encode_failures", can_sink.encode_failures());
  field("send_failures", can_sink.send_failures());
  field("write_failures", std::uint64_t{g_out.failures()} + g_trace.failures());
  line("\nestimator-board: instructions");
  field("map", map_instructions);
  field("replay", replay_instructions);
  const std::uint64_t steps = std::uint64_t{c.predictions} + c.corrections;
  field("per_step", steps > 0u ? replay_instructions / steps : 0u);
  line(" (exact under qemu -icount shift=10)\n");

  const bool errors = bad_lines != 0u || long_lines != 0u || input_cut || !output_ok || c.queue_full != 0u ||
                      can_sink.encode_failures() != 0u || can_sink.send_failures() != 0u;
  line(errors ? "estimator-board: FAIL\n" : "estimator-board: PASS\n");
  return errors ? 2 : 0;
}
