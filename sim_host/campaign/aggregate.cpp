#include "campaign/aggregate.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "campaign/campaign.hpp"
#include "campaign/statistics.hpp"
#include "sim/plot.hpp"

namespace sim::campaign {
namespace fs = std::filesystem;
using ordered = nlohmann::ordered_json;

namespace {

// Metrics that are better when larger (the rest: errors, times, counts, are worse when larger).
bool higher_is_better(const std::string& name) {
  for (const char* s : {"in_95_band_share", "true_share", "landmarks_mapped", "localized_time_s", "accepted"})
    if (name.size() >= std::string(s).size() && name.compare(name.size() - std::string(s).size(), std::string::npos, s) == 0)
      return true;
  return false;
}

// An array element's name in a path: its phase, robot or id when it has one, else its index.
std::string element_name(const nlohmann::json& e, std::size_t i) {
  if (e.is_object())
    for (const char* k : {"phase", "robot", "id", "name"}) {
      const auto it = e.find(k);
      if (it == e.end()) continue;
      std::string s = it->is_string() ? it->get<std::string>() : it->dump();
      for (char& c : s)
        if (c == ' ' || c == '.') c = '_';
      return s;
    }
  return std::to_string(i);
}

// metrics.json says "none" with -1 for an error or a time that has no value (a run never localized).
bool none_sentinel(const std::string& name, double v) {
  if (v != -1.0) return false;
  for (const char* s : {"rmse", "error", "time_to", "_at_s"})
    if (name.find(s) != std::string::npos) return true;
  return false;
}

void flatten(const nlohmann::json& j, const std::string& path, std::map<std::string, double>& out,
             std::set<std::string>* booleans) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (path.empty() && (it.key() == "scenario" || it.key() == "filter" || it.key() == "seed" || it.key() == "timing"))
        continue;
      flatten(it.value(), path.empty() ? it.key() : path + "." + it.key(), out, booleans);
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) flatten(j[i], path + "." + element_name(j[i], i), out, booleans);
  } else if (j.is_boolean()) {
    out[path] = j.get<bool>() ? 1.0 : 0.0;
    if (booleans != nullptr) booleans->insert(path);
  } else if (j.is_number() && !none_sentinel(path, j.get<double>())) {
    out[path] = j.get<double>();
  }
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

void write_json(const fs::path& p, const ordered& a) {
  std::ofstream f(p);
  f << a.dump(2) << "\n";
  if (!f) throw std::runtime_error("cannot write " + p.string());
}

// The headline metrics drawn per seed: the RMSEs (at most four), else the first four that differ between seeds.
std::vector<std::string> plotted(const ordered& metrics) {
  std::vector<std::string> out;
  for (auto it = metrics.begin(); it != metrics.end() && out.size() < 4; ++it)
    if (it.key().find("rmse") != std::string::npos) out.push_back(it.key());
  for (auto it = metrics.begin(); it != metrics.end() && out.empty(); ++it)
    if (it.value()["min"] != it.value()["max"]) out.push_back(it.key());
  if (out.size() > 4) out.resize(4);
  return out;
}

// aggregate.png: each headline metric per seed, its mean and p95 as lines (data in aggregate.dat, script aggregate.gp).
void plot_aggregate(const fs::path& dir, const ordered& a, const std::vector<SeedResult>& seeds) {
  const std::vector<std::string> names = plotted(a["metrics"]);
  if (names.empty()) return;
  {
    std::ofstream d(dir / "aggregate.dat");
    d << "# seed";
    for (const std::string& n : names) d << " " << n;
    d << "\n";
    for (const SeedResult& s : seeds) {
      if (!s.ok) continue;
      d << s.seed;
      for (const std::string& n : names) {
        const auto it = s.metrics.find(n);
        if (it == s.metrics.end()) d << " NaN";
        else d << " " << it->second;
      }
      d << "\n";
    }
  }
  std::ofstream gp(dir / "aggregate.gp");
  gp << "set terminal pngcairo size 1200," << 300 * names.size() + 100 << " font ',10'\n"
     << "set output 'aggregate.png'\nset datafile missing 'NaN'\nset grid\nset key outside right\n"
     << "set offsets 0.5, 0.5, graph 0.05, 0\n" << (seeds.size() <= 30 ? "set xtics 1\n" : "set format x '%.0f'\n")
     << "set multiplot layout " << names.size() << ",1 title 'campaign " << a["campaign"]["scenario"].get<std::string>()
     << ": " << a["seeds"]["succeeded"].get<std::size_t>() << " of " << a["seeds"]["total"].get<std::size_t>()
     << " seeds'\n";
  for (std::size_t i = 0; i < names.size(); ++i) {
    const ordered& m = a["metrics"][names[i]];
    gp << "set xlabel 'seed'\nset ylabel '" << names[i] << "' noenhanced\n"
       << "plot 'aggregate.dat' using 1:" << i + 2 << " with impulses lw 2 lc rgb '#3060c0' notitle, '' using 1:"
       << i + 2 << " with points pt 7 lc rgb '#3060c0' title 'per seed', " << m["mean"].get<double>()
       << " with lines lc rgb '#2ca02c' title 'mean', " << m["p95"].get<double>()
       << " with lines dt 2 lc rgb '#d62728' title 'p95'\n";
  }
  gp << "unset multiplot\n";
  gp.close();
  run_gnuplot(dir / "aggregate.gp", dir / "aggregate.png");
}

}  // namespace

