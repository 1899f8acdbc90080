// Scenario files: TOML (toml++) into the runners' configurations, every refusal located by line and column.
#include "sim/scenario_file.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <vector>

#include "sim/angles.hpp"
#include "sim/sample_motion.hpp"
#include "sim/sensor_stream.hpp"
#include "team/team_scenarios.hpp"

namespace sim {
namespace {

// The keys read while scenario_file_keys() parses its documents (null otherwise).
thread_local std::set<std::string>* g_keys = nullptr;

std::string located(const std::string& source, const toml::source_position& at, const std::string& reason) {
  std::ostringstream s;
  s << source << ":" << at.line << ":" << at.column << ": " << reason;
  return s.str();
}

// A --set value is parsed as its own document named "--set KEY=VALUE": a refusal of it names the option, not a line.
constexpr std::string_view kSetPrefix = "--set ";
std::string located(const std::string& source, const toml::source_region& at, const std::string& reason) {
  if (at.path != nullptr && at.path->rfind(kSetPrefix, 0) == 0) return *at.path + ": " + reason;
  return located(source, at.begin, reason);
}

const char* type_name(toml::node_type t) {
  switch (t) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// A condition on a number and how the refusal states it.
struct Check {
  bool (*ok)(double);
  const char* what;
};
constexpr Check kAny{[](double) { return true; }, ""};
constexpr Check kPositive{[](double v) { return v > 0.0; }, "must be > 0"};
constexpr Check kNonNegative{[](double v) { return v >= 0.0; }, "must be >= 0"};
constexpr Check kNoise{[](double v) { return v >= 0.0 && v <= 1.0e6; }, "must be in [0, 1e6]"};
constexpr Check kProbability{[](double v) { return v >= 0.0 && v <= 1.0; }, "must be in [0, 1]"};
constexpr Check kFov{[](double v) { return v > 0.0 && v <= 360.0; }, "must be in (0, 360] deg"};
constexpr Check kSpeed{[](double v) { return v > 0.0 && v <= 3.0; }, "must be in (0, 3] m/s"};
constexpr Check kDuration{[](double v) { return v > 0.0 && v <= 3600.0; }, "must be in (0, 3600] s"};

// One table of the file: typed reads with defaults, each key marked as read; done() refuses the keys never read.
class Section {
 public:
  Section(const std::string& source, const toml::table* t, std::string path, toml::source_position at)
      : source_(source), t_(t), path_(std::move(path)), at_(at) {}

  [[noreturn]] void fail(const toml::node& n, const std::string& reason) const {
    throw ScenarioFileError(located(source_, n.source(), reason));
  }
  [[noreturn]] void fail_at(const toml::source_region& at, const std::string& reason) const {
    throw ScenarioFileError(located(source_, at, reason));
  }
  // A refusal about `key`, at the key when the file has it, else at this table (a check that involves a default).
  [[noreturn]] void fail_key(const char* key, const std::string& reason) {
    if (const toml::node* n = get(key)) fail(*n, reason);
    throw ScenarioFileError(located(source_, at_, reason));
  }

  // Marks `key` read (and, for a value rather than a table, known to scenario_file_keys()).
  const toml::node* get(const char* key, bool value = true) {
    read_.insert(key);
    if (g_keys != nullptr && value) g_keys->insert(name(key));
    return t_ != nullptr ? t_->get(key) : nullptr;
  }
  std::string name(const char* key) const { return path_.empty() ? std::string(key) : path_ + "." + key; }

  double number(const char* key, double def, Check check = kAny) {
    const toml::node* n = get(key);
    if (n == nullptr) return def;
    double v = 0.0;
    if (const auto* i = n->as_integer()) v = static_cast<double>(i->get());
    else if (const auto* f = n->as_floating_point()) v = f->get();
    else fail(*n, name(key) + ": expected a number, got " + type_name(n->type()));
    if (!std::isfinite(v)) fail(*n, name(key) + ": must be finite");
    if (!check.ok(v)) fail(*n, name(key) + ": " + check.what + " (got " + fmt(v) + ")");
    return v;
  }
  float number_f(const char* key, float def, Check check = kAny) {
    return static_cast<float>(number(key, static_cast<double>(def), check));
  }

  std::int64_t integer(const char* key, std::int64_t def, std::int64_t lo, std::int64_t hi) {
    const toml::node* n = get(key);
    if (n == nullptr) return def;
    const auto* i = n->as_integer();
    if (i == nullptr) fail(*n, name(key) + ": expected an integer, got " + type_name(n->type()));
    const std::int64_t v = i->get();
    if (v < lo || v > hi)
      fail(*n, name(key) + ": must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " +
                   std::to_string(v) + ")");
    return v;
  }
  int integer_i(const char* key, int def, int lo, int hi) { return static_cast<int>(integer(key, def, lo, hi)); }

  // An array of `count` numbers (an empty array or none: `def`).
  std::vector<float> numbers(const char* key, std::size_t count, Check check) {
    const toml::node* n = get(key);
    if (n == nullptr) return {};
    const auto* a = n->as_array();
    if (a == nullptr) fail(*n, name(key) + ": expected an array of " + std::to_string(count) + " numbers, got " + type_name(n->type()));
    if (a->size() != count && !a->empty())
      fail(*n, name(key) + ": expected " + std::to_string(count) + " numbers, got " + std::to_string(a->size()));
    std::vector<float> out;
    for (const toml::node& c : *a) {
      double v = 0.0;
      if (const auto* i = c.as_integer()) v = static_cast<double>(i->get());
      else if (const auto* f = c.as_floating_point()) v = f->get();
      else fail(c, name(key) + ": expected a number, got " + type_name(c.type()));
      if (!std::isfinite(v) || !check.ok(v)) fail(c, name(key) + ": " + check.what + " (got " + fmt(v) + ")");
      out.push_back(static_cast<float>(v));
    }
    return out;
  }

  // A sample rate of the 100 Hz simulation: divides 100.
  int rate_hz(const char* key, int def) {
    const int v = integer_i(key, def, 1, 100);
    if (100 % v != 0) fail(*get(key), name(key) + ": must divide the 100 Hz simulation step (got " + std::to_string(v) + ")");
    return v;
  }

  bool boolean(const char* key, bool def) {
    const toml::node* n = get(key);
    if (n == nullptr) return def;
    const auto* b = n->as_boolean();
    if (b == nullptr) fail(*n, name(key) + ": expected a boolean, got " + type_name(n->type()));
    return b->get();
  }

  std::string text(const char* key, const std::string& def) {
    const toml::node* n = get(key);
    if (n == nullptr) return def;
    const auto* s = n->as_string();
    if (s == nullptr) fail(*n, name(key) + ": expected a string, got " + type_name(n->type()));
    return s->get();
  }

  // A file's path: a string without control characters (a newline in a path is a typo, and the messages naming
  // the file as FILE:LINE:COLUMN would be broken across lines).
  std::string path(const char* key) {
    const std::string v = text(key, "");
    if (const toml::node* n = get(key)) check_path(*n, key, v);
    return v;
  }
  void check_path(const toml::node& n, const char* key, const std::string& v) const {
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto c = static_cast<unsigned char>(v[i]);
      if (c < 0x20 || c == 0x7f) {
        char hex[8];
        std::snprintf(hex, sizeof hex, "0x%02x", static_cast<unsigned>(c));
        fail(n, name(key) + ": the path has a control character (byte " + hex + " at " + std::to_string(i + 1) + ")");
      }
    }
  }

  std::string choice(const char* key, const std::string& def, std::initializer_list<const char*> options) {
    const std::string v = text(key, def);
    std::string all;
    for (const char* o : options) {
      if (v == o) return v;
      all += all.empty() ? std::string(o) : std::string(", ") + o;
    }
    fail(*get(key), name(key) + ": '" + v + "' is not one of " + all);
  }

  // A sub-table (absent: empty, every key at its default).
  Section table(const char* key) {
    const toml::node* n = get(key, false);
    if (n == nullptr) return Section(source_, nullptr, name(key), at_);
    const auto* t = n->as_table();
    if (t == nullptr) fail(*n, name(key) + ": expected a table, got " + type_name(n->type()));
    return Section(source_, t, name(key), n->source().begin);
  }

  // Refuses every key of the table that was never read.
  void done() const {
    if (t_ == nullptr) return;
    for (auto&& [k, v] : *t_) {
      if (read_.count(std::string(k.str())) > 0) continue;
      const toml::source_region& at = k.source().begin.line > 0 ? k.source() : v.source();
      throw ScenarioFileError(
          located(source_, at, "unknown key '" + name(std::string(k.str()).c_str()) + "'" + hint_));
    }
  }

  // Said after an unknown key's name (what the table does read).
  void hint(std::string h) { hint_ = std::move(h); }
  const std::string& source() const { return source_; }

 private:
  const std::string& source_;
  const toml::table* t_;
  std::string path_;
  toml::source_position at_;
  std::set<std::string> read_;
  std::string hint_;
};

std::vector<est::sim::Waypoint> read_route(Section& world) {
  std::vector<est::sim::Waypoint> out;
  const toml::node* n = world.get("route");
  if (n == nullptr) return out;
  const auto* a = n->as_array();
  if (a == nullptr) world.fail(*n, "world.route: expected an array of [x, y] pairs, got " + std::string(type_name(n->type())));
  for (const toml::node& p : *a) {
    const auto* xy = p.as_array();
    if (xy == nullptr || xy->size() < 2 || xy->size() > 3)
      world.fail(p, "world.route: each waypoint is [x, y] or [x, y, speed_mps] (m, map frame; m/s)");
    double v[3] = {0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < xy->size(); ++i) {
      const toml::node& c = *xy->get(i);
      if (const auto* in = c.as_integer()) v[i] = static_cast<double>(in->get());
      else if (const auto* f = c.as_floating_point()) v[i] = f->get();
      else world.fail(c, "world.route: expected a number, got " + std::string(type_name(c.type())));
      if (!std::isfinite(v[i])) world.fail(c, "world.route: must be finite");
      if (i == 2 && !kSpeed.ok(v[i])) world.fail(c, std::string("world.route: a waypoint's speed ") + kSpeed.what);
    }
    out.push_back({static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])});
  }
  if (out.size() == 1) world.fail(*n, "world.route: needs at least two waypoints (or none: the world's own route)");
  return out;
}

