#pragma once
// estimator_node as a library: the firmware's filter loop on the host behind the transports. Live, sensor inputs
// from SocketCAN and/or LCM, estimates out on LCM (and CAN); in replay, an LCM log or a candump log of CAN frames
// through the same pipeline in lockstep, as fast as possible, estimates to an LCM log and/or a candump log. Tests
// construct a Node, run it and read its counters in process (host only; throws std::runtime_error on a map that
// cannot be loaded, std::invalid_argument on a configuration the firmware refuses).
//
// Data path: transport (live LCM: node/lcm_receiver.hpp's thread and bounded queue, then memq) -> node/estimator_pipeline.hpp (hal::ValidatedInputs -> [input counter, recorder] ->
// hal::LoopPort -> est::loop::FilterLoop) -> the outputs (LCM, CAN, log files), and with --view the live view
// (sim_host/view/: the estimates, MCL's particles at ~10 Hz and the input's ground truth, handed off without ever
// holding the loop).
// Time: live, CAN inputs carry the kernel's receive time and LCM inputs their sender's stamp_ns (moved onto the node's
// clock by one offset at the first message unless --stamps sender: node/stamp_alignment.hpp), checked against
// CLOCK_MONOTONIC; in replay the HAL's clock reads each message's own stamp (so staleness, a property of live
// arrival that a log does not keep, never fires) and the loop's step clock stands still (no overruns, no timing
// in the outputs): the output log is a function of the input log and the options alone.
#include <cstdint>
#include <cstdio>
#include <memory>

#include "est/loop/input_kinds.hpp"
#include "node/estimator_pipeline.hpp"
#include "node/node_config.hpp"

namespace node {

class Node {
 public:
  explicit Node(const NodeConfig& config);
  ~Node();
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  // Replays or runs live, as configured, until the end of the log, --duration, or SIGINT/SIGTERM; the exit status.
  int run();
  void print_summary(std::FILE* f) const;

  // What a run did.
  const EstimatorPipeline& pipeline() const;
  std::uint64_t inputs_to_loop(est::loop::InputKind k) const;  // checked samples handed to the loop, by kind
  std::uint64_t estimates() const;                             // published
  std::uint32_t rejects_total() const;                         // everywhere: transports, HAL, loop port
  std::uint64_t log_events() const;                            // replay: events read, and sensor inputs among them
  std::uint64_t log_inputs() const;
  std::uint64_t log_problems() const;  // replay: faults of the LCM log (cut, bad sync word, impossible length)

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace node