std::map<std::string, double> flatten_metrics(const nlohmann::json& metrics, std::set<std::string>* booleans) {
  std::map<std::string, double> out;
  flatten(metrics, "", out, booleans);
  return out;
}

SeedResult read_seed_result(const fs::path& dir, std::uint64_t seed, std::set<std::string>* booleans) {
  SeedResult r;
  r.seed = seed;
  const fs::path d = seed_dir(dir, seed);
  r.log = d / "run.log";
  std::ifstream status(d / "exit_status");
  if (!(status >> r.exit_status)) {
    r.exit_status = -1;
    r.reason = fs::is_directory(d) ? "no exit_status: the run did not finish" : "no result: the run never started";
    return r;
  }
  if (r.exit_status != 0) {
    r.reason = "exit status " + std::to_string(r.exit_status);
    return r;
  }
  try {
    r.metrics = flatten_metrics(nlohmann::json::parse(slurp(d / "metrics.json")), booleans);
  } catch (const nlohmann::json::exception& e) {
    r.reason = "exit status 0 but no readable metrics.json (" + std::string(e.what()) + ")";
    return r;
  }
  r.ok = true;
  return r;
}

namespace {

// One group of seeds (the campaign's, or one combination's): counts, failures, every metric's statistics, per seed.
ordered summarize_seeds(const std::vector<SeedResult>& seeds, const std::set<std::string>& booleans) {
  std::map<std::string, std::vector<SeedValue>> values;
  std::size_t ok = 0;
  for (const SeedResult& s : seeds) {
    if (!s.ok) continue;
    ++ok;
    for (const auto& [name, v] : s.metrics) values[name].push_back({s.seed, v});
  }
  ordered a;
  a["seeds"] = {{"total", seeds.size()}, {"succeeded", ok}, {"failed", seeds.size() - ok}};
  ordered failures = ordered::array();
  for (const SeedResult& s : seeds)
    if (!s.ok)
      failures.push_back({{"seed", s.seed},
                          {"exit_status", s.exit_status >= 0 ? ordered(s.exit_status) : ordered(nullptr)},
                          {"reason", s.reason},
                          {"log", s.log.string()}});
  a["failures"] = failures;
  ordered metrics = ordered::object();
  for (const auto& [name, v] : values) {
    const Worst worst = booleans.count(name) > 0 || higher_is_better(name) ? Worst::smallest : Worst::largest;
    const MetricSummary m = summarize(v, worst);
    ordered missing = ordered::array();  // succeeded seeds whose metrics.json has no number for it (null: e.g. never localized)
    for (const SeedResult& s : seeds)
      if (s.ok && s.metrics.count(name) == 0) missing.push_back(s.seed);
    metrics[name] = {{"seeds", m.count},      {"mean", m.mean}, {"median", m.median}, {"p95", m.p95},
                     {"min", m.min},          {"max", m.max},
                     {"worst", {{"seed", m.worst_seed}, {"value", m.worst_value}}},
                     {"worst_is", worst == Worst::largest ? "largest" : "smallest"},
                     {"missing_seeds", missing}};
  }
  a["metrics"] = metrics;
  ordered per_seed = ordered::object();
  for (const SeedResult& s : seeds)
    if (s.ok) per_seed[std::to_string(s.seed)] = s.metrics;
  a["per_seed"] = per_seed;
  return a;
}

std::vector<SeedResult> read_seeds(const Campaign& c, const fs::path& dir, std::set<std::string>& booleans) {
  std::vector<SeedResult> seeds;
  for (std::uint64_t s = c.first_seed;; ++s) {
    seeds.push_back(read_seed_result(dir, s, &booleans));
    if (s == c.last_seed) break;
  }
  return seeds;
}

// aggregate.png of a grid: each headline metric per combination (x: the combination's index, named below the axis),
// every seed's value as a point, the combination's mean and p95 as marks (data in aggregate.dat, script aggregate.gp).
void plot_grid(const fs::path& dir, const ordered& a, const std::vector<std::vector<SeedResult>>& groups) {
  std::vector<std::string> names;
  for (const ordered& k : a["combinations"]) {
    names = plotted(k["metrics"]);
    if (!names.empty()) break;
  }
  if (names.empty()) return;
  {
    std::ofstream d(dir / "aggregate.dat");
    d << "# combination seed";
    for (const std::string& n : names) d << " " << n;
    d << "\n";
    for (std::size_t i = 0; i < groups.size(); ++i)
      for (const SeedResult& s : groups[i]) {
        if (!s.ok) continue;
        d << i << " " << s.seed;
        for (const std::string& n : names) {
          const auto it = s.metrics.find(n);
          if (it == s.metrics.end()) d << " NaN";
          else d << " " << it->second;
        }
        d << "\n";
      }
    std::ofstream m(dir / "aggregate_combinations.dat");
    m << "# combination then mean p95 of each of:";
    for (const std::string& n : names) m << " " << n;
    m << "\n";
    for (std::size_t i = 0; i < groups.size(); ++i) {
      m << i;
      for (const std::string& n : names) {
        const ordered& ms = a["combinations"][i]["metrics"];
        if (!ms.contains(n)) m << " NaN NaN";
        else m << " " << ms[n]["mean"].get<double>() << " " << ms[n]["p95"].get<double>();
      }
      m << "\n";
    }
  }
  // Each combination named by its values below its index; the keys, in the same order, in the axis label.
  std::string xtics = "set xtics (", keys;
  for (const auto& kv : a["combinations"][0]["set"].items()) keys += (keys.empty() ? "" : " / ") + kv.key();
  for (std::size_t i = 0; i < groups.size(); ++i) {
    std::string label = std::to_string(i);
    for (const auto& kv : a["combinations"][i]["set"].items()) label += "\\n" + kv.value().get<std::string>();
    for (char& ch : label)
      if (ch == '"') ch = '\'';
    xtics += (i == 0 ? "\"" : ", \"") + label + "\" " + std::to_string(i);
  }
  xtics += ") noenhanced\n";
  std::ofstream gp(dir / "aggregate.gp");
  gp << "set terminal pngcairo size 1200," << (320 + 14 * a["combinations"][0]["set"].size()) * names.size() + 100 << " font ',10'\n"
     << "set output 'aggregate.png'\nset datafile missing 'NaN'\nset grid\nset key outside right\n"
     << "set offsets 0.5, 0.5, graph 0.05, 0\n" << xtics
     << "set multiplot layout " << names.size() << ",1 title 'campaign " << a["campaign"]["scenario"].get<std::string>()
     << ": " << groups.size() << " combinations x " << (groups.empty() ? 0 : groups.front().size()) << " seeds, "
     << a["seeds"]["succeeded"].get<std::size_t>() << " of " << a["seeds"]["total"].get<std::size_t>()
     << " runs succeeded; x: the combination of " << keys << "' noenhanced\n";
  for (std::size_t i = 0; i < names.size(); ++i)
    gp << "set ylabel '" << names[i] << "' noenhanced\n"
       << "plot 'aggregate.dat' using 1:" << i + 3 << " with points pt 7 lc rgb '#3060c0' title 'per seed', "
       << "'aggregate_combinations.dat' using 1:" << 2 * i + 2
       << " with linespoints pt 5 ps 1.5 lc rgb '#2ca02c' title 'mean', '' using 1:" << 2 * i + 3
       << " with points pt 2 ps 1.5 lc rgb '#d62728' title 'p95'\n";
  gp << "unset multiplot\n";
  gp.close();
  run_gnuplot(dir / "aggregate.gp", dir / "aggregate.png");
}

const char* kNote =
    "metrics: every number of the seeds' metrics.json by dotted path (booleans 0/1; configuration and "
    "wall-clock timing left out); median of an even count: the mean of the middle two; p95: nearest rank; "
    "worst: the seed with the largest value (worst_is: smallest for booleans and shares that are better "
    "larger), the lowest seed on a tie; missing_seeds: succeeded seeds that gave no number (null)";

}  // namespace

