// diffdrive-landmarks: three differential-drive robots drive loops in a 20 m x 15 m field of known landmarks
// (range, bearing, signature; 6 m reach, 180 degrees ahead). Each robot's sensor also sees the other robots in view,
// by the tag of the marker each carries, not by identity; which tag is which robot is a permutation drawn from the
// seed (never the identity). Wheel-encoder ticks slip against the ground. The filter
// (est/team/anonymous_team_mcl.hpp) starts from uniform clouds and a uniform belief over the 3! assignments. Writes
// OUT/metrics.json, OUT/trajectory.csv, OUT/assignment_belief.png and OUT/trajectory.png with their gnuplot scripts
// (unless o.plots is false), and prints a summary.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "est/team/anonymous_team_mcl.hpp"
#include "node/pacer.hpp"
#include "sim/plot.hpp"
#include "sim/progress.hpp"
#include "team/team_logs.hpp"
#include "team/team_scenarios.hpp"
#include "view/live_view.hpp"

namespace sim::team {
namespace {

namespace fs = std::filesystem;

constexpr int kRobots = 3;
constexpr std::uint32_t kParticles = 1500;
using Filter = est::team::AnonymousTeamMcl<kRobots, kParticles>;

constexpr double kDefaultDuration = 60.0;  // s
constexpr float kDt = 0.1f;                // s, one step of every robot (motion, landmarks, sightings)
constexpr double kStepsPerSecond = 10.0;   // 1 / kDt, for the times written
constexpr float kReach = 6.0f;             // m, landmarks and robots
constexpr float kHalfFov = 1.5707963f;     // rad: the sensor looks forward, 180 degrees wide
constexpr float kDetection = 0.95f;        // each landmark and robot in reach is seen with this probability
constexpr float kFieldX = 20.0f, kFieldY = 15.0f;
constexpr float kLocalizedError = 0.5f;    // m: "localized" in the metrics, against the truth

// Fourteen landmarks, signatures 1..14, irregular so that no two places look alike.
const est::Landmark kLandmarks[] = {
    {2.0f, 2.5f, 1.0f},   {7.5f, 1.5f, 2.0f},  {13.0f, 2.0f, 3.0f},   {18.0f, 3.0f, 4.0f},  {3.0f, 7.0f, 5.0f},
    {9.0f, 6.0f, 6.0f},   {12.5f, 9.0f, 7.0f}, {17.5f, 8.0f, 8.0f},   {1.5f, 12.5f, 9.0f},  {6.5f, 13.0f, 10.0f},
    {11.0f, 13.5f, 11.0f}, {16.0f, 12.0f, 12.0f}, {5.0f, 10.0f, 13.0f}, {15.0f, 5.5f, 14.0f}};
constexpr std::int32_t kLandmarkCount = 14;

// A loop: a circle about (cx, cy) of radius r at speed v, counter-clockwise when ccw.
struct Loop {
  float cx, cy, r, v;
  bool ccw;
};
const Loop kLoops[kRobots] = {{6.0f, 7.5f, 3.5f, 0.5f, true}, {14.0f, 7.5f, 3.5f, 0.5f, false},
                              {10.0f, 7.5f, 5.5f, 0.5f, true}};

est::DiffDriveParams world_motion() {  // the ground truth's slip
  est::DiffDriveParams p;
  p.travel_sigma_per_m = 0.02f;
  p.travel_sigma_floor = 0.001f;
  p.final_rot_sigma = 0.003f;
  return p;
}

est::team::AnonymousTeamMclConfig filter_config() {
  est::team::AnonymousTeamMclConfig c;
  c.motion = world_motion();  // same wheels; the filter's noise larger than the world's
  c.motion.travel_sigma_per_m = 0.05f;
  c.motion.travel_sigma_floor = 0.002f;
  c.motion.final_rot_sigma = 0.01f;
  c.landmark_noise = {0.1f, 0.05f, 0.1f};
  c.sighting_sigma_range = 0.1f;
  c.sighting_sigma_bearing = 0.05f;
  c.sighting_reach_m = kReach;
  c.min_x = 0.0f;
  c.min_y = 0.0f;
  c.max_x = kFieldX;
  c.max_y = kFieldY;
  return c;
}

std::ofstream open_out(const fs::path& p) {
  std::ofstream f(p, std::ios::binary);
  if (!f) throw std::runtime_error("cannot write " + p.string());
  return f;
}

struct Row {
  double t;
  est::Pose2 truth[kRobots];
  est::Pose2 est[kRobots];
  bool localized[kRobots];
  float p_true;
  int best;
};

double d(float x) { return static_cast<double>(x); }

// A gnuplot script OUT/NAME.gp drawing OUT/NAME.png from the CSVs beside it: the common settings and the title.
std::ofstream plot_script(const fs::path& out, const std::string& name, int height_px, const std::string& title) {
  std::ofstream gp = open_out(out / (name + ".gp"));
  gp << "# sim_host run diffdrive-landmarks (gnuplot " << name << ".gp in this folder)\n"
     << "set terminal pngcairo size 1200," << height_px << " enhanced font 'Sans,11'\nset output '" << name
     << ".png'\nset datafile separator ','\nset grid lc rgb 'gray85'\nset key outside right top vertical noenhanced\n"
     << "set title '" << title << "' noenhanced\n";
  return gp;
}

// The belief on the true assignment over time: a time series against the 0.95 line, on [0, 1], the time it first
// crossed marked.
void plot_belief(const fs::path& out, double duration, double first_095) {
  {
    std::ofstream gp = plot_script(out, "assignment_belief", 600,
                                   "diffdrive-landmarks: belief on the true tag assignment (of the 3! tag-to-robot "
                                   "assignments)");
    gp << "set xlabel 't (s)'\nset ylabel 'P(true assignment)'\n"
       << "set xrange [0:" << duration << "]\nset yrange [0:1.05]\n";
    if (first_095 >= 0.0)
      gp << "set arrow 1 from " << first_095 << ", graph 0 to " << first_095
         << ", graph 1 nohead lw 1.5 lc rgb '#2ca02c'\n";
    gp << "plot 'trajectory.csv' skip 1 using 1:" << 2 + 7 * kRobots
       << " with steps lw 2 lc rgb '#3060c0' title 'P(true assignment)', "
          "0.95 with lines lw 1 dt 2 lc rgb 'red' title '0.95', "
          "NaN with lines lw 1.5 lc rgb '#2ca02c' title 'first above 0.95', "
          "'-' using 1:2 with points pt 7 ps 1.5 lc rgb '#3060c0' title 'prior (uniform, 1/6)'\n"
          "0," << 1.0 / 6.0 << "\ne\n";
    if (!gp) throw std::runtime_error("error writing assignment_belief.gp");
  }
  sim::run_gnuplot(out / "assignment_belief.gp", out / "assignment_belief.png");
}

// The true paths (wide, light) and the estimates while localized (narrow, dark, drawn over them), the landmarks.
void plot_trajectory(const fs::path& out) {
  {
    std::ofstream f = open_out(out / "landmarks.dat");
    for (std::int32_t j = 0; j < kLandmarkCount; ++j) f << d(kLandmarks[j].x) << "," << d(kLandmarks[j].y) << "\n";
  }
  {
    std::ofstream gp = plot_script(out, "trajectory", 900,
                                   "diffdrive-landmarks: true paths (wide) and estimates once localized (narrow)");
    gp << "set size ratio -1\nset xlabel 'x (m)'\nset ylabel 'y (m)'\nplot ";
    const char* light[kRobots] = {"#f0a0a0", "#a0d8a0", "#d0b0e8"};
    const char* dark[kRobots] = {"#b01010", "#107010", "#6020a0"};
    for (int r = 0; r < kRobots; ++r) {
      const int c = 2 + 7 * r;  // truth x, y, theta, estimate x, y, theta, localized
      gp << "'trajectory.csv' skip 1 using " << c << ":" << c + 1 << " with lines lw 5 lc rgb '" << light[r]
         << "' title 'robot " << r << " truth', '' skip 1 using ($" << c + 6 << " > 0 ? $" << c + 3
         << " : NaN):" << c + 4 << " with lines lw 1.2 lc rgb '" << dark[r] << "' title 'robot " << r
         << " estimate', ";
    }
    gp << "'landmarks.dat' using 1:2 with points pt 5 ps 1.5 lc rgb 'black' title 'landmarks'\n";
    if (!gp) throw std::runtime_error("error writing trajectory.gp");
  }
  sim::run_gnuplot(out / "trajectory.gp", out / "trajectory.png");
}

// One step to the view: each robot's truth and estimate (its cluster's covariance; robot 0's with the status), and
// the known landmarks at the view's rate.
void feed_view(view::LiveView& v, hal::TimeNs stamp_ns, const est::Pose2* truth, const Filter& filter) {
  for (int r = 0; r < kRobots; ++r) {
    v.publish_team_truth(r, stamp_ns, {d(truth[r].x), d(truth[r].y), d(truth[r].theta)});
    const est::team::TeamRobotEstimate& e = filter.estimate(r);
    view::EstimateSample s;
    s.stamp_ns = stamp_ns;
    s.pose = {d(e.mean.x), d(e.mean.y), d(e.mean.theta)};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) s.covariance[3 * i + j] = d(e.covariance(i, j));
    v.publish_team_estimate(r, s, r == 0);
  }
  if (!v.landmarks_due()) return;
  view::LandmarkSample l[kLandmarkCount];
  for (std::int32_t j = 0; j < kLandmarkCount; ++j) l[j] = {j, d(kLandmarks[j].x), d(kLandmarks[j].y), {}};
  v.publish_landmarks(stamp_ns, l, kLandmarkCount);
}

}  // namespace

