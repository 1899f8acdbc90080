#include "campaign/campaign.hpp"

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

namespace sim::campaign {
namespace {

std::uint64_t seed_of(const std::string& text) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
    throw std::invalid_argument("'" + text + "' is not a seed (a non-negative integer)");
  try {
    return std::stoull(text);
  } catch (const std::out_of_range&) {
    throw std::invalid_argument("'" + text + "' is out of range for a seed");
  }
}

std::string exact(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

}  // namespace

void parse_seed_range(const std::string& text, Campaign& c) {
  const std::size_t dots = text.find("..");
  c.first_seed = seed_of(text.substr(0, dots));
  c.last_seed = dots == std::string::npos ? c.first_seed : seed_of(text.substr(dots + 2));
  if (c.last_seed < c.first_seed) throw std::invalid_argument("'" + text + "': the last seed is below the first");
  if (c.last_seed - c.first_seed >= 100000) throw std::invalid_argument("'" + text + "': at most 100000 seeds");
}

std::filesystem::path seed_dir(const std::filesystem::path& dir, std::uint64_t seed) {
  return dir / ("seed-" + std::to_string(seed));
}

std::vector<std::string> run_options(const Campaign& c) {
  std::vector<std::string> o = {"--quiet", "--no-plots"};
  if (c.duration_s > 0.0) o.insert(o.end(), {"--duration", exact(c.duration_s)});
  for (const std::string& s : c.sets) o.insert(o.end(), {"--set", s});
  return o;
}

std::vector<std::string> seed_command(const Campaign& c, std::uint64_t seed, const std::filesystem::path& dir) {
  std::vector<std::string> cmd = {c.sim_host, "run", c.scenario, "--seed", std::to_string(seed),
                                  "--out", seed_dir(dir, seed).string()};
  const std::vector<std::string> o = run_options(c);
  cmd.insert(cmd.end(), o.begin(), o.end());
  return cmd;
}

void write_campaign_json(const Campaign& c, const std::filesystem::path& dir) {
  nlohmann::ordered_json j;
  j["scenario"] = c.scenario;
  j["seeds"] = {{"first", c.first_seed}, {"last", c.last_seed}};
  j["set"] = c.sets;
  j["duration_s"] = c.duration_s > 0.0 ? nlohmann::ordered_json(c.duration_s) : nlohmann::ordered_json(nullptr);
  j["sim_host"] = c.sim_host;
  std::string shown;
  for (const std::string& a : seed_command(c, c.first_seed, dir)) shown += (shown.empty() ? "" : " ") + a;
  j["seed_command"] = shown;
  j["seed_outputs"] = "seed-N/: metrics.json and the run's other files, run.log (stdout and stderr), exit_status";
  std::filesystem::create_directories(dir);
  std::ofstream f(dir / "campaign.json");
  f << j.dump(2) << "\n";
  if (!f) throw std::runtime_error("cannot write " + (dir / "campaign.json").string());
}

Campaign read_campaign_json(const std::filesystem::path& dir) {
  const std::filesystem::path p = dir / "campaign.json";
  std::ifstream f(p);
  if (!f) throw std::runtime_error("no campaign in " + dir.string() + " (" + p.string() + " cannot be read)");
  try {
    const nlohmann::json j = nlohmann::json::parse(f);
    Campaign c;
    c.scenario = j.at("scenario").get<std::string>();
    c.first_seed = j.at("seeds").at("first").get<std::uint64_t>();
    c.last_seed = j.at("seeds").at("last").get<std::uint64_t>();
    c.sets = j.at("set").get<std::vector<std::string>>();
    c.duration_s = j.at("duration_s").is_null() ? 0.0 : j.at("duration_s").get<double>();
    c.sim_host = j.at("sim_host").get<std::string>();
    if (c.last_seed < c.first_seed) throw std::runtime_error("seeds.last is below seeds.first");
    return c;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(p.string() + ": not a campaign: " + e.what());
  }
}

}  // namespace sim::campaign
