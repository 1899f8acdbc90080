#pragma once
// The LCM backend: sensor inputs from LCM channels into a hal::SensorPort and, when asked, the team's messages
// through a team validator into a hal::TeamPort; estimates, health and this robot's team message out to LCM
// channels. Every sensor is received the same way, by its LcmCodec (hal/sensors/<sensor>/lcm.hpp). Host only.
#include <cstdint>
#include <est_lcm/slam_map_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "hal/estimate.hpp"
#include "hal/lcm/channels.hpp"
#include "hal/lcm/lcm_convert.hpp"
#include "hal/sensor_port.hpp"
#include "hal/team/validator.hpp"
#include "hal/team_message.hpp"

namespace hal::lcm {

// Subscribes on construction, unsubscribes on destruction. Messages arrive during lcm.handle*() calls.
class LcmInputs {
 public:
  LcmInputs(::lcm::LCM& lcm, InputConfig config, SensorPort& port);
  ~LcmInputs();
  LcmInputs(const LcmInputs&) = delete;
  LcmInputs& operator=(const LcmInputs&) = delete;

  // Receives the team channel (config.channels.team) from now on: each message is decoded (a payload that is no
  // team message is counted in team_rejects()), judged and counted by `validator`, and the accepted ones, in order or
  // out of order, go to `port`. A second call replaces the validator and port. Both must outlive this.
  void subscribe_team(TeamPort& port, team::TeamValidator& validator);

  // Sensor payloads refused before the HAL's validators, by reason; and the sensor samples passed on.
  const LcmRejectCounters& rejects() const { return rejects_; }
  std::uint64_t accepted() const { return accepted_; }
  // Team payloads that did not decode (malformed, bad_count, bad_shape); what decodes the validator counts.
  const LcmRejectCounters& team_rejects() const { return team_rejects_; }
  // Whether `channel` is one of the sensor channels this receives.
  bool is_input_channel(const std::string& channel) const;
  // The sensor channels this receives, in subscription order.
  const std::vector<std::string>& input_channels() const { return input_channels_; }

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
  std::vector<::lcm::Subscription*> subscriptions_;
  std::vector<std::string> input_channels_;
  LcmRejectCounters rejects_;
  std::uint64_t accepted_ = 0;
  TeamPort* team_port_ = nullptr;
  team::TeamValidator* team_validator_ = nullptr;
  ::lcm::Subscription* team_subscription_ = nullptr;
  LcmRejectCounters team_rejects_;
  est::team::TeamMessage team_message_;  // large: kept here rather than on the stack
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
  void publish_slam_map(const est_lcm::slam_map_t& map);  // EKF-SLAM's landmarks and counters (Channels::slam_map)
  // This robot's message of a step, on the team channel (Channels::team; the sender is message.robot).
  void publish_team(const est::team::TeamMessage& message);

  std::uint64_t publish_failures() const { return failures_; }

 private:
  template <typename Message>
  void send(const std::string& channel, const Message& m);

  ::lcm::LCM& lcm_;
  Channels channels_;
  std::uint64_t failures_ = 0;
};

}  // namespace hal::lcm
