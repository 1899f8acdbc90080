// The team estimator's spec, options and output lines (node/team_spec.hpp).
#include "node/team_spec.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "est/util/digest.hpp"

namespace node {

namespace {
std::string shortest(float v) {  // the shortest decimal that reads back as v
  char b[32];
  for (int digits = 6; digits <= 9; ++digits) {
    std::snprintf(b, sizeof b, "%.*g", digits, static_cast<double>(v));
    if (std::strtof(b, nullptr) == v) break;
  }
  return b;
}
std::string hex(float v) {
  char b[32];
  std::snprintf(b, sizeof b, "%a", static_cast<double>(v));
  return b;
}
}  // namespace

void add_team_spec_options(CLI::App& app, TeamSpec& s) {
  const char* g = "Team (--filter coop-ekf)";
  est::team::CoopEkfConfig& c = s.estimator;
  app.add_option("--team-size", c.robots, "robots in the team (every node of the team the same)")
      ->capture_default_str()->check(CLI::Range(1, kTeamMaxRobots))->group(g);
  app.add_option("--team-step", c.step_s, "the team's step, s (each message covers one)")
      ->capture_default_str()->check(CLI::PositiveNumber)->group(g);
  app.add_option("--team-initial", s.initial, "the team's initial estimate x0,y0,x1,y1,... (m)")
      ->delimiter(',')->group(g);
  app.add_option("--team-initial-sigma", s.initial_sigma_m, "its standard deviation per axis (m)")
      ->capture_default_str()->check(CLI::PositiveNumber)->group(g);
  app.add_option_function<std::vector<float>>(
         "--team-landmark",
         [&s](const std::vector<float>& v) {
           s.landmarks.push_back({static_cast<std::int32_t>(v[0]), v[1], v[2]});
         },
         "a landmark with a prior: id,x,y (repeatable)")
      ->delimiter(',')->expected(3)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)->group(g);
  app.add_option("--team-landmark-sigma", s.landmark_sigma_m, "the landmark priors' standard deviation per axis (m)")
      ->capture_default_str()->check(CLI::PositiveNumber)->group(g);
  app.add_option("--team-sigma-range", c.noise.sigma_range, "range noise (m)")
      ->capture_default_str()->check(CLI::PositiveNumber)->group(g);
  app.add_option("--team-sigma-bearing", c.noise.sigma_bearing, "bearing noise (rad)")
      ->capture_default_str()->check(CLI::PositiveNumber)->group(g);
  app.add_option("--team-motion-sigma", c.motion_sigma_mps, "control noise per axis, as a velocity (m/s)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(g);
  app.add_option("--team-unknown-speed", c.unknown_speed_mps,
                 "a robot whose message is missing may move this fast per axis (m/s)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->group(g);
  app.add_option("--team-window", s.window_steps, "steps a missing team message is waited for")
      ->capture_default_str()->check(CLI::Range(1, kTeamWindowSteps))->group(g);
}

void check_team_spec(const TeamSpec& s) {
  const int R = s.estimator.robots;
  if (R < 1 || R > kTeamMaxRobots)
    throw std::invalid_argument("--team-size must be 1.." + std::to_string(kTeamMaxRobots));
  if (s.initial.size() != static_cast<std::size_t>(2 * R))
    throw std::invalid_argument("--team-initial needs " + std::to_string(2 * R) + " numbers (x,y per robot)");
  if (s.landmarks.size() > static_cast<std::size_t>(kTeamMaxLandmarks))
    throw std::invalid_argument("at most " + std::to_string(kTeamMaxLandmarks) + " landmarks");
  if (s.window_steps < 1 || s.window_steps > kTeamWindowSteps)
    throw std::invalid_argument("--team-window must be 1.." + std::to_string(kTeamWindowSteps));
}

std::string team_command_line(const TeamSpec& s) {
  const est::team::CoopEkfConfig& c = s.estimator;
  std::string o = "--filter coop-ekf --team-size " + std::to_string(c.robots) + " --team-step " + shortest(c.step_s) +
                  " --team-initial ";
  for (std::size_t i = 0; i < s.initial.size(); ++i) o += (i ? "," : "") + shortest(s.initial[i]);
  o += " --team-initial-sigma " + shortest(s.initial_sigma_m);
  for (const TeamLandmarkPrior& l : s.landmarks)
    o += " --team-landmark " + std::to_string(l.id) + "," + shortest(l.x) + "," + shortest(l.y);
  o += " --team-landmark-sigma " + shortest(s.landmark_sigma_m) +
       " --team-sigma-range " + shortest(c.noise.sigma_range) +
       " --team-sigma-bearing " + shortest(c.noise.sigma_bearing) +
       " --team-motion-sigma " + shortest(c.motion_sigma_mps) +
       " --team-unknown-speed " + shortest(c.unknown_speed_mps) + " --team-window " + std::to_string(s.window_steps);
  return o;
}

void start_team(const TeamSpec& s, TeamWindow& w, TeamEstimator& e) {
  check_team_spec(s);
  const int R = s.estimator.robots;
  Eigen::Vector2f means[kTeamMaxRobots];
  TeamEstimator::RobotCovariance covs[kTeamMaxRobots];
  for (int a = 0; a < R; ++a) {
    const std::size_t i = static_cast<std::size_t>(2 * a);
    means[a] = Eigen::Vector2f(s.initial[i], s.initial[i + 1]);
    covs[a] = TeamEstimator::RobotCovariance::Identity() * (s.initial_sigma_m * s.initial_sigma_m);
  }
  if (!e.init(s.estimator, means, covs)) throw std::invalid_argument("the cooperative EKF refuses this team spec");
  for (const TeamLandmarkPrior& l : s.landmarks)
    if (e.add_landmark(l.id, Eigen::Vector2f(l.x, l.y),
                       Eigen::Matrix2f::Identity() * (s.landmark_sigma_m * s.landmark_sigma_m)) !=
        est::CorrectionStatus::accepted)
      throw std::invalid_argument("landmark " + std::to_string(l.id) + ": refused (a duplicate id?)");
  if (!w.start(R, s.first_seq)) throw std::invalid_argument("the team window refuses this team size");
}

std::string team_estimate_header() { return "seq,status,dim,mean...,covariance_digest"; }

std::string team_estimate_line(std::uint32_t seq, const TeamEstimator& e) {
  const auto& s = e.slam();
  char st[16];
  std::snprintf(st, sizeof st, "%x", e.status());
  std::string l = std::to_string(seq) + "," + st + "," + std::to_string(s.dim());
  for (int i = 0; i < s.dim(); ++i) l += "," + hex(s.mean()(i));
  est::Digest d;
  for (int c = 0; c < s.dim(); ++c)
    for (int r = 0; r < s.dim(); ++r) d.add(s.covariance()(r, c));
  char dg[24];
  std::snprintf(dg, sizeof dg, ",%016llx", static_cast<unsigned long long>(d.value()));
  return l + dg;
}

}  // namespace node
