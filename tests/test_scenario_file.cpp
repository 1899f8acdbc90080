// Scenario files (sim/scenario_file.hpp, sim/builtin_scenarios.hpp): TOML into the runners' configurations, the
// refusals located by line and column, the annotated example documenting every key at simulate's defaults, and the
// built-in scenarios.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "scratch_dir.hpp"
#include "sim/builtin_scenarios.hpp"
#include "sim/scenario_file.hpp"
#include "sim/sensor_stream.hpp"

namespace {

// The refusal's message, or "" when the text parses.
std::string refusal(const std::string& text) {
  try {
    sim::parse_scenario(text, "f.toml");
  } catch (const sim::ScenarioFileError& e) {
    return e.what();
  }
  return "";
}

// The keys a file documents: `key = ...` lines, commented out or not, under their [table] headers.
std::set<std::string> documented_keys(const std::string& text) {
  std::set<std::string> keys;
  std::istringstream in(text);
  std::string line, table;
  const std::regex header(R"(^\[([a-z_.-]+)\]\s*$)"), assignment(R"(^([a-z_0-9]+)\s*=)");
  while (std::getline(in, line)) {
    std::size_t i = line.find_first_not_of(" \t#");
    if (i == std::string::npos) continue;
    const std::string body = line.substr(i);
    std::smatch m;
    if (std::regex_match(body, m, header)) table = m[1];
    else if (std::regex_search(body, m, assignment)) keys.insert(table.empty() ? m[1].str() : table + "." + m[1].str());
  }
  return keys;
}

}  // namespace

