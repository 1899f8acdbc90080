#pragma once
// estimator_node's configuration: the transports, the maps, and the estimator (node/estimator_spec.hpp), every
// option of the command line with its default, in one struct (host only).
#include <cstdint>
#include <string>

#include "hal/lcm/channels.hpp"
#include "node/estimator_spec.hpp"

namespace CLI {  // <CLI/CLI.hpp> costs ~8 s of compile per file: only the files that register options include it
class App;
}  // namespace CLI

namespace node {

inline constexpr std::int32_t kMapMaxSide = 2048;    // cells per side of a map file
inline constexpr std::int32_t kMaxLandmarks = 1024;  // landmarks in a landmark map file

struct NodeConfig {
  // Inputs and outputs.
  std::string can_interface;    // --can
  int can_receive_buffer_bytes = 1 << 20;  // --can-rcvbuf
  std::string lcm_url;          // --lcm: inputs (and outputs unless --lcm-out)
  bool lcm_input = false;
  std::string lcm_out_url;      // --lcm-out: outputs; default --lcm's URL, else LCM's default (udpm)
  // --stamps align|sender: live LCM inputs' stamps mapped onto the node's clock at the first message
  // (node/stamp_alignment.hpp), or judged as sent. Align by default: a sender on this host's CLOCK_MONOTONIC passes
  // the gate as sent and keeps its stamps (offset 0), so a robot's own drivers see no change, while a log played
  // with lcm-logplayer (or a sender on another clock), which the gate would reject wholesale as stale, just works;
  // `sender` is for a rig that wants a sender off the node's clock to show as stale or from-the-future rejects.
  bool align_stamps = true;
  double live_speed = 1.0;  // live LCM: the stream's pace against the wall clock (lcm-logplayer --speed)
  bool can_out = false;
  std::string replay_path;      // --replay: an LCM log
  std::string replay_can_path;  // --replay-can: a candump log of estimator.dbc frames
  std::string out_path;         // --out: estimates to an LCM log
  std::string out_can_path;     // --out-can: estimate frames to a candump log
  std::string record_path;      // --record-inputs
  hal::lcm::Channels channels;
  double status_hz = 1.0;
  double duration_s = 0.0;  // live: stop after this long (0: until SIGINT/SIGTERM)
  bool quiet = false;
  unsigned lcm_wheel_counter_bits = 32;

  // Live view (sim_host/view/): the Foxglove WebSocket protocol and the page on 127.0.0.1:view_port (0: off).
  std::uint16_t view_port = 0;
  bool view_wait = false;     // replay: start once a viewer has subscribed
  // Replay pacing by the log's receive times: 0 as fast as possible, 1 real time, 2 twice as fast. Pacing changes
  // only when the inputs are handled, never what they give: the outputs stay the lockstep replay's, bit for bit.
  // Default: 0, or 1 with --view (a replay at full speed is over before anyone sees it).
  double replay_speed = -1.0;

  // Maps: 'office' (the simulator's synthetic office) or files.
  std::string map = "office";
  std::string landmarks = "office";

  EstimatorSpec spec;

  bool replay() const { return !replay_path.empty() || !replay_can_path.empty(); }
};

// Registers every option on `app` (defaults shown in --help), and checks them after parsing (throws CLI::ValidationError).
void add_options(CLI::App& app, NodeConfig& c);
void finish_options(const CLI::App& app, NodeConfig& c);

// The options that give `spec` (with the map and landmark sources), for a replay of a recorded run: parsing them
// with add_options gives the same estimator.
std::string command_line(const EstimatorSpec& spec, const std::string& map, const std::string& landmarks);

}  // namespace node