// A control script's command [t_s, terms...] (world/control_script.hpp): why it is refused and which of its fields
// (0: t_s) the reason is about; an empty reason when it is fine. `previous_t_s` < 0: the first command.
struct CommandIssue {
  std::string reason;
  std::size_t field = 0;  // kWholeCommand: the command itself
};
constexpr std::size_t kWholeCommand = static_cast<std::size_t>(-1);
CommandIssue check_command(const std::vector<double>& v, RobotKind model, double previous_t_s) {
  const std::size_t terms = static_cast<std::size_t>(est::sim::command_terms(model));
  const std::string names = est::sim::command_term_names(model);
  if (v.size() != terms + 1)
    return {std::string("robot.controls: the ") + to_string(model) + " robot's command is [t_s, " + names + "] (" +
                std::to_string(terms + 1) + " numbers), got " + std::to_string(v.size()),
            kWholeCommand};
  if (!(v[0] >= 0.0 && v[0] <= 3600.0)) return {"robot.controls: t_s must be in [0, 3600] s (got " + fmt(v[0]) + ")", 0};
  if (previous_t_s >= 0.0 && !(v[0] > previous_t_s))
    return {"robot.controls: t_s must be after the previous command's " + fmt(previous_t_s) + " s (got " + fmt(v[0]) +
                ")",
            0};
  const double steer_max = static_cast<double>(robot_models().truth.bicycle.steer_max);
  std::size_t at = 0;
  for (std::size_t i = 1; i <= terms; ++i) {
    const std::size_t end = names.find(", ", at);
    const std::string name = names.substr(at, end == std::string::npos ? std::string::npos : end - at);
    at = end + 2;
    const double x = v[i];
    const auto unit = [&](const char* u) { return name.size() > 4 && name.compare(name.size() - 4, 4, u) == 0; };
    if (unit("_mps") && !(std::fabs(x) <= 3.0))
      return {"robot.controls: " + name + " must be in [-3, 3] m/s (got " + fmt(x) + ")", i};
    if (unit("_rps") && !(std::fabs(x) <= 3.0))
      return {"robot.controls: " + name + " must be in [-3, 3] rad/s (got " + fmt(x) + ")", i};
    if (unit("_rad") && !(std::fabs(x) <= steer_max))
      return {"robot.controls: " + name + " must be within the steering stops, +-" + fmt(steer_max) + " rad (got " +
                  fmt(x) + ")",
              i};
  }
  return {};
}

