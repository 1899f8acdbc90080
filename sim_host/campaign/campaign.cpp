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

// A folder name for a combination: its index, then its KEY=VALUEs with anything but [A-Za-z0-9._=+-] as '_' (the
// index keeps names unique whatever the values held).
std::string folder_name(std::size_t index, const std::vector<std::string>& sets) {
  std::string s = std::to_string(index);
  for (const std::string& kv : sets) {
    s += s.size() == std::to_string(index).size() ? "-" : ",";
    for (char ch : kv) {
      const bool plain = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
                         ch == '.' || ch == '_' || ch == '=' || ch == '+' || ch == '-';
      s += plain ? ch : '_';
    }
  }
  return s;
}

}  // namespace

std::vector<std::string> split_values(const std::string& text) {
  std::vector<std::string> out(1);
  int depth = 0;
  char quote = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (quote != 0) {
      if (ch == '\\' && quote == '"' && i + 1 < text.size()) {
        out.back() += ch;
        out.back() += text[++i];  // an escaped character, a quote included, stays in the string
        continue;
      }
      if (ch == quote) quote = 0;
    } else if (ch == '"' || ch == '\'') {
      quote = ch;
    } else if (ch == '[' || ch == '{') {
      ++depth;
    } else if ((ch == ']' || ch == '}') && depth > 0) {
      --depth;
    } else if (ch == ',' && depth == 0) {
      out.emplace_back();
      continue;
    }
    out.back() += ch;
  }
  return out;
}

void add_set(Campaign& c, const std::string& key_equals_values) {
  const std::size_t eq = key_equals_values.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument("--set " + key_equals_values + ": expected KEY=VALUE or KEY=V1,V2,...");
  const std::string key = key_equals_values.substr(0, eq);
  const std::vector<std::string> values = split_values(key_equals_values.substr(eq + 1));
  const auto given = [&](const std::string& k) {
    for (const GridAxis& a : c.grid)
      if (a.key == k) return true;
    for (const std::string& s : c.sets)
      if (s.compare(0, k.size() + 1, k + "=") == 0) return true;
    return false;
  };
  if (values.size() > 1) {
    for (const std::string& v : values)
      if (v.empty()) throw std::invalid_argument("--set " + key_equals_values + ": an empty value in the list");
    if (given(key)) throw std::invalid_argument("--set " + key_equals_values + ": '" + key + "' is given twice");
    c.grid.push_back({key, values});
    return;
  }
  for (const GridAxis& a : c.grid)
    if (a.key == key) throw std::invalid_argument("--set " + key_equals_values + ": '" + key + "' is given twice");
  c.sets.push_back(key_equals_values);
}

std::vector<Combination> Campaign::combinations() const {
  if (grid.empty()) return {Combination{}};
  std::size_t n = 1;
  for (const GridAxis& a : grid) n *= a.values.size();
  std::vector<Combination> out;
  for (std::size_t i = 0; i < n; ++i) {
    Combination k;
    k.index = i;
    std::size_t rest = i;
    std::vector<std::size_t> at(grid.size());
    for (std::size_t a = grid.size(); a-- > 0;) {
      at[a] = rest % grid[a].values.size();
      rest /= grid[a].values.size();
    }
    for (std::size_t a = 0; a < grid.size(); ++a) k.sets.push_back(grid[a].key + "=" + grid[a].values[at[a]]);
    k.name = folder_name(i, k.sets);
    out.push_back(k);
  }
  return out;
}

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

std::filesystem::path combination_dir(const std::filesystem::path& dir, const Combination& k) {
  return k.name.empty() ? dir : dir / k.name;
}

std::vector<std::string> combination_options(const Combination& k) {
  std::vector<std::string> o;
  for (const std::string& s : k.sets) o.insert(o.end(), {"--set", s});
  return o;
}

std::vector<std::string> run_options(const Campaign& c) {
  std::vector<std::string> o = {"--quiet", "--no-plots"};
  if (c.duration_s > 0.0) o.insert(o.end(), {"--duration", exact(c.duration_s)});
  for (const std::string& s : c.sets) o.insert(o.end(), {"--set", s});
  return o;
}

std::vector<std::string> seed_command(const Campaign& c, const Combination& k, std::uint64_t seed,
                                      const std::filesystem::path& dir) {
  std::vector<std::string> cmd = {c.sim_host, "run", c.scenario, "--seed", std::to_string(seed),
                                  "--out", seed_dir(combination_dir(dir, k), seed).string()};
  const std::vector<std::string> o = run_options(c), g = combination_options(k);
  cmd.insert(cmd.end(), o.begin(), o.end());
  cmd.insert(cmd.end(), g.begin(), g.end());
  return cmd;
}

void write_campaign_json(const Campaign& c, const std::filesystem::path& dir) {
  nlohmann::ordered_json j;
  j["scenario"] = c.scenario;
  j["seeds"] = {{"first", c.first_seed}, {"last", c.last_seed}};
  j["set"] = c.sets;
  if (!c.grid.empty()) {
    j["grid"] = nlohmann::ordered_json::array();
    for (const GridAxis& a : c.grid) j["grid"].push_back({{"key", a.key}, {"values", a.values}});
    j["combinations"] = nlohmann::ordered_json::array();
    for (const Combination& k : c.combinations())
      j["combinations"].push_back({{"index", k.index}, {"name", k.name}, {"set", k.sets}});
  }
  j["duration_s"] = c.duration_s > 0.0 ? nlohmann::ordered_json(c.duration_s) : nlohmann::ordered_json(nullptr);
  j["sim_host"] = c.sim_host;
  std::string shown;
  for (const std::string& a : seed_command(c, c.combinations().front(), c.first_seed, dir)) shown += (shown.empty() ? "" : " ") + a;
  j["seed_command"] = shown;
  j["seed_outputs"] = c.grid.empty()
                          ? "seed-N/: metrics.json and the run's other files, run.log (stdout and stderr), exit_status"
                          : "COMBINATION/seed-N/ (combinations[].name): metrics.json and the run's other files, run.log "
                            "(stdout and stderr), exit_status";
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
    if (j.contains("grid"))
      for (const nlohmann::json& a : j.at("grid"))
        c.grid.push_back({a.at("key").get<std::string>(), a.at("values").get<std::vector<std::string>>()});
    c.duration_s = j.at("duration_s").is_null() ? 0.0 : j.at("duration_s").get<double>();
    c.sim_host = j.at("sim_host").get<std::string>();
    if (c.last_seed < c.first_seed) throw std::runtime_error("seeds.last is below seeds.first");
    return c;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(p.string() + ": not a campaign: " + e.what());
  }
}

}  // namespace sim::campaign