void run_diffdrive_landmarks(const TeamRunOptions& o) {
  const double duration = o.duration_s < 0.0 ? kDefaultDuration : o.duration_s;
  if (!(duration > 0.0 && duration <= 3600.0))
    throw std::runtime_error("diffdrive-landmarks: --duration must be in (0, 3600] s");
  if (o.out.empty()) throw std::runtime_error("diffdrive-landmarks: --out is required");
  const fs::path out(o.out);
  fs::create_directories(out);

  const est::LandmarkMap map(kLandmarks, kLandmarkCount);
  const est::DiffDriveParams motion = world_motion();
  const est::LandmarkNoise noise{0.08f, 0.03f, 0.1f};
  // Streams: 0 the scenario's draws, 1 the world's motion and sensors; the filter takes the seed's own streams.
  est::Rng pick = est::Rng::stream(o.seed, 0u);
  est::Rng rng = est::Rng::stream(o.seed ^ 0x5eed5eed5eedull, 1u);

  // The true tag mapping: a non-identity permutation (h = 0 is the identity).
  const est::PermutationBelief<kRobots> table;
  const int true_h = 1 + static_cast<int>(pick.below(static_cast<std::uint32_t>(Filter::kHypotheses - 1)));
  std::int32_t robot_of_tag[kRobots];
  std::int32_t tag_of_robot[kRobots];
  for (int t = 0; t < kRobots; ++t) {
    robot_of_tag[t] = table.robot_of(true_h, t);
    tag_of_robot[robot_of_tag[t]] = t;
  }
  est::Pose2 truth[kRobots];
  for (int r = 0; r < kRobots; ++r) {
    const Loop& l = kLoops[r];
    const float phase = pick.uniform(-est::kPi, est::kPi);
    truth[r] = {l.cx + l.r * est::fmath::cos(phase), l.cy + l.r * est::fmath::sin(phase),
                est::fmath::normalize_angle(phase + (l.ccw ? est::kHalfPi : -est::kHalfPi))};
  }

  auto filter = std::make_unique<Filter>(filter_config(), map, o.seed);
  const int steps = static_cast<int>(std::lround(duration * kStepsPerSecond));
  std::vector<Row> rows;
  rows.reserve(static_cast<std::size_t>(steps));
  const float m_per_tick = est::diff_drive_m_per_tick(motion);
  std::vector<est::LandmarkMeasurement> lm;
  std::vector<est::team::RobotSighting> seen;
  Progress progress("diffdrive-landmarks", duration, o.quiet, Progress::Unit::simulated_s, 2.0);
  node::Pacer pacer(o.view != nullptr ? o.view_speed : 0.0);
  for (int k = 1; k <= steps; ++k) {
    progress.update(k / kStepsPerSecond);
    for (int r = 0; r < kRobots; ++r) {
      const Loop& l = kLoops[r];
      const float w = (l.ccw ? 1.0f : -1.0f) * l.v / l.r;
      const float half = 0.5f * w * motion.track_width;
      est::DiffDriveControl u;
      u.left_ticks = static_cast<std::int32_t>(std::lround((l.v - half) * kDt / m_per_tick));
      u.right_ticks = static_cast<std::int32_t>(std::lround((l.v + half) * kDt / m_per_tick));
      // The encoders count what the wheels turned; the ground moved the robot by that plus slip.
      truth[r] = est::sample_motion_model_diff_drive(est::wheel_travel_from_ticks(u, motion), truth[r], motion, rng);
      filter->predict(r, u);
    }
    for (int r = 0; r < kRobots; ++r) {
      lm.clear();
      for (std::int32_t j = 0; j < map.size(); ++j) {
        const est::LandmarkMeasurement e = est::expected_landmark_measurement(truth[r], map[j]);
        const bool in_view = e.range <= kReach && std::fabs(e.bearing) <= kHalfFov;
        if (in_view && rng.uniform() < kDetection)
          lm.push_back(est::sample_landmark_measurement(truth[r], map[j], noise, rng));
      }
      filter->correct_landmarks(r, lm.data(), static_cast<std::int32_t>(lm.size()));
    }
    seen.clear();
    for (int i = 0; i < kRobots; ++i) {
      for (int j = 0; j < kRobots; ++j) {
        if (j == i) continue;
        const est::LandmarkMeasurement e = est::expected_landmark_measurement(truth[i], {truth[j].x, truth[j].y, 0});
        if (e.range > kReach || std::fabs(e.bearing) > kHalfFov || !(rng.uniform() < kDetection)) continue;
        est::team::RobotSighting s;
        s.observer = i;
        s.tag = tag_of_robot[j];
        s.z.range_m = e.range + est::sample_normal(rng, noise.sigma_range);
        s.z.bearing_rad = est::fmath::normalize_angle(e.bearing + est::sample_normal(rng, noise.sigma_bearing));
        seen.push_back(s);
      }
    }
    filter->correct_sightings(seen.data(), static_cast<std::int32_t>(seen.size()));
    Row w;
    w.t = static_cast<double>(k) / kStepsPerSecond;
    for (int r = 0; r < kRobots; ++r) {
      w.truth[r] = truth[r];
      w.est[r] = filter->estimate(r).mean;
      w.localized[r] = filter->estimate(r).localized;
    }
    w.p_true = filter->probability(true_h);
    w.best = filter->belief().most_probable();
    rows.push_back(w);
    if (o.view != nullptr) {
      const hal::TimeNs stamp_ns = static_cast<hal::TimeNs>(std::llround(w.t * 1e9));
      pacer.at(stamp_ns);
      feed_view(*o.view, stamp_ns, truth, *filter);
    }
  }
  progress.finish();

  // trajectory.csv: t, then per robot truth (x, y, theta), estimate (x, y, theta), localized; then the belief.
  {
    std::ofstream f = open_out(out / "trajectory.csv");
    f << "t_s";
    for (int r = 0; r < kRobots; ++r) {
      const std::string p = "r" + std::to_string(r) + "_";
      f << "," << p << "true_x_m," << p << "true_y_m," << p << "true_theta_rad," << p << "est_x_m," << p
        << "est_y_m," << p << "est_theta_rad," << p << "localized";
    }
    f << ",p_true_assignment,best_hypothesis\n";
    char b[96];
    for (const Row& w : rows) {
      std::snprintf(b, sizeof b, "%.2f", w.t);
      f << b;
      for (int r = 0; r < kRobots; ++r) {
        std::snprintf(b, sizeof b, ",%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d", d(w.truth[r].x), d(w.truth[r].y),
                      d(w.truth[r].theta), d(w.est[r].x), d(w.est[r].y), d(w.est[r].theta), w.localized[r] ? 1 : 0);
        f << b;
      }
      std::snprintf(b, sizeof b, ",%.6f,%d\n", d(w.p_true), w.best);
      f << b;
    }
    if (!f) throw std::runtime_error("error writing trajectory.csv");
  }

  // Metrics. Per robot: the filter's first localized step; from then on the RMSE against the truth; and the time
  // after which the error stays below kLocalizedError to the end (-1: never).
  nlohmann::json m;
  m["scenario"] = "diffdrive-landmarks";
  m["seed"] = o.seed;
  m["duration_s"] = duration;
  m["particles_per_robot"] = kParticles;
  m["true_hypothesis"] = true_h;
  m["true_robot_of_tag"] = std::vector<int>(robot_of_tag, robot_of_tag + kRobots);
  nlohmann::json robots = nlohmann::json::array();
  bool all_localized = true;
  for (int r = 0; r < kRobots; ++r) {
    std::size_t first_flag = rows.size();
    for (std::size_t k = 0; k < rows.size() && first_flag == rows.size(); ++k)
      if (rows[k].localized[r]) first_flag = k;
    std::size_t stays = rows.size();
    for (std::size_t k = rows.size(); k-- > 0;) {
      const double e = std::hypot(d(rows[k].est[r].x - rows[k].truth[r].x), d(rows[k].est[r].y - rows[k].truth[r].y));
      if (!(e < static_cast<double>(kLocalizedError))) break;
      stays = k;
    }
    double se = 0.0, worst = 0.0;
    std::size_t n = 0;
    for (std::size_t k = first_flag; k < rows.size(); ++k, ++n) {
      const double e = std::hypot(d(rows[k].est[r].x - rows[k].truth[r].x), d(rows[k].est[r].y - rows[k].truth[r].y));
      se += e * e;
      worst = e > worst ? e : worst;
    }
    nlohmann::json j;
    j["robot"] = r;
    const bool localized = first_flag < rows.size() && stays < rows.size();
    all_localized = all_localized && localized;
    j["localized"] = localized;
    j["time_to_localize_s"] = stays < rows.size() ? rows[stays].t : -1.0;
    j["filter_localized_at_s"] = first_flag < rows.size() ? rows[first_flag].t : -1.0;
    j["position_rmse_m"] = n > 0 ? std::sqrt(se / static_cast<double>(n)) : -1.0;
    j["max_position_error_m"] = n > 0 ? worst : -1.0;
    robots.push_back(j);
  }
  m["robots"] = robots;
  m["all_localized"] = all_localized;
  double first_095 = -1.0, stays_095 = -1.0;
  for (const Row& w : rows)
    if (first_095 < 0.0 && w.p_true > 0.95f) first_095 = w.t;
  for (std::size_t k = rows.size(); k-- > 0;) {
    if (!(rows[k].p_true > 0.95f)) break;
    stays_095 = rows[k].t;
  }
  const est::team::AnonymousTeamMclCounters& c = filter->counters();
  nlohmann::json b;
  b["final_true_share"] = rows.empty() ? 0.0 : d(rows.back().p_true);
  b["time_to_095_s"] = first_095;
  b["time_stays_above_095_s"] = stays_095;
  b["final_best_hypothesis"] = rows.empty() ? -1 : rows.back().best;
  b["final_identity_share"] = d(filter->identity_probability());
  m["assignment_belief"] = b;
  m["ambiguous_steps"] = c.ambiguous_steps;
  m["sightings"] = c.sightings;
  nlohmann::json cj;
  cj["sighting_steps"] = c.sighting_steps;
  cj["sightings"] = c.sightings;
  cj["rejected_sightings"] = c.rejected_sightings;
  cj["duplicate_sightings"] = c.duplicate_sightings;
  cj["ambiguous_steps"] = c.ambiguous_steps;
  cj["corrections_applied"] = c.corrections_applied;
  cj["corrections_unlocalized"] = c.corrections_unlocalized;
  cj["self_sightings"] = c.self_sightings;
  cj["landmark_sightings"] = c.landmark_sightings;
  cj["rejected_landmarks"] = c.rejected_landmarks;
  cj["unknown_landmarks"] = c.unknown_landmarks;
  cj["predictions"] = c.predictions;
  cj["rejected_controls"] = c.rejected_controls;
  cj["injected_particles"] = c.injected_particles;
  cj["resamplings"] = c.resamplings;
  cj["degenerate_corrections"] = c.degenerate_corrections;
  m["counters"] = cj;
  {
    std::ofstream f = open_out(out / "metrics.json");
    f << m.dump(2) << "\n";
    if (!f) throw std::runtime_error("error writing metrics.json");
  }
  // The run's log: each robot's truth and estimate (no inputs: no node runs the anonymous team).
  std::vector<TeamLogStep> logged;
  for (const Row& w : rows) {
    TeamLogStep s;
    s.stamp_ns = static_cast<hal::TimeNs>(std::llround(w.t * 1e9));
    for (int r = 0; r < kRobots; ++r) {
      s.truth.push_back(w.truth[r]);
      hal::Estimate e;
      e.stamp_ns = s.stamp_ns;
      e.pose = w.est[r];
      s.estimate.push_back(e);
    }
    logged.push_back(s);
  }
  write_team_logs(out, "diffdrive-landmarks", {}, logged, nullptr);
  if (o.plots) {
    plot_belief(out, duration, first_095);
    plot_trajectory(out);
  }

  std::printf("diffdrive-landmarks: seed %llu, %.0f s, true assignment h=%d (tag -> robot %d %d %d)\n",
              static_cast<unsigned long long>(o.seed), duration, true_h, robot_of_tag[0], robot_of_tag[1],
              robot_of_tag[2]);
  for (const nlohmann::json& j : robots)
    std::printf("  robot %d: localized after %.1f s, position RMSE %.3f m (max %.3f m)\n", j["robot"].get<int>(),
                j["time_to_localize_s"].get<double>(), j["position_rmse_m"].get<double>(),
                j["max_position_error_m"].get<double>());
  std::printf("  belief on the true assignment: final %.4f, above 0.95 first at %.1f s; %u sightings, %u ambiguous "
              "steps of %u, %u corrections\n",
              d(rows.empty() ? 0.0f : rows.back().p_true), first_095, c.sightings, c.ambiguous_steps,
              c.sighting_steps, c.corrections_applied);
  std::printf("  wrote %s (metrics.json, trajectory.csv, run.lcmlog: each robot's truth and estimate)\n",
              out.string().c_str());
}

}  // namespace sim::team