est::sim::TimedCommand timed_command(const std::vector<double>& v) {
  est::sim::TimedCommand c;
  c.t_s = v[0];
  for (std::size_t i = 1; i < v.size(); ++i) c.u[i - 1] = static_cast<float>(v[i]);
  return c;
}

constexpr std::uintmax_t kMaxControlScriptBytes = 16u << 20;

// A control script as a CSV file: "t_s,term,..." per line, '#' lines and blank lines skipped; refused as
// PATH:LINE:COLUMN: reason.
std::vector<est::sim::TimedCommand> read_controls_csv(const std::string& path, RobotKind model) {
  // A regular file of bounded size (not a device or a pipe that never ends).
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw ScenarioFileError(path + ":1:1: the control script is not a regular file");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > kMaxControlScriptBytes)
    throw ScenarioFileError(path + ":1:1: the control script is larger than 16 MiB");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw ScenarioFileError(path + ":1:1: cannot read the control script");
  std::vector<est::sim::TimedCommand> out;
  std::string line;
  double previous = -1.0;
  for (std::size_t number = 1; std::getline(f, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto refuse = [&](std::size_t column, const std::string& reason) {
      throw ScenarioFileError(path + ":" + std::to_string(number) + ":" + std::to_string(column + 1) + ": " + reason);
    };
    std::vector<double> v;
    std::vector<std::size_t> columns;
    for (std::size_t at = 0;;) {
      const std::size_t comma = line.find(',', at);
      const std::string field = line.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
      const std::size_t lead = field.find_first_not_of(" \t");
      const std::size_t tail = field.find_last_not_of(" \t");
      const std::string text = lead == std::string::npos ? "" : field.substr(lead, tail - lead + 1);
      char* end = nullptr;
      const double x = text.empty() ? 0.0 : std::strtod(text.c_str(), &end);
      if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(x))
        refuse(at + (lead == std::string::npos ? 0 : lead), "robot.controls: '" + text + "' is not a finite number");
      v.push_back(x);
      columns.push_back(at + lead);
      if (comma == std::string::npos) break;
      at = comma + 1;
    }
    const CommandIssue issue = check_command(v, model, previous);
    if (!issue.reason.empty()) refuse(issue.field < columns.size() ? columns[issue.field] : columns.front(), issue.reason);
    previous = v[0];
    out.push_back(timed_command(v));
  }
  if (out.empty()) throw ScenarioFileError(path + ":1:1: robot.controls: the control script has no command");
  return out;
}

