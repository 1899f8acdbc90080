#pragma once
// The LCM backend: sensor inputs from LCM channels into a hal::SensorPort (and team messages into a TeamPort),
// estimates and health out to LCM channels. Every sensor is received the same way, by its LcmCodec
// (hal/sensors/<sensor>/lcm.hpp). Host only.
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "hal/estimate.hpp"
#include "hal/lcm/channels.hpp"
#include "hal/lcm/lcm_convert.hpp"
#include "hal/sensor_port.hpp"
#include "hal/team_message.hpp"

namespace hal::lcm {

// Subscribes on construction, unsubscribes on destruction. Messages arrive during lcm.handle*() calls.
class LcmInputs {
 public:
  LcmInputs(::lcm::LCM& lcm, InputConfig config, SensorPort& port, TeamPort* team = nullptr);
  ~LcmInputs();
  LcmInputs(const LcmInputs&) = delete;
  LcmInputs& operator=(const LcmInputs&) = delete;

  const LcmRejectCounters& rejects() const { return rejects_; }
  const FaultCounters& team_faults() const { return team_faults_; }
  std::uint64_t accepted() const { return accepted_; }
  // Whether `channel` is one of the sensor channels this receives.
  bool is_input_channel(const std::string& channel) const;

 private:
  template <typename Sample>
  void receive(const ::lcm::ReceiveBuffer* rbuf, const std::string& channel);
  template <typename... Samples>
  void subscribe_all(SampleList<Samples...>);
  void on_team(const ::lcm::ReceiveBuffer* rbuf, const std::string& channel);
  bool note(LcmReject r);

  ::lcm::LCM& lcm_;
  InputConfig config_;
  SensorPort& port_;
  TeamPort* team_;
  std::vector<::lcm::Subscription*> subscriptions_;
  std::vector<std::string> input_channels_;
  LcmRejectCounters rejects_;
  FaultCounters team_faults_;
  std::uint64_t accepted_ = 0;
  TeamMessage team_message_;  // large: kept here rather than on the stack
};

class LcmOutputs final : public EstimateSink {
 public:
  LcmOutputs(::lcm::LCM& lcm, Channels channels) : lcm_(lcm), channels_(std::move(channels)) {}

  void publish(const Estimate& estimate) override;
  void publish_status(const est_lcm::status_t& status);
  // Every decimation-th particle of n; weights as given.
  void publish_particles(TimeNs stamp_ns, const float* x, const float* y, const float* theta, const float* weight,
                         std::size_t n, std::size_t decimation);
  void publish_ground_truth(const est_lcm::ground_truth_t& truth);
  void publish_team(const TeamMessage& message);

  std::uint64_t publish_failures() const { return failures_; }

 private:
  template <typename Message>
  void send(const std::string& channel, const Message& m);

  ::lcm::LCM& lcm_;
  Channels channels_;
  std::uint64_t failures_ = 0;
};

}  // namespace hal::lcm