TEST_CASE("a malformed scenario is refused with its file, line, column and reason", "[scenario]") {
  struct Case {
    const char* text;
    const char* where;   // FILE:LINE:COLUMN
    const char* reason;  // part of the reason
  };
  const Case cases[] = {
      {"seed = 1\n[robot]\nmodel = \"tank\"\n", "f.toml:3:9: ", "robot.model: 'tank' is not one of bicycle"},
      {"[sensors.rangefinder]\nhz = 10\nbeems = 360\n", "f.toml:3:1: ", "unknown key 'sensors.rangefinder.beems'"},
      {"duration_s = \"long\"\n", "f.toml:1:14: ", "duration_s: expected a number, got a string"},
      {"duration_s = -5\n", "f.toml:1:14: ", "duration_s: must be in (0, 3600] s"},
      {"[sensors.rangefinder]\nhz = 7\n", "f.toml:2:6: ", "must divide the 100 Hz simulation step"},
      {"[filter]\nparticles = 2.5\n", "f.toml:2:13: ", "filter.particles: expected an integer, got a float"},
      {"[filter]\nparticles = 50000\n", "f.toml:2:13: ", "filter.particles: must be in [1, 20000]"},
      {"[filter]\ntype = \"ekf\"\nstart = \"global\"\n", "f.toml:3:9: ", "the EKF tracks from the true start"},
      {"[robot]\nmodel = \"diff-drive\"\n[sensors.rangefinder]\nmount = \"handlebar\"\n", "f.toml:4:9: ",
       "the handlebar is the bicycle's"},
      {"[faults]\ncounts = { \"scan.vanished\" = 2 }\n", "f.toml:2:12: ", "unknown fault class 'scan.vanished'"},
      {"[robot]\nmodel = \"diff-drive\"\n[faults]\ncounts = { \"steering.nan\" = 2 }\n", "f.toml:4:12: ",
       "'steering.nan' does not apply"},
      {"[world]\nroute = [[1, 2], [3]]\n", "f.toml:2:18: ", "each waypoint is [x, y] or [x, y, speed_mps]"},
      {"[world]\nroute = [[1, 2], [3, 4, 9]]\n", "f.toml:2:25: ", "a waypoint's speed must be in (0, 3] m/s"},
      {"[world]\nmap = \"office.yaml\"\n", "f.toml:2:7: ", "world.route is required with world.map"},
      {"[robot]\nomni_noise = [0.1, 0.2]\n", "f.toml:2:14: ", "robot.omni_noise: expected 9 numbers, got 2"},
      {"[filter]\nomni_noise = [1, 1, 1, 1, -1, 1, 1, 1, 1]\n", "f.toml:2:27: ", "filter.omni_noise: must be in"},
      {"robot = 3\n", "f.toml:1:9: ", "robot: expected a table, got an integer"},
      {"[team]\nscenario = \"coop-slam\"\n[robot]\nmodel = \"omni\"\n", "f.toml:3:2: ",
       "unknown key 'robot': a team scenario reads description, seed, duration_s and [team]"},
      {"[team]\nscenario = \"solo\"\n", "f.toml:2:12: ", "team.scenario: 'solo' is not one of coop-slam"},
      {"[exercise]\nname = \"bicycle-exercise\"\n", "", ""},  // parses
      {"seed = 1\nseed = 2\n", "f.toml:2:", "cannot redefine existing integer 'seed'"},
      {"[robot\nmodel = \"bicycle\"\n", "f.toml:1:", ""},
      {"description = \"unterminated\n", "f.toml:1:", ""},
      // A check against a default names the table when the key is left out (the scenario fuzzer's find: it read
      // the absent key's node, a null reference).
      {"[sensors.rangefinder]\np_rand = 0.999\n", "f.toml:1:1: ", "p_rand + p_short must be <= 1"},
      {"[sensors.rangefinder]\np_rand = 0.5\np_short = 0.6\n", "f.toml:3:11: ", "p_rand + p_short must be <= 1"},
      // Control scripts (robot.controls): each command in the model's terms, times increasing, values in range.
      {"[world]\nroute = [[1, 2], [3, 4]]\n[robot]\ncontrols = [[0, 0.5, 0.1]]\n", "f.toml:4:12: ",
       "robot.controls: a robot follows world.route or a control script, not both"},
      {"[robot]\ncontrols = [[0, 0.5]]\n", "f.toml:2:13: ",
       "the bicycle robot's command is [t_s, v_mps, steer_rad] (3 numbers), got 2"},
      {"[robot]\nmodel = \"omni\"\ncontrols = [[0, 0.5, 0.1]]\n", "f.toml:3:13: ",
       "the omni robot's command is [t_s, v1_mps, v2_mps, w_rps] (4 numbers), got 3"},
      {"[robot]\nmodel = \"velocity\"\ncontrols = [[0, 0.5, 0], [5, 0.5, 0.2], [4, 0, 0]]\n", "f.toml:3:42: ",
       "robot.controls: t_s must be after the previous command's 5 s (got 4)"},
      {"[robot]\ncontrols = [[0, 0.5, 1.6]]\n", "f.toml:2:22: ", "steer_rad must be within the steering stops"},
      {"[robot]\nmodel = \"velocity\"\ncontrols = [[0, 4, 0]]\n", "f.toml:3:17: ", "v_mps must be in [-3, 3] m/s"},
      {"[robot]\nmodel = \"diff-drive\"\ncontrols = [[0, 1, -3.5]]\n", "f.toml:3:20: ",
       "w_rps must be in [-3, 3] rad/s"},
      {"[robot]\nmodel = \"holonomic\"\ncontrols = [[-1, 0.1, 0]]\n", "f.toml:3:14: ", "t_s must be in [0, 3600] s"},
      {"[robot]\nmodel = \"velocity\"\ncontrols = [[0, \"fast\", 0]]\n", "f.toml:3:17: ",
       "robot.controls: expected a number, got a string"},
      {"[robot]\ncontrols = 5\n", "f.toml:2:12: ", "robot.controls: expected an array of commands"},
      {"[robot]\ncontrols = [0, 0.5, 0]\n", "f.toml:2:13: ", "robot.controls: each command is [t_s, v_mps, steer_rad]"},
      {"[robot]\nmodel = \"velocity\"\ncontrols = [[0, 0.5, 0]]\n[faults]\nkidnap_at_s = 10\n", "f.toml:5:15: ",
       "a kidnapping carries the robot along its route"},
      {"[world]\nmap = \"lab.yaml\"\n[robot]\nmodel = \"velocity\"\ncontrols = [[0, 0.5, 0]]\n", "f.toml:5:12: ",
       "robot.start_pose is required with a control script in a map"},
      {"[robot]\nstart_pose = [1, 2]\n", "f.toml:2:14: ", "robot.start_pose: expected 3 numbers, got 2"},
      // A control script's path with a newline or a carriage return (found by fuzz_scenario): refused at the key,
      // on one line, not as a file that cannot be read under a name broken across lines.
      {"[robot]\ncontrols = \"ulvslip_fqnge_pl\\nmor\"\n", "f.toml:2:12: ",
       "robot.controls: the path has a control character (byte 0x0a at 17)"},
      {"[robot]\ncontrols = \"u_f1\\range_mtor\"\n", "f.toml:2:12: ",
       "robot.controls: the path has a control character (byte 0x0d at 5)"},
      {"[world]\nmap = \"lab\\t.yaml\"\n", "f.toml:2:7: ", "world.map: the path has a control character (byte 0x09 at 4)"},
      {"[world]\nlandmarks = \"marks.csv\\n\"\n", "f.toml:2:13: ",
       "world.landmarks: the path has a control character (byte 0x0a at 10)"},
  };
  for (const Case& c : cases) {
    INFO(c.text);
    const std::string e = refusal(c.text);
    INFO(e);
    if (std::string(c.where).empty()) {
      CHECK(e.empty());
      continue;
    }
    CHECK(e.rfind(c.where, 0) == 0);
    CHECK(e.find(c.reason) != std::string::npos);
    CHECK(e.find('\n') == std::string::npos);  // one line
  }
}