// robot.controls: an array of commands [t_s, terms...], or the path of a CSV file of them (beside() resolves it).
template <typename Beside>
std::vector<est::sim::TimedCommand> read_controls(Section& robot, RobotKind model, const Beside& beside) {
  const toml::node* n = robot.get("controls");
  if (n == nullptr) return {};
  if (const auto* path = n->as_string()) {
    if (path->get().empty()) robot.fail(*n, "robot.controls: an empty path (leave the key out for none)");
    robot.check_path(*n, "controls", path->get());
    return read_controls_csv(beside(path->get()), model);
  }
  const auto* a = n->as_array();
  if (a == nullptr)
    robot.fail(*n, "robot.controls: expected an array of commands [t_s, " +
                       std::string(est::sim::command_term_names(model)) + "] or a CSV file's path, got " +
                       type_name(n->type()));
  std::vector<est::sim::TimedCommand> out;
  double previous = -1.0;
  for (const toml::node& row : *a) {
    const auto* r = row.as_array();
    if (r == nullptr)
      robot.fail(row, "robot.controls: each command is [t_s, " + std::string(est::sim::command_term_names(model)) + "]");
    std::vector<double> v;
    for (const toml::node& c : *r) {
      double x = 0.0;
      if (const auto* i = c.as_integer()) x = static_cast<double>(i->get());
      else if (const auto* f = c.as_floating_point()) x = f->get();
      else robot.fail(c, "robot.controls: expected a number, got " + std::string(type_name(c.type())));
      if (!std::isfinite(x)) robot.fail(c, "robot.controls: must be finite");
      v.push_back(x);
    }
    const CommandIssue issue = check_command(v, model, previous);
    if (!issue.reason.empty())
      robot.fail(issue.field < r->size() ? *r->get(issue.field) : row, issue.reason);
    previous = v[0];
    out.push_back(timed_command(v));
  }
  return out;
}

