// The campaign aggregator (sim_host/campaign/statistics.hpp, aggregate.hpp): the statistics against hand-computed
// values, and a hand-made campaign folder with succeeded, failed and missing seeds.
#include <catch2/catch.hpp>

#include <fstream>
#include <nlohmann/json.hpp>

#include "campaign/aggregate.hpp"
#include "campaign/campaign.hpp"
#include "campaign/statistics.hpp"
#include "scratch_dir.hpp"

using sim::campaign::MetricSummary;
using sim::campaign::summarize;
using sim::campaign::Worst;

TEST_CASE("mean, median, p95 and the worst seed of an odd count", "[campaign]") {
  // Sorted: 1, 1.5, 3, 4, 9. Mean 18.5 / 5; median the third; p95 the ceil(4.75) = 5th.
  const MetricSummary m = summarize({{1, 3.0}, {2, 1.0}, {3, 4.0}, {4, 1.5}, {5, 9.0}}, Worst::largest);
  CHECK(m.count == 5);
  CHECK(m.mean == Approx(3.7));
  CHECK(m.median == 3.0);
  CHECK(m.p95 == 9.0);
  CHECK(m.min == 1.0);
  CHECK(m.max == 9.0);
  CHECK(m.worst_seed == 5);
  CHECK(m.worst_value == 9.0);
  const MetricSummary s = summarize({{1, 3.0}, {2, 1.0}, {3, 4.0}, {4, 1.5}, {5, 9.0}}, Worst::smallest);
  CHECK(s.worst_seed == 2);
  CHECK(s.worst_value == 1.0);
}

TEST_CASE("an even count's median is the mean of the middle two; p95 is the nearest rank", "[campaign]") {
  const MetricSummary m = summarize({{10, 2.0}, {11, 8.0}, {12, 4.0}, {13, 6.0}}, Worst::largest);
  CHECK(m.mean == 5.0);
  CHECK(m.median == 5.0);
  CHECK(m.p95 == 8.0);  // ceil(3.8) = 4th
  std::vector<sim::campaign::SeedValue> twenty;
  for (int i = 1; i <= 20; ++i) twenty.push_back({static_cast<std::uint64_t>(100 + i), static_cast<double>(i)});
  const MetricSummary t = summarize(twenty, Worst::largest);
  CHECK(t.p95 == 19.0);  // ceil(19) = 19th, not the maximum
  CHECK(t.median == 10.5);
  CHECK(t.worst_seed == 120);
  const MetricSummary one = summarize({{7, 0.25}}, Worst::largest);
  CHECK((one.mean == 0.25 && one.median == 0.25 && one.p95 == 0.25 && one.worst_seed == 7));
  CHECK_THROWS(summarize({}, Worst::largest));
}

TEST_CASE("equally bad seeds: the lowest is the worst", "[campaign]") {
  CHECK(summarize({{9, 2.0}, {4, 2.0}, {6, 1.0}}, Worst::largest).worst_seed == 4);
  CHECK(summarize({{9, 1.0}, {4, 2.0}, {6, 1.0}}, Worst::smallest).worst_seed == 6);
}