ordered aggregate_campaign(const fs::path& dir, bool plot) {
  const Campaign c = read_campaign_json(dir);
  std::set<std::string> booleans;
  ordered a;
  a["campaign"] = nlohmann::ordered_json::parse(slurp(dir / "campaign.json"));
  if (c.grid.empty()) {
    const std::vector<SeedResult> seeds = read_seeds(c, dir, booleans);
    const ordered g = summarize_seeds(seeds, booleans);
    for (auto it = g.begin(); it != g.end(); ++it) a[it.key()] = it.value();
    a["note"] = kNote;
    write_json(dir / "aggregate.json", a);
    if (plot && a["seeds"]["succeeded"].get<std::size_t>() > 0) plot_aggregate(dir, a, seeds);
    return a;
  }
  // A grid: the statistics per combination, each over its seeds; the counts and failures over every run.
  const std::vector<Combination> combinations = c.combinations();
  std::vector<std::vector<SeedResult>> groups;
  for (const Combination& k : combinations) groups.push_back(read_seeds(c, combination_dir(dir, k), booleans));
  std::size_t total = 0, ok = 0;
  ordered failures = ordered::array(), list = ordered::array();
  for (std::size_t i = 0; i < combinations.size(); ++i) {
    const Combination& k = combinations[i];
    ordered g = summarize_seeds(groups[i], booleans);
    ordered e;
    e["index"] = k.index;
    e["name"] = k.name;
    ordered set = ordered::object();
    for (const std::string& kv : k.sets) set[kv.substr(0, kv.find('='))] = kv.substr(kv.find('=') + 1);
    e["set"] = set;
    e["dir"] = combination_dir(dir, k).string();
    for (auto it = g.begin(); it != g.end(); ++it) e[it.key()] = it.value();
    total += g["seeds"]["total"].get<std::size_t>();
    ok += g["seeds"]["succeeded"].get<std::size_t>();
    for (ordered f : g["failures"]) {
      f["combination"] = k.name;
      failures.push_back(f);
    }
    list.push_back(e);
  }
  a["seeds"] = {{"total", total}, {"succeeded", ok}, {"failed", total - ok}};
  a["failures"] = failures;
  a["combinations"] = list;
  a["note"] = std::string(kNote) + "; with a grid: seeds and failures count every run, each combination has its own "
                                   "statistics over its seeds (combinations[].metrics, per_seed)";
  write_json(dir / "aggregate.json", a);
  if (plot && ok > 0) plot_grid(dir, a, groups);
  return a;
}