void read_filter(Section& f, FilterOptions& fo) {
  const std::string type = f.choice("type", "mcl", {"mcl", "ekf"});
  fo.filter = type == "ekf" ? est::loop::Filter::ekf : est::loop::Filter::mcl;
  const std::string start =
      f.choice("start", type == "ekf" ? "tracking" : "global", {"global", "tracking", "wrong"});
  if (type == "ekf" && start != "tracking")
    f.fail_key("start", "filter.start: the EKF tracks from the true start pose: '" + start +
                            "' needs filter.type = 'mcl' (the EKF has no search to leave a wrong belief)");
  parse(start, fo.start);
  const std::string model = f.choice("sensor_model", "likelihood-field", {"likelihood-field", "beam", "steered"});
  node::parse(model, fo.range_model);
  node::parse(f.choice("beam_cast", "table", {"table", "cone"}), fo.beam_cast);
  fo.particles = static_cast<std::uint32_t>(f.integer("particles", fo.particles, 1, 20000));
  fo.kld = f.boolean("kld", fo.kld);
  fo.kld_min = static_cast<std::uint32_t>(f.integer("kld_min", fo.kld_min, 1, 20000));
  fo.beam_stride = f.integer_i("beam_stride", fo.beam_stride, 1, 360);
  fo.omni_noise = f.numbers("omni_noise", 9, kNoise);
  fo.handle_positions = f.integer_i("handle_positions", fo.handle_positions, 0, 16);
  fo.handle_reading_sigma_rad = f.number_f("handle_reading_sigma_rad", fo.handle_reading_sigma_rad, kPositive);
  fo.handle_reading_floor = f.number_f("handle_reading_floor", fo.handle_reading_floor, kPositive);
  fo.unknown_steer_sigma_rad = f.number_f("unknown_steer_sigma_rad", fo.unknown_steer_sigma_rad, kPositive);
  fo.clearance_m = f.number_f("clearance_m", fo.clearance_m, kNonNegative);
  fo.alpha_slow = f.number_f("alpha_slow", fo.alpha_slow, kProbability);
  fo.alpha_fast = f.number_f("alpha_fast", fo.alpha_fast, kProbability);
  fo.max_injection = f.number_f("max_injection", fo.max_injection, kProbability);
  fo.ekf_start_sigma_xy_m = f.number_f("ekf_start_sigma_xy_m", fo.ekf_start_sigma_xy_m, kPositive);
  fo.ekf_start_sigma_theta_rad = f.number_f("ekf_start_sigma_theta_rad", fo.ekf_start_sigma_theta_rad, kPositive);
  fo.ekf_rot_sigma_rad = f.number_f("ekf_rot_sigma_rad", fo.ekf_rot_sigma_rad, kNonNegative);
  fo.ekf_lost_sigma_m = f.number_f("ekf_lost_sigma_m", fo.ekf_lost_sigma_m, kPositive);
  f.done();
}

void read_sensors(Section& sensors, ScenarioConfig& s) {
  Section enc = sensors.table("encoders");
  s.encoder_hz = enc.rate_hz("hz", s.encoder_hz);
  s.encoder_scale_error = enc.number("scale_error", s.encoder_scale_error);
  s.encoder_noise = enc.number("noise", s.encoder_noise, kNonNegative);
  s.slip_events = enc.integer_i("slip_events", s.slip_events, 0, 1000);
  s.slip_duration_s = enc.number("slip_duration_s", s.slip_duration_s, kPositive);
  s.slip_factor = enc.number("slip_factor", s.slip_factor, kNonNegative);
  enc.done();

  Section steer = sensors.table("steering");
  s.steering_sensor = steer.boolean("present", s.steering_sensor);
  s.steering_hz = steer.rate_hz("hz", s.steering_hz);
  s.steering_sigma_deg = steer.number("sigma_deg", s.steering_sigma_deg, kNonNegative);
  s.steering_bias_deg = steer.number("bias_deg", s.steering_bias_deg);
  steer.done();

  Section twist = sensors.table("twist");
  s.twist_hz = twist.rate_hz("hz", s.twist_hz);
  twist.done();
  Section odo = sensors.table("odometry");
  s.odometry_hz = odo.rate_hz("hz", s.odometry_hz);
  odo.done();

  Section rf = sensors.table("rangefinder");
  s.scan_hz = rf.rate_hz("hz", s.scan_hz);
  s.beams = rf.integer_i("beams", s.beams, 1, 360);
  s.fov_deg = rf.number("fov_deg", s.fov_deg, kFov);
  s.range_max_m = rf.number("range_max_m", s.range_max_m, kPositive);
  s.range_noise.sigma = rf.number_f("sigma_m", s.range_noise.sigma, kPositive);
  s.range_noise.p_rand = rf.number_f("p_rand", s.range_noise.p_rand, kProbability);
  s.range_noise.p_short = rf.number_f("p_short", s.range_noise.p_short, kProbability);
  if (s.range_noise.p_rand + s.range_noise.p_short > 1.0f)
    rf.fail_key("p_short", "sensors.rangefinder: p_rand + p_short must be <= 1");
  const std::string mount = rf.choice("mount", "base", {"base", "handlebar"});
  s.handlebar = mount == "handlebar";
  if (s.handlebar && s.robot != RobotKind::bicycle)
    rf.fail_key("mount", "sensors.rangefinder.mount: the handlebar is the bicycle's (robot.model = 'bicycle')");
  s.handlebar_mount.sensor_on_part.x =
      rf.number_f("handlebar_offset_m", s.handlebar_mount.sensor_on_part.x, kNonNegative);
  const std::vector<float> pose = rf.numbers("base_pose", 3, kAny);
  if (!pose.empty()) {
    if (s.handlebar) rf.fail_key("base_pose", "sensors.rangefinder.base_pose: the rangefinder is on the handlebar");
    s.rangefinder_mount = {pose[0], pose[1], pose[2]};
  }
  rf.done();

  Section lm = sensors.table("landmarks");
  s.landmark_hz = lm.rate_hz("hz", s.landmark_hz);
  s.landmark_sensor.noise.sigma_range = lm.number_f("range_sigma_m", s.landmark_sensor.noise.sigma_range, kPositive);
  s.landmark_sensor.noise.sigma_bearing =
      lm.number_f("bearing_sigma_rad", s.landmark_sensor.noise.sigma_bearing, kPositive);
  s.landmark_sensor.noise.sigma_signature =
      lm.number_f("signature_sigma", s.landmark_sensor.noise.sigma_signature, kNonNegative);
  s.landmark_sensor.max_range = lm.number_f("max_range_m", s.landmark_sensor.max_range, kPositive);
  const double fov_deg = lm.number("fov_deg", -1.0, kFov);  // absent: the sensor's own (a full turn), to the bit
  if (fov_deg > 0.0) s.landmark_sensor.fov = static_cast<float>(fov_deg * kPi / 180.0);
  s.landmark_ids_known = lm.choice("ids", "known", {"known", "unknown"}) == "known";
  lm.done();
  sensors.done();
}