TEST_CASE("a control script's CSV file is refused with its own file, line, column and reason", "[scenario]") {
  const est::test::ScratchDir dir("scenario_controls_csv");
  const auto refused = [&](const std::string& csv) {
    std::ofstream(dir.path / "ctl.csv", std::ios::binary) << csv;
    std::ofstream(dir.path / "s.toml") << "[robot]\nmodel = \"velocity\"\ncontrols = \"ctl.csv\"\n";
    try {
      sim::read_scenario_file((dir.path / "s.toml").string());
    } catch (const sim::ScenarioFileError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string at = (dir.path / "ctl.csv").string() + ":";
  struct Case {
    const char* csv;
    const char* where;   // LINE:COLUMN after the CSV's path
    const char* reason;  // part of the reason
  };
  const Case cases[] = {
      {"0,0.5,0\n5,abc,0\n", "2:3: ", "robot.controls: 'abc' is not a finite number"},
      {"# t_s,v_mps,w_rps\n0,0.5,0\n\n3,0.5\n", "4:1: ", "command is [t_s, v_mps, w_rps] (3 numbers), got 2"},
      {"0,0.5,0\r\n0,0.5,0.1\r\n", "2:1: ", "t_s must be after the previous command's 0 s (got 0)"},
      {" 0, 0.5, 9\n", "1:10: ", "w_rps must be in [-3, 3] rad/s (got 9)"},
      {"0,0.5,nan\n", "1:7: ", "'nan' is not a finite number"},
      {"0,0.5,\n", "1:7: ", "'' is not a finite number"},
      {"# only a comment\n\n", "1:1: ", "the control script has no command"},
  };
  for (const Case& c : cases) {
    INFO(c.csv);
    const std::string e = refused(c.csv);
    INFO(e);
    CHECK(e.rfind(at + c.where, 0) == 0);
    CHECK(e.find(c.reason) != std::string::npos);
    CHECK(e.find('\n') == std::string::npos);
  }
  std::ofstream(dir.path / "t.toml") << "[robot]\ncontrols = \"none.csv\"\n";
  CHECK_THROWS_WITH(sim::read_scenario_file((dir.path / "t.toml").string()),
                    (dir.path / "none.csv").string() + ":1:1: cannot read the control script");
  // Nor a device or a folder (a path like /dev/zero would never end).
  std::ofstream(dir.path / "d.toml") << "[robot]\ncontrols = \"/dev/zero\"\n";
  CHECK_THROWS_WITH(sim::read_scenario_file((dir.path / "d.toml").string()),
                    "/dev/zero:1:1: the control script is not a regular file");
}

TEST_CASE("a control script's commands reach the configuration in the model's terms, from the file or a CSV",
          "[scenario]") {
  const sim::ScenarioFile f = sim::parse_scenario(
      "[robot]\nmodel = \"omni\"\nstart_pose = [11.5, 9, 0.5]\ncontrols = [[0, 0.5, 0.2, 0.35], [2.5, -0.1, 0, -1]]\n",
      "omni.toml");
  REQUIRE(f.scenario.controls.size() == 2);
  CHECK(f.scenario.controls[1].t_s == 2.5);
  CHECK(f.scenario.controls[0].u == est::sim::RobotCommand{0.5f, 0.2f, 0.35f});
  CHECK(f.scenario.controls[1].u == est::sim::RobotCommand{-0.1f, 0.0f, -1.0f});
  REQUIRE(f.scenario.start_pose.has_value());
  CHECK(f.scenario.start_pose->theta == 0.5f);
  CHECK(f.scenario.kidnap_at_s < 0.0);  // no route to be carried along
  CHECK(f.scenario.route.empty());

  const est::test::ScratchDir dir("scenario_controls_ok");
  std::filesystem::create_directories(dir.path / "scripts");
  std::ofstream(dir.path / "scripts" / "u.csv") << "# t_s,v_mps,steer_rad\n0, 0.6, 0.2\n\n12.5,0.3,-0.4\n";
  std::ofstream(dir.path / "b.toml") << "[robot]\ncontrols = \"scripts/u.csv\"\n";
  const sim::ScenarioFile g = sim::read_scenario_file((dir.path / "b.toml").string());
  REQUIRE(g.scenario.controls.size() == 2);
  CHECK(g.scenario.controls[1].t_s == 12.5);
  CHECK(g.scenario.controls[1].u == est::sim::RobotCommand{0.3f, -0.4f, 0.0f});
  CHECK_FALSE(g.scenario.start_pose.has_value());  // the route's start segment in the office

  // Held from each command's time until the next; still before the first.
  const est::sim::ControlScript script({{1.0, {0.5f, 0.1f, 0.0f}}, {3.0, {0.2f, 0.0f, 0.0f}}});
  CHECK(script.at(0.99) == est::sim::RobotCommand{});
  CHECK(script.at(1.0)[0] == 0.5f);
  CHECK(script.at(2.99)[0] == 0.5f);
  CHECK(script.at(3.0)[0] == 0.2f);
  CHECK(script.at(1e6)[0] == 0.2f);
  CHECK_THROWS(est::sim::ControlScript({}));
  CHECK_THROWS(est::sim::ControlScript({{1.0, {}}, {1.0, {}}}));
}

TEST_CASE("a scenario file that cannot be read is refused with its name", "[scenario]") {
  try {
    sim::read_scenario_file("/nonexistent/scenario.toml");
    FAIL("read");
  } catch (const sim::ScenarioFileError& e) {
    CHECK(std::string(e.what()).rfind("/nonexistent/scenario.toml:1:1: ", 0) == 0);
  }
  CHECK_THROWS_WITH(sim::load_scenario("no-such-scenario"), Catch::Contains("neither a built-in scenario"));
}

TEST_CASE("a file's map is found beside it and its keys reach the configuration", "[scenario]") {
  const sim::ScenarioFile f = sim::parse_scenario(
      "seed = 7\nduration_s = 12\n[world]\nmap = \"maps/lab.yaml\"\nroute = [[1, 2], [3.5, 4, 1.2]]\n"
      "[robot]\nmodel = \"velocity\"\nspeed_mps = 0.5\n[sensors.rangefinder]\nbeams = 180\nsigma_m = 0.05\n"
      "[filter]\nsensor_model = \"beam\"\nparticles = 5000\n[faults]\nplan = \"none\"\ncounts = { \"scan.dropped\" = 4 }\n"
      "kidnap_at_s = -1\n[metrics]\nhold_s = 1\n",
      "/tmp/scen/lab.toml");
  CHECK(f.runner == sim::ScenarioRunner::simulate);
  CHECK(f.scenario.seed == 7u);
  CHECK(f.scenario.duration_s == 12.0);
  CHECK(f.scenario.map_yaml == "/tmp/scen/maps/lab.yaml");
  REQUIRE(f.scenario.route.size() == 2);
  CHECK(f.scenario.route[1].x == 3.5f);
  CHECK(f.scenario.route[0].speed_mps == 0.0f);
  CHECK(f.scenario.route[1].speed_mps == 1.2f);
  CHECK(f.scenario.robot == sim::RobotKind::velocity);
  CHECK(f.scenario.speed_mps == 0.5);
  CHECK(f.scenario.beams == 180);
  CHECK(f.scenario.range_noise.sigma == 0.05f);
  CHECK(f.filter.range_model == node::RangeModel::beam);
  CHECK(f.filter.particles == 5000u);
  CHECK(f.scenario.faults == sim::FaultCounts{{"scan.dropped", 4}});
  CHECK(f.scenario.kidnap_at_s < 0.0);
  CHECK(f.filter.hold_s == 1.0);
}

TEST_CASE("an EKF scenario has no kidnapping and a tracking start unless asked, as simulate", "[scenario]") {
  const sim::ScenarioFile f = sim::parse_scenario("[filter]\ntype = \"ekf\"\n", "ekf.toml");
  CHECK(f.filter.filter == est::loop::Filter::ekf);
  CHECK(f.filter.start == sim::StartKind::tracking);
  CHECK(f.scenario.kidnap_at_s < 0.0);
  const sim::ScenarioFile g = sim::parse_scenario("[filter]\ntype = \"ekf\"\n[faults]\nkidnap_at_s = 20\n", "ekf.toml");
  CHECK(g.scenario.kidnap_at_s == 20.0);
}

TEST_CASE("the example documents every key the parser knows, and only those", "[scenario]") {
  const sim::BuiltinScenario* example = sim::find_builtin_scenario("example");
  REQUIRE(example != nullptr);
  const std::set<std::string> known = sim::scenario_file_keys();
  const std::set<std::string> documented = documented_keys(example->text);
  CHECK(known.size() > 60);
  for (const std::string& k : known) {
    INFO("key " << k);
    CHECK(documented.count(k) == 1);
  }
  for (const std::string& k : documented) {
    INFO("documented key " << k);
    CHECK(known.count(k) == 1);
  }
}

TEST_CASE("the example parses to simulate's defaults", "[scenario]") {
  const sim::BuiltinScenario* example = sim::find_builtin_scenario("example");
  REQUIRE(example != nullptr);
  const sim::ScenarioFile f = sim::parse_scenario(example->text, example->path);
  const sim::ScenarioFile empty = sim::parse_scenario("", "empty.toml");
  const sim::ScenarioConfig d;  // simulate's option defaults
  const sim::FilterOptions fd;
  for (const sim::ScenarioFile* p : {&f, &empty}) {
    const sim::ScenarioConfig& s = p->scenario;
    const sim::FilterOptions& o = p->filter;
    CHECK(p->runner == sim::ScenarioRunner::simulate);
    CHECK(s.seed == d.seed);
    CHECK(s.duration_s == d.duration_s);
    CHECK(s.map_yaml == d.map_yaml);
    CHECK(s.route.empty());
    CHECK(s.robot == d.robot);
    CHECK(s.speed_mps == d.speed_mps);
    CHECK(s.start_segment == d.start_segment);
    CHECK(s.handle_detents == d.handle_detents);
    CHECK(s.encoder_hz == d.encoder_hz);
    CHECK(s.encoder_scale_error == d.encoder_scale_error);
    CHECK(s.encoder_noise == d.encoder_noise);
    CHECK(s.slip_events == d.slip_events);
    CHECK(s.slip_duration_s == d.slip_duration_s);
    CHECK(s.slip_factor == d.slip_factor);
    CHECK(s.steering_sensor == d.steering_sensor);
    CHECK(s.steering_hz == d.steering_hz);
    CHECK(s.steering_sigma_deg == d.steering_sigma_deg);
    CHECK(s.steering_bias_deg == d.steering_bias_deg);
    CHECK(s.twist_hz == d.twist_hz);
    CHECK(s.odometry_hz == d.odometry_hz);
    CHECK(s.scan_hz == d.scan_hz);
    CHECK(s.beams == d.beams);
    CHECK(s.fov_deg == d.fov_deg);
    CHECK(s.range_max_m == d.range_max_m);
    CHECK(s.range_noise.sigma == d.range_noise.sigma);
    CHECK(s.range_noise.p_rand == d.range_noise.p_rand);
    CHECK(s.range_noise.p_short == d.range_noise.p_short);
    CHECK(s.handlebar == d.handlebar);
    CHECK(s.handlebar_mount.sensor_on_part.x == d.handlebar_mount.sensor_on_part.x);
    CHECK(s.rangefinder_mount.x == d.rangefinder_mount.x);
    CHECK(s.rangefinder_mount.y == d.rangefinder_mount.y);
    CHECK(s.rangefinder_mount.theta == d.rangefinder_mount.theta);
    CHECK(s.landmark_sensor.fov == Approx(d.landmark_sensor.fov));
    CHECK(s.landmark_hz == d.landmark_hz);
    CHECK(s.landmark_sensor.noise.sigma_range == d.landmark_sensor.noise.sigma_range);
    CHECK(s.landmark_sensor.noise.sigma_bearing == d.landmark_sensor.noise.sigma_bearing);
    CHECK(s.landmark_sensor.noise.sigma_signature == d.landmark_sensor.noise.sigma_signature);
    CHECK(s.landmark_sensor.max_range == d.landmark_sensor.max_range);
    CHECK(s.landmark_ids_known == d.landmark_ids_known);
    CHECK(s.faults == sim::default_fault_counts(d.robot, true, true));  // simulate's --faults default
    CHECK(s.kidnap_at_s == d.kidnap_at_s);
    CHECK(s.burst_at_s == d.burst_at_s);
    CHECK(s.burst_ms == d.burst_ms);
    CHECK(o.filter == fd.filter);
    CHECK(o.start == fd.start);
    CHECK(o.range_model == fd.range_model);
    CHECK(o.particles == fd.particles);
    CHECK(o.kld == fd.kld);
    CHECK(o.kld_min == fd.kld_min);
    CHECK(o.beam_stride == fd.beam_stride);
    CHECK(o.handle_positions == fd.handle_positions);
    CHECK(o.handle_reading_sigma_rad == fd.handle_reading_sigma_rad);
    CHECK(o.unknown_steer_sigma_rad == fd.unknown_steer_sigma_rad);
    CHECK(o.clearance_m == fd.clearance_m);
    CHECK(o.alpha_slow == fd.alpha_slow);
    CHECK(o.alpha_fast == fd.alpha_fast);
    CHECK(o.max_injection == fd.max_injection);
    CHECK(o.ekf_start_sigma_xy_m == fd.ekf_start_sigma_xy_m);
    CHECK(o.ekf_start_sigma_theta_rad == fd.ekf_start_sigma_theta_rad);
    CHECK(o.ekf_rot_sigma_rad == fd.ekf_rot_sigma_rad);
    CHECK(o.ekf_lost_sigma_m == fd.ekf_lost_sigma_m);
    CHECK(o.converge_pos_m == fd.converge_pos_m);
    CHECK(o.converge_heading_deg == fd.converge_heading_deg);
    CHECK(o.hold_s == fd.hold_s);
  }
  // The omni noise: the example writes out the simulator's and estimator_node's, the empty file leaves them.
  const sim::RobotModels models = sim::robot_models();
  CHECK(empty.scenario.omni_noise.empty());
  CHECK(empty.filter.omni_noise.empty());
  CHECK(f.scenario.omni_noise == std::vector<float>(models.truth.omni.alpha, models.truth.omni.alpha + 9));
  CHECK(f.filter.omni_noise == std::vector<float>(models.filter.omni.alpha, models.filter.omni.alpha + 9));
}

TEST_CASE("every built-in scenario parses, describes itself and is the file in the repository", "[scenario]") {
  const std::set<std::string> expected = {"bicycle-exercise", "bicycle-rangefinder", "bicycle-rangefinder-global",
                                          "coop-slam",        "coop-slam-team",      "diffdrive-landmarks",
                                          "diffdrive-script", "example",             "kidnapped",
                                          "omni-velocity"};
  std::set<std::string> names;
  for (const sim::BuiltinScenario& b : sim::builtin_scenarios()) {
    INFO(b.name);
    names.insert(b.name);
    const sim::ScenarioFile f = sim::parse_scenario(b.text, b.path);
    CHECK(!f.description.empty());
    CHECK(f.description.find('\n') == std::string::npos);
    // The embedded text is the repository's file.
    std::ifstream in(std::string(SIM_SCENARIOS_DIR) + "/" + b.name + ".toml", std::ios::binary);
    REQUIRE(in);
    std::ostringstream s;
    s << in.rdbuf();
    CHECK(s.str() == b.text);
  }
  CHECK(names == expected);
  CHECK(sim::load_scenario("coop-slam").runner == sim::ScenarioRunner::team);
  CHECK(sim::load_scenario("bicycle-exercise").runner == sim::ScenarioRunner::exercise);
  CHECK(sim::load_scenario("bicycle-rangefinder").filter.range_model == node::RangeModel::steered);
  // A FILE is read from disk.
  const std::string path = (std::filesystem::temp_directory_path() / "scenario_file_test.toml").string();
  std::ofstream(path) << "seed = 9\n[robot]\nmodel = \"holonomic\"\n";
  const sim::ScenarioFile f = sim::load_scenario(path);
  CHECK(f.scenario.seed == 9u);
  CHECK(f.scenario.robot == sim::RobotKind::holonomic);
  std::filesystem::remove(path);
}

namespace {

// The refusal of `text` with one --set KEY=VALUE, or "" when it parses.
std::string set_refusal(const std::string& text, const std::string& kv) {
  try {
    sim::parse_scenario(text, "f.toml", {sim::parse_override(kv)});
  } catch (const sim::ScenarioFileError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("an override (--set KEY=VALUE) puts a key by its dotted path, in the file's table or beside it", "[scenario]") {
  const sim::ScenarioFile f = sim::parse_scenario(
      "seed = 3\n[filter]\nparticles = 100\n", "f.toml",
      {sim::parse_override("filter.particles=256"), sim::parse_override("sensors.rangefinder.beams=90"),
       sim::parse_override("filter.sensor_model=beam"), sim::parse_override("seed=9"),
       sim::parse_override("faults.counts.scan.stale=2"), sim::parse_override("faults.kidnap_at_s=12.5")});
  CHECK(f.filter.particles == 256);
  CHECK(f.scenario.beams == 90);
  CHECK(f.filter.range_model == node::RangeModel::beam);
  CHECK(f.scenario.seed == 9);
  CHECK(f.scenario.faults.at("scan.stale") == 2);
  CHECK(f.scenario.kidnap_at_s == 12.5);
  // The later of two overrides of one key wins, as a later line of a file would be refused: the last one counts.
  CHECK(sim::parse_scenario("", "f.toml", {sim::parse_override("filter.particles=5"),
                                           sim::parse_override("filter.particles=7")})
            .filter.particles == 7);
  // A team scenario reads its file the same way.
  const sim::ScenarioFile t = sim::load_scenario("coop-slam", {sim::parse_override("team.scenario=coop-slam-team"),
                                                               sim::parse_override("duration_s=2")});
  CHECK(t.team == "coop-slam-team");
  CHECK(t.team_duration_s == 2.0);
}

TEST_CASE("an override is refused with its key and reason: an unknown key, another runner's key, a wrong value",
          "[scenario]") {
  CHECK(set_refusal("", "filter.partcles=64") ==
        "--set filter.partcles=64: unknown key 'filter.partcles' (sim_host/scenarios/example.toml documents every key)");
  CHECK(set_refusal("", "filter.particles=abc") ==
        "--set filter.particles=abc: filter.particles: expected an integer, got a string");
  CHECK(set_refusal("", "filter.particles=0") == "--set filter.particles=0: filter.particles: must be in [1, 20000] (got 0)");
  CHECK(set_refusal("", "robot.model=tank") ==
        "--set robot.model=tank: robot.model: 'tank' is not one of bicycle, diff-drive, velocity, odometry, omni, "
        "holonomic");
  CHECK(set_refusal("", "sensors.rangefinder.fov_deg=[1,2]") ==
        "--set sensors.rangefinder.fov_deg=[1,2]: sensors.rangefinder.fov_deg: expected a number, got an array");
  CHECK(set_refusal("", "faults.counts.scan.nope=2") ==
        "--set faults.counts.scan.nope=2: faults.counts: unknown fault class 'scan.nope' (sim_host simulate --help "
        "lists them)");
  CHECK(set_refusal("[team]\n", "filter.particles=3") ==
        "--set filter.particles=3: 'filter.particles' is not a key of a team scenario");
  CHECK(set_refusal("", "team.scenario=coop-slam") ==
        "--set team.scenario=coop-slam: 'team.scenario' is not a key of a single robot's scenario");
  CHECK(set_refusal("filter = 3\n", "filter.particles=3") ==
        "--set filter.particles=3: 'filter' is not a table in the file");
  CHECK(set_refusal("", "seed='x") == "--set seed='x: not a TOML value");
  CHECK_THROWS_WITH(sim::parse_override("particles"), "--set particles: expected KEY=VALUE (e.g. filter.particles=256)");
  CHECK_THROWS_WITH(sim::parse_override("=3"), "--set =3: expected KEY=VALUE (e.g. filter.particles=256)");
}