TEST_CASE("a campaign folder: metrics over the succeeded seeds, each failed or missing seed with its log",
          "[campaign]") {
  namespace fs = std::filesystem;
  est::test::ScratchDir d("campaign_aggregate");
  sim::campaign::Campaign c;
  c.scenario = "kidnapped";
  c.first_seed = 1;
  c.last_seed = 5;
  c.sim_host = "/bin/false";
  sim::campaign::write_campaign_json(c, d.path);
  const auto seed = [&](int n, const std::string& status, const std::string& metrics) {
    const fs::path s = sim::campaign::seed_dir(d.path, static_cast<std::uint64_t>(n));
    fs::create_directories(s);
    std::ofstream(s / "run.log") << "seed " << n << "\n";
    if (!status.empty()) std::ofstream(s / "exit_status") << status << "\n";
    if (!metrics.empty()) std::ofstream(s / "metrics.json") << metrics;
  };
  seed(1, "0", R"({"seed": 1, "scenario": {"beams": 360}, "timing": {"wall_s": 3.5}, "localized": true,
                   "accuracy": {"rmse_position_m": 0.1, "max_heading_error_deg": 2.0},
                   "phases": [{"phase": "global localization", "time_to_localize_s": 2.0}]})");
  seed(2, "0", R"({"seed": 2, "scenario": {"beams": 360}, "timing": {"wall_s": 1.5}, "localized": false,
                   "accuracy": {"rmse_position_m": 0.3, "max_heading_error_deg": -1, "turns": -1},
                   "phases": [{"phase": "global localization", "time_to_localize_s": null}]})");
  seed(3, "1", "");             // failed
  seed(4, "0", "{ truncated");  // exit 0 but no readable metrics
  // seed 5: never started (no folder)
  const nlohmann::json a = nlohmann::json::parse(sim::campaign::aggregate_campaign(d.path, false).dump());
  CHECK(nlohmann::json::parse(est::test::slurp(d.path / "aggregate.json")) == a);
  CHECK(a["seeds"]["total"] == 5);
  CHECK(a["seeds"]["succeeded"] == 2);
  CHECK(a["seeds"]["failed"] == 3);
  REQUIRE(a["failures"].size() == 3);
  CHECK(a["failures"][0]["seed"] == 3);
  CHECK(a["failures"][0]["exit_status"] == 1);
  CHECK(a["failures"][0]["log"] == (d.path / "seed-3" / "run.log").string());
  CHECK(a["failures"][1]["seed"] == 4);
  CHECK(a["failures"][1]["reason"].get<std::string>().find("no readable metrics.json") != std::string::npos);
  CHECK(a["failures"][2]["seed"] == 5);
  CHECK(a["failures"][2]["exit_status"].is_null());
  CHECK(a["failures"][2]["reason"] == "no result: the run never started");
  const auto& rmse = a["metrics"]["accuracy.rmse_position_m"];
  CHECK(rmse["seeds"] == 2);
  CHECK(rmse["mean"].get<double>() == Approx(0.2));
  CHECK(rmse["worst"]["seed"] == 2);
  CHECK(rmse["worst_is"] == "largest");
  // A boolean is worst false; a null is a missing seed, not a zero.
  CHECK(a["metrics"]["localized"]["worst"]["seed"] == 2);
  CHECK(a["metrics"]["localized"]["worst_is"] == "smallest");
  const auto& ttl = a["metrics"]["phases.global_localization.time_to_localize_s"];
  CHECK(ttl["seeds"] == 1);
  CHECK(ttl["missing_seeds"] == nlohmann::json::array({2}));
  // So is metrics.json's -1 for an error that has no value; a -1 of another kind is a number.
  CHECK(a["metrics"]["accuracy.max_heading_error_deg"]["missing_seeds"] == nlohmann::json::array({2}));
  CHECK(a["metrics"]["accuracy.turns"]["mean"] == -1.0);
  // The configuration and the wall-clock timing are not metrics.
  CHECK(a["metrics"].contains("timing.wall_s") == false);
  CHECK(a["metrics"].contains("scenario.beams") == false);
  CHECK(a["metrics"].contains("seed") == false);
  CHECK(a["per_seed"]["1"]["accuracy.rmse_position_m"] == 0.1);
  CHECK(a["per_seed"].contains("3") == false);
}

TEST_CASE("a --set with several values is a grid axis; commas inside a TOML array or string are the value's",
          "[campaign]") {
  using sim::campaign::split_values;
  CHECK(split_values("256") == std::vector<std::string>{"256"});
  CHECK(split_values("100,200,300") == std::vector<std::string>{"100", "200", "300"});
  CHECK(split_values("[1, 2],[3,4]") == std::vector<std::string>{"[1, 2]", "[3,4]"});
  CHECK(split_values("'a,b',\"c,\\\"d\",{x = 1, y = 2}") ==
        std::vector<std::string>{"'a,b'", "\"c,\\\"d\"", "{x = 1, y = 2}"});
  sim::campaign::Campaign c;
  sim::campaign::add_set(c, "filter.particles=100,200");
  sim::campaign::add_set(c, "duration_s=3");
  sim::campaign::add_set(c, "sensors.scan.range_sigma_m=0.01,0.02,0.05");
  CHECK(c.sets == std::vector<std::string>{"duration_s=3"});
  REQUIRE(c.grid.size() == 2);
  CHECK_THROWS_WITH(sim::campaign::add_set(c, "filter.particles=300"), Catch::Contains("given twice"));
  CHECK_THROWS_WITH(sim::campaign::add_set(c, "duration_s=1,2"), Catch::Contains("given twice"));
  CHECK_THROWS_WITH(sim::campaign::add_set(c, "filter.type=mcl,"), Catch::Contains("an empty value"));
  // The cartesian product, the first axis varying slowest; each a folder of its own.
  const auto k = c.combinations();
  REQUIRE(k.size() == 6);
  CHECK(k[0].sets == std::vector<std::string>{"filter.particles=100", "sensors.scan.range_sigma_m=0.01"});
  CHECK(k[2].sets == std::vector<std::string>{"filter.particles=100", "sensors.scan.range_sigma_m=0.05"});
  CHECK(k[3].sets == std::vector<std::string>{"filter.particles=200", "sensors.scan.range_sigma_m=0.01"});
  CHECK(k[5].name == "5-filter.particles=200,sensors.scan.range_sigma_m=0.05");
  sim::campaign::Campaign q;
  sim::campaign::add_set(q, "world.map='a/b c',\"a_b_c\"");
  CHECK(q.combinations()[0].name == "0-world.map=_a_b_c_");
  CHECK(q.combinations()[1].name == "1-world.map=_a_b_c_");
  // Without a grid: one unnamed combination, the seeds in the campaign's own folder.
  CHECK(sim::campaign::Campaign{}.combinations().size() == 1);
  CHECK(sim::campaign::combination_dir("/x", sim::campaign::Campaign{}.combinations()[0]) == "/x");
}