void read_faults(Section& f, ScenarioConfig& s, bool ekf) {
  const std::string plan = f.choice("plan", "default", {"default", "none"});
  const bool landmarks = has_landmarks(s);
  s.faults = plan == "default" ? default_fault_counts(s.robot, landmarks, s.steering_sensor) : FaultCounts{};
  if (const toml::node* n = f.get("counts")) {
    const auto* t = n->as_table();
    if (t == nullptr) f.fail(*n, "faults.counts: expected a table of \"stream.class\" = count");
    for (auto&& [k, v] : *t) {
      const std::string key(k.str());
      bool known = false;
      for (const FaultClassInfo& c : fault_catalogue()) known = known || c.key == key;
      if (!known)
        f.fail_at(k.source(), "faults.counts: unknown fault class '" + key + "' (sim_host simulate --help lists them)");
      if (!fault_applies(s.robot, key, s.steering_sensor, landmarks))
        f.fail_at(k.source(), "faults.counts: '" + key + "' does not apply to this robot and world");
      const auto* c = v.as_integer();
      if (c == nullptr || c->get() < 0 || c->get() > 1000)
        f.fail(v, "faults.counts: '" + key + "' must be an integer count in [0, 1000]");
      s.faults[key] = static_cast<int>(c->get());
    }
  }
  // An EKF cannot recover from a kidnapping: none unless asked (as simulate). A robot on a control script has no
  // route to be carried along: none.
  const bool scripted = !s.controls.empty();
  s.kidnap_at_s = f.number("kidnap_at_s", ekf || scripted ? -1.0 : s.kidnap_at_s);
  if (scripted && s.kidnap_at_s >= 0.0)
    f.fail_key("kidnap_at_s", "faults.kidnap_at_s: a kidnapping carries the robot along its route; a robot on "
                              "robot.controls has none (-1)");
  s.burst_at_s = f.number("burst_at_s", s.burst_at_s);
  s.burst_ms = f.number("burst_ms", s.burst_ms, kPositive);
  f.done();
}

void read_team(Section& top, ScenarioFile& out) {
  top.hint(": a team scenario reads description, seed, duration_s and [team]");
  out.runner = ScenarioRunner::team;
  out.scenario.seed = static_cast<std::uint64_t>(top.integer("seed", 1, 0, INT64_MAX));
  out.team_duration_s = top.number("duration_s", -1.0, kDuration);  // absent: the team's own length
  Section t = top.table("team");
  out.team = t.text("scenario", "coop-slam");
  if (!team::is_team_scenario(out.team)) {
    std::string all;
    for (const team::TeamScenarioInfo& i : team::team_scenarios()) all += (all.empty() ? "" : ", ") + i.name;
    t.fail_key("scenario", "team.scenario: '" + out.team + "' is not one of " + all);
  }
  t.done();
}

