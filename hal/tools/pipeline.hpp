#pragma once
// What estimator_node runs: the map and its models (distance transform, likelihood field, free space; or the
// landmark map), the MCL or EKF estimator of the chosen robot model (est/loop/configured_loop.hpp), the firmware's
// FilterLoop and the HAL-to-loop adapter in front of it, behind one interface so the rest of the node depends on
// neither the model nor the filter (host only).
#include <cstdint>
#include <memory>
#include <string>

#include "est/loop/status.hpp"
#include "hal/estimate.hpp"
#include "hal/loop_port.hpp"
#include "hal/sensor_port.hpp"
#include "hal/time.hpp"
#include "node_config.hpp"

namespace hal::node {

class Pipeline {
 public:
  virtual ~Pipeline() = default;

  virtual ValidatedSensorPort& port() = 0;  // validated samples in
  virtual void flush() = 0;                 // applies every queued input
  virtual void set_transport_status(std::uint32_t bits) = 0;
  virtual void set_upstream_rejects(std::uint32_t total) = 0;

  virtual const est::loop::LoopCounters& loop_counters() const = 0;
  virtual const LoopPortRejectCounters& port_rejects() const = 0;
  virtual std::uint32_t published() const = 0;
  virtual std::uint32_t nonfinite_estimates() const = 0;
  virtual std::string map_description() const = 0;
  virtual std::string filter_description() const = 0;
};

// Loads the map (throws std::runtime_error with the reason), builds the models, initializes the filter (at the
// initial pose or globally) and wires the loop: its step clock times the steps, estimates go to `sink`.
std::unique_ptr<Pipeline> make_pipeline(const NodeConfig& config, Clock& step_clock, EstimateSink& sink);

}  // namespace hal::node