TEST_CASE("a grid's folder: statistics per combination, failures named with their combination", "[campaign]") {
  namespace fs = std::filesystem;
  est::test::ScratchDir d("campaign_aggregate_grid");
  sim::campaign::Campaign c;
  c.scenario = "kidnapped";
  c.first_seed = 1;
  c.last_seed = 2;
  c.sim_host = "/bin/false";
  sim::campaign::add_set(c, "filter.particles=100,200");
  sim::campaign::write_campaign_json(c, d.path);
  const auto k = c.combinations();
  REQUIRE(k.size() == 2);
  const auto seed = [&](std::size_t combo, int n, const std::string& status, double rmse) {
    const fs::path s = sim::campaign::seed_dir(sim::campaign::combination_dir(d.path, k[combo]), static_cast<std::uint64_t>(n));
    fs::create_directories(s);
    std::ofstream(s / "run.log") << "run\n";
    std::ofstream(s / "exit_status") << status << "\n";
    std::ofstream(s / "metrics.json") << R"({"accuracy": {"rmse_position_m": )" << rmse << "}}";
  };
  seed(0, 1, "0", 0.4);
  seed(0, 2, "0", 0.2);
  seed(1, 1, "0", 0.05);
  seed(1, 2, "2", 0.0);
  const nlohmann::json a = nlohmann::json::parse(sim::campaign::aggregate_campaign(d.path, false).dump());
  CHECK(a["seeds"]["total"] == 4);
  CHECK(a["seeds"]["succeeded"] == 3);
  REQUIRE(a["failures"].size() == 1);
  CHECK(a["failures"][0]["combination"] == k[1].name);
  CHECK(a["failures"][0]["seed"] == 2);
  CHECK(a["failures"][0]["log"] == (d.path / k[1].name / "seed-2" / "run.log").string());
  REQUIRE(a["combinations"].size() == 2);
  const nlohmann::json &c0 = a["combinations"][0], &c1 = a["combinations"][1];
  CHECK(c0["set"] == nlohmann::json{{"filter.particles", "100"}});
  CHECK(c1["set"] == nlohmann::json{{"filter.particles", "200"}});
  CHECK(c0["metrics"]["accuracy.rmse_position_m"]["mean"].get<double>() == Approx(0.3));
  CHECK(c0["metrics"]["accuracy.rmse_position_m"]["worst"]["seed"] == 1);
  CHECK(c1["metrics"]["accuracy.rmse_position_m"]["seeds"] == 1);
  CHECK(c1["metrics"]["accuracy.rmse_position_m"]["mean"].get<double>() == Approx(0.05));
  CHECK(c1["seeds"]["failed"] == 1);
  CHECK(a.contains("metrics") == false);  // no statistics over different parameters
  // campaign.json round-trips the grid.
  const sim::campaign::Campaign r = sim::campaign::read_campaign_json(d.path);
  REQUIRE(r.grid.size() == 1);
  CHECK(r.grid[0].values == std::vector<std::string>{"100", "200"});
  CHECK(sim::campaign::aggregate_summary(sim::campaign::aggregate_campaign(d.path, false))
            .find("FAILED " + k[1].name + " seed 2: exit status 2") != std::string::npos);
}