void read_exercise(Section& top, ScenarioFile& out) {
  top.hint(": an exercise reads description, seed and [exercise]");
  out.runner = ScenarioRunner::exercise;
  out.exercise_seed =
      static_cast<std::uint64_t>(top.integer("seed", static_cast<std::int64_t>(kDefaultMotionSeed), 0, INT64_MAX));
  if (const toml::node* d = top.get("duration_s")) top.fail(*d, "duration_s: an exercise draws samples, it has no duration");
  Section x = top.table("exercise");
  out.exercise = x.choice("name", "bicycle-exercise", {"bicycle-exercise"});
  out.exercise_samples = x.integer_i("samples", out.exercise_samples, 1, 10000000);
  x.done();
}

void read_simulate(Section& top, ScenarioFile& out) {
  ScenarioConfig& s = out.scenario;
  FilterOptions& fo = out.filter;
  s.seed = static_cast<std::uint64_t>(top.integer("seed", static_cast<std::int64_t>(s.seed), 0, INT64_MAX));
  s.duration_s = top.number("duration_s", s.duration_s, kDuration);

  Section world = top.table("world");
  // Paths relative to the file's folder.
  const auto beside = [&](const std::string& p) {
    const std::filesystem::path dir = std::filesystem::path(top.source()).parent_path();
    return p.empty() || std::filesystem::path(p).is_absolute() || dir.empty() ? p : (dir / p).string();
  };
  s.map_yaml = beside(world.path("map"));
  s.landmarks_csv = beside(world.path("landmarks"));
  s.route = read_route(world);
  world.done();

  Section robot = top.table("robot");
  const std::string model =
      robot.choice("model", "bicycle", {"bicycle", "diff-drive", "velocity", "odometry", "omni", "holonomic"});
  parse(model, s.robot);
  s.speed_mps = robot.number("speed_mps", s.speed_mps, kSpeed);
  s.start_segment = static_cast<std::size_t>(robot.integer("start_segment", 0, 0, 10000));
  s.handle_detents = robot.integer_i("handle_detents", s.handle_detents, 0, 64);
  s.omni_noise = robot.numbers("omni_noise", 9, kNoise);
  const std::vector<float> start = robot.numbers("start_pose", 3, kAny);
  if (!start.empty()) s.start_pose = est::Pose2{start[0], start[1], start[2]};
  s.controls = read_controls(robot, s.robot, beside);
  if (!s.controls.empty() && !s.route.empty())
    robot.fail_key("controls", "robot.controls: a robot follows world.route or a control script, not both");
  if (!s.map_yaml.empty() && s.route.empty() && s.controls.empty())
    world.fail_key("map", "world.route is required with world.map (at least two waypoints [x, y]), or robot.controls");
  if (!s.map_yaml.empty() && s.route.empty() && !s.start_pose)
    robot.fail_key("controls", "robot.start_pose is required with a control script in a map (no route to start on)");
  robot.done();

  Section sensors = top.table("sensors");
  read_sensors(sensors, s);

  Section filter = top.table("filter");
  read_filter(filter, fo);
  if (fo.filter == est::loop::Filter::ekf && !has_landmarks(s))
    filter.fail_key("type",
                "filter.type: the EKF needs landmarks, and a map_server map has none (world.landmarks or the office)");

  Section faults = top.table("faults");
  read_faults(faults, s, fo.filter == est::loop::Filter::ekf);

  Section metrics = top.table("metrics");
  fo.converge_pos_m = metrics.number("localized_m", fo.converge_pos_m, kPositive);
  fo.converge_heading_deg = metrics.number("localized_deg", fo.converge_heading_deg, kPositive);
  fo.hold_s = metrics.number("hold_s", fo.hold_s, kNonNegative);
  metrics.done();
}

const char* runner_noun(ScenarioRunner r) {
  switch (r) {
    case ScenarioRunner::simulate: return "a single robot's scenario";
    case ScenarioRunner::team: return "a team scenario";
    case ScenarioRunner::exercise: return "an exercise";
  }
  return "?";
}

ScenarioRunner runner_of(const toml::table& doc) {
  if (doc.contains("team")) return ScenarioRunner::team;
  if (doc.contains("exercise")) return ScenarioRunner::exercise;
  return ScenarioRunner::simulate;
}