std::string aggregate_summary(const ordered& a) {
  std::ostringstream s;
  const bool grid = a.contains("combinations");
  s << "campaign " << a["campaign"]["scenario"].get<std::string>() << ", seeds "
    << a["campaign"]["seeds"]["first"].get<std::uint64_t>() << ".." << a["campaign"]["seeds"]["last"].get<std::uint64_t>();
  if (grid) s << " x " << a["combinations"].size() << " combinations";
  s << ": " << a["seeds"]["succeeded"].get<std::size_t>() << " of " << a["seeds"]["total"].get<std::size_t>()
    << " succeeded, " << a["seeds"]["failed"].get<std::size_t>() << " failed\n";
  for (const auto& f : a["failures"])
    s << "  FAILED " << (f.contains("combination") ? f["combination"].get<std::string>() + " " : std::string())
      << "seed " << f["seed"].get<std::uint64_t>() << ": " << f["reason"].get<std::string>() << "; log "
      << f["log"].get<std::string>() << "\n";
  const auto lines = [&s](const ordered& metrics, const std::string& indent) {
    for (const std::string& name : plotted(metrics)) {
      const ordered& m = metrics[name];
      char line[256];
      std::snprintf(line, sizeof line, "%s%s: mean %.4g, median %.4g, p95 %.4g, worst %.4g (seed %llu)\n",
                    indent.c_str(), name.c_str(), m["mean"].get<double>(), m["median"].get<double>(),
                    m["p95"].get<double>(), m["worst"]["value"].get<double>(),
                    static_cast<unsigned long long>(m["worst"]["seed"].get<std::uint64_t>()));
      s << line;
    }
  };
  if (!grid) {
    lines(a["metrics"], "  ");
    return s.str();
  }
  for (const ordered& k : a["combinations"]) {
    s << "  " << k["name"].get<std::string>() << ": " << k["seeds"]["succeeded"].get<std::size_t>() << " of "
      << k["seeds"]["total"].get<std::size_t>() << " seeds\n";
    lines(k["metrics"], "    ");
  }
  return s.str();
}

}  // namespace sim::campaign
