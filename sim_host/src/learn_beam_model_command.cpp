// The learn-beam-model subcommand (sim/learn_beam_model.hpp).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sim/commands.hpp"
#include "sim/learn_beam_model.hpp"

namespace sim {

void add_learn_beam_model_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "learn-beam-model",
      "Learn the beam model's intrinsic parameters (z_hit, z_short, z_max, z_rand, sigma_hit, lambda_short) by EM "
      "(Thrun table 6.2) from an LCM log's scans (EST_RANGE_SCAN) and ground truth (EST_GROUND_TRUTH), e.g. one "
      "written by `sim_host record`, on the map the log was recorded in");
  auto opts = std::make_shared<LearnBeamModelOptions>();
  auto json_out = std::make_shared<std::string>();
  auto mount = std::make_shared<std::string>("0,0,0");
  cmd->add_option("--log", opts->log_path, "LCM log file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--map", opts->map_yaml, "ROS map_server YAML (default: the synthetic office)");
  cmd->add_option("--mount", *mount, "rangefinder pose in the robot frame: x,y,theta (m, m, rad)")->capture_default_str();
  cmd->add_option("--stride", opts->beam_stride, "use every s-th beam")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--json", *json_out, "also write the learned parameters and counts as JSON");
  cmd->callback([opts, json_out, mount] {
    float mx = 0.0f, my = 0.0f, mt = 0.0f;
    if (std::sscanf(mount->c_str(), "%f,%f,%f", &mx, &my, &mt) != 3)
      throw CLI::ValidationError("--mount", "expected x,y,theta");
    opts->mount = {mx, my, mt};
    const LearnBeamModelResult r = learn_beam_model_from_log(*opts);
    const est::BeamModelParams& p = r.learned.params;
    std::cout << "learn-beam-model: " << r.readings_used << " readings from " << r.scans_used << " scans ("
              << r.scans_skipped << " scans without ground truth, " << r.readings_skipped << " non-finite readings)\n"
              << "  z_hit " << p.z_hit << "  z_short " << p.z_short << "  z_max " << p.z_max << "  z_rand " << p.z_rand
              << "\n  sigma_hit " << p.sigma_hit << " m  lambda_short " << p.lambda_short << " 1/m\n"
              << "  EM " << (r.learned.converged ? "converged" : "did NOT converge") << " after "
              << r.learned.iterations << " iterations, log-likelihood " << r.learned.log_likelihood << "\n";
    if (!json_out->empty()) {
      nlohmann::json j = {{"z_hit", p.z_hit},         {"z_short", p.z_short},
                          {"z_max", p.z_max},         {"z_rand", p.z_rand},
                          {"sigma_hit", p.sigma_hit}, {"lambda_short", p.lambda_short},
                          {"range_max", p.range_max}, {"converged", r.learned.converged},
                          {"iterations", r.learned.iterations}, {"scans_used", r.scans_used},
                          {"readings_used", r.readings_used}};
      std::ofstream(*json_out) << j.dump(2) << "\n";
    }
  });
}

}  // namespace sim