// Puts one --set into the document, at its dotted path, as if the file had said it; the value keeps the option as
// its source, so the parser's own checks refuse it by the option's name.
void apply_override(toml::table& doc, const ScenarioOverride& o) {
  const std::string where = std::string(kSetPrefix) + o.key + "=" + o.value;
  const auto refuse = [&](const std::string& reason) { throw ScenarioFileError(where + ": " + reason); };
  const ScenarioRunner runner = runner_of(doc);
  // faults.counts is a table of "stream.class" keys: what follows it is one key, dots and all.
  const std::string counts = "faults.counts.";
  const bool fault_count = o.key.rfind(counts, 0) == 0 && o.key.size() > counts.size();
  if (!fault_count && scenario_file_keys(runner).count(o.key) == 0) {
    if (scenario_file_keys().count(o.key) > 0)
      refuse("'" + o.key + "' is not a key of " + runner_noun(runner));
    refuse("unknown key '" + o.key + "' (sim_host/scenarios/example.toml documents every key)");
  }
  if (fault_count && runner != ScenarioRunner::simulate) refuse("'faults.counts' is not a key of " + std::string(runner_noun(runner)));
  toml::table value;
  try {
    value = toml::parse("v = " + o.value, where);
  } catch (const toml::parse_error&) {
    // A bare word is a string (filter.type=ekf), unless it cannot be one.
    if (o.value.find_first_of("'\r\n") != std::string::npos) refuse("not a TOML value");
    try {
      value = toml::parse("v = '" + o.value + "'", where);
    } catch (const toml::parse_error&) {
      refuse("not a TOML value");
    }
  }
  std::vector<std::string> path;
  if (fault_count) path = {"faults", "counts", o.key.substr(counts.size())};
  else
    for (std::size_t at = 0, dot = 0; dot != std::string::npos; at = dot + 1) {
      dot = o.key.find('.', at);
      path.push_back(o.key.substr(at, dot == std::string::npos ? std::string::npos : dot - at));
    }
  toml::table* t = &doc;
  std::string prefix;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    prefix += (i == 0 ? "" : ".") + path[i];
    toml::node* n = t->get(path[i]);
    if (n == nullptr) n = t->insert(path[i], toml::table{}).first->second.as_table();
    if (n == nullptr || !n->is_table()) refuse("'" + prefix + "' is not a table in the file");
    t = n->as_table();
  }
  toml::node& v = *value.get("v");
  v.visit([&](auto&& x) {
    t->insert_or_assign(toml::key(path.back(), toml::source_region(v.source())), std::move(x));
  });
}

}  // namespace

ScenarioOverride parse_override(const std::string& key_equals_value) {
  const std::size_t eq = key_equals_value.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ScenarioFileError(std::string(kSetPrefix) + key_equals_value + ": expected KEY=VALUE (e.g. filter.particles=256)");
  return {key_equals_value.substr(0, eq), key_equals_value.substr(eq + 1)};
}

ScenarioFile parse_scenario(const std::string& text, const std::string& source,
                            const std::vector<ScenarioOverride>& overrides) {
  toml::table doc;
  try {
    doc = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw ScenarioFileError(located(source, e.source().begin, std::string(e.description())));
  }
  for (const ScenarioOverride& o : overrides) apply_override(doc, o);
  ScenarioFile out;
  out.source = source;
  Section top(out.source, &doc, "", {1, 1});
  out.description = top.text("description", "");
  const bool has_team = doc.contains("team"), has_exercise = doc.contains("exercise");
  if (has_team && has_exercise) top.fail_key("exercise", "a scenario has [team] or [exercise], not both");
  if (has_team) read_team(top, out);
  else if (has_exercise) read_exercise(top, out);
  else read_simulate(top, out);
  top.done();
  return out;
}

ScenarioFile read_scenario_file(const std::string& path, const std::vector<ScenarioOverride>& overrides) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw ScenarioFileError(path + ":1:1: cannot read the file");
  std::ostringstream s;
  s << f.rdbuf();
  return parse_scenario(s.str(), path, overrides);
}

void set_duration(ScenarioFile& f, double duration_s) {
  if (!kDuration.ok(duration_s)) throw ScenarioFileError(std::string("--duration: ") + kDuration.what);
  if (f.runner == ScenarioRunner::exercise)
    throw ScenarioFileError("--duration: an exercise draws samples, it has no duration");
  f.scenario.duration_s = duration_s;
  f.team_duration_s = duration_s;
}

std::set<std::string> scenario_file_keys(ScenarioRunner runner) {
  std::set<std::string> keys;
  g_keys = &keys;
  try {
    parse_scenario(runner == ScenarioRunner::team       ? "[team]\n"
                   : runner == ScenarioRunner::exercise ? "[exercise]\n"
                                                        : "",
                   "keys");
  } catch (...) {
    g_keys = nullptr;
    throw;
  }
  g_keys = nullptr;
  return keys;
}

std::set<std::string> scenario_file_keys() {
  std::set<std::string> keys;
  for (ScenarioRunner r : {ScenarioRunner::simulate, ScenarioRunner::team, ScenarioRunner::exercise})
    keys.merge(scenario_file_keys(r));
  return keys;
}

}  // namespace sim
