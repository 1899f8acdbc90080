// The LCM backend (hal/lcm/lcm_backend.hpp).
#include "hal/lcm/lcm_backend.hpp"

#include <algorithm>

namespace hal::lcm {

LcmInputs::LcmInputs(::lcm::LCM& lcm, InputConfig config, SensorPort& port)
    : lcm_(lcm), config_(std::move(config)), port_(port) {
  subscribe_all(RawSamples{});
}

LcmInputs::~LcmInputs() {
  for (::lcm::Subscription* s : subscriptions_)
    if (s != nullptr) lcm_.unsubscribe(s);
  if (team_subscription_ != nullptr) lcm_.unsubscribe(team_subscription_);
}

void LcmInputs::subscribe_team(TeamPort& port, team::TeamValidator& validator) {
  team_port_ = &port;
  team_validator_ = &validator;
  if (team_subscription_ == nullptr)
    team_subscription_ = lcm_.subscribe(config_.channels.team, &LcmInputs::on_team, this);
}

template <typename... Samples>
void LcmInputs::subscribe_all(SampleList<Samples...>) {
  (..., (input_channels_.push_back(config_.channels.*LcmCodec<Samples>::channel),
         subscriptions_.push_back(
             lcm_.subscribe(config_.channels.*LcmCodec<Samples>::channel, &LcmInputs::receive<Samples>, this))));
}

bool LcmInputs::is_input_channel(const std::string& channel) const {
  return std::find(input_channels_.begin(), input_channels_.end(), channel) != input_channels_.end();
}

bool LcmInputs::note(LcmReject r) {
  if (r == LcmReject::none) {
    ++accepted_;
    return true;
  }
  rejects_.add(r);
  return false;
}

template <typename Sample>
void LcmInputs::receive(const ::lcm::ReceiveBuffer* rbuf, const std::string&) {
  using Codec = LcmCodec<Sample>;
  typename Codec::Message m{};
  typename Codec::Storage storage;
  Sample sample{};
  LcmReject r = decode_guarded(rbuf->data, rbuf->data_size, m, Codec::max_count(config_));
  if (r == LcmReject::none) r = Codec::to_hal(m, config_, storage, sample);
  if (note(r)) port_.on(sample);
}

void LcmInputs::on_team(const ::lcm::ReceiveBuffer* rbuf, const std::string&) {
  est_lcm::team_message_t m{};
  LcmReject r = decode_guarded(rbuf->data, rbuf->data_size, m, std::int64_t{est::team::kMaxTeamMeasurements});
  if (r == LcmReject::none) r = to_hal(m, team_message_);
  if (r != LcmReject::none) {
    team_rejects_.add(r);
    return;
  }
  if (team::TeamValidator::accepted(team_validator_->check(team_message_))) team_port_->on_team_message(team_message_);
}

template <typename Message>
void LcmOutputs::send(const std::string& channel, const Message& m) {
  if (lcm_.publish(channel, &m) != 0) ++failures_;
}

void LcmOutputs::publish(const Estimate& estimate) { send(channels_.pose, to_lcm(estimate)); }

void LcmOutputs::publish_status(const est_lcm::status_t& status) { send(channels_.status, status); }

void LcmOutputs::publish_particles(TimeNs stamp_ns, const float* x, const float* y, const float* theta,
                                   const float* weight, std::size_t n, std::size_t decimation) {
  if (decimation == 0) decimation = 1;
  est_lcm::particle_cloud_t m{};
  m.stamp_ns = stamp_ns;
  m.num_total = static_cast<std::int32_t>(n);
  m.decimation = static_cast<std::int32_t>(decimation);
  for (std::size_t i = 0; i < n; i += decimation) {
    m.x_m.push_back(x[i]);
    m.y_m.push_back(y[i]);
    m.theta_rad.push_back(theta[i]);
    m.weight.push_back(weight[i]);
  }
  m.num_particles = static_cast<std::int32_t>(m.x_m.size());
  send(channels_.particles, m);
}

void LcmOutputs::publish_ground_truth(const est_lcm::ground_truth_t& truth) { send(channels_.ground_truth, truth); }

void LcmOutputs::publish_slam_map(const est_lcm::slam_map_t& map) { send(channels_.slam_map, map); }

void LcmOutputs::publish_team(const est::team::TeamMessage& message) { send(channels_.team, to_lcm(message)); }

}  // namespace hal::lcm
