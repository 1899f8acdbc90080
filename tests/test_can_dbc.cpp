// hal/can/estimator.dbc against the codec's tables, field by field, both ways: a change to either side alone fails.
// The file's own consistency: its version, its nodes, a comment on every message, the cycle time of every periodic
// message, the receive and send id lists. Then frames the codec encodes are decoded with the DBC alone (as cantools
// would) and must give the same values.
#include <catch2/catch.hpp>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "dbc_parser.hpp"
#include "hal/can/estimator_dbc.hpp"

using namespace hal::can;
using est::test::Dbc;
using est::test::DbcMessage;
using est::test::DbcSignal;

namespace {

std::string dbc_path() { return ESTIMATOR_DBC_PATH; }

const std::string& dbc_text() {
  static const std::string text = est::test::read_text_file(dbc_path());
  return text;
}

// Every difference between the DBC and the codec's tables, as readable lines.
std::vector<std::string> mismatches(const Dbc& dbc) {
  std::vector<std::string> out;
  auto differ = [&](const std::string& where, const std::string& what) { out.push_back(where + ": " + what); };
  for (const std::string& e : dbc.errors) differ("DBC", "unparsed line '" + e + "'");
  if (dbc.messages.size() != std::size(dbc::kMessages))
    differ("DBC", "has " + std::to_string(dbc.messages.size()) + " messages, codec " +
                      std::to_string(std::size(dbc::kMessages)));
  for (const MessageSpec& spec : dbc::kMessages) {
    const DbcMessage* m = dbc.message(spec.id);
    const std::string where = spec.name;
    if (m == nullptr) {
      differ(where, "id " + std::to_string(spec.id) + " missing from the DBC");
      continue;
    }
    if (m->name != spec.name) differ(where, "DBC name " + m->name);
    if (m->dlc != spec.dlc) differ(where, "DBC length " + std::to_string(m->dlc));
    if (m->sender != spec.sender) differ(where, "DBC sender " + m->sender);
    if (m->signals.size() != spec.signal_count)
      differ(where, "DBC has " + std::to_string(m->signals.size()) + " signals");
    for (std::size_t i = 0; i < spec.signal_count; ++i) {
      const SignalSpec& s = spec.signals[i];
      const std::string sw = where + "." + s.name;
      const DbcSignal* d = m->signal(s.name);
      if (d == nullptr) {
        differ(sw, "missing from the DBC");
        continue;
      }
      if (d->start_bit != s.start_bit) differ(sw, "start bit " + std::to_string(d->start_bit));
      if (d->length != s.length) differ(sw, "length " + std::to_string(d->length));
      if (d->little_endian != (s.order == ByteOrder::little_endian)) differ(sw, "byte order");
      if (d->is_signed != s.is_signed) differ(sw, "signedness");
      // The board computes in float: the DBC's decimal, rounded to float, must be the table's constant exactly.
      if (static_cast<float>(d->factor) != s.factor) differ(sw, "factor " + std::to_string(d->factor));
      if (static_cast<float>(d->offset) != s.offset) differ(sw, "offset " + std::to_string(d->offset));
      if (static_cast<float>(d->minimum) != s.minimum) differ(sw, "minimum " + std::to_string(d->minimum));
      if (static_cast<float>(d->maximum) != s.maximum) differ(sw, "maximum " + std::to_string(d->maximum));
      if (d->unit != s.unit) differ(sw, "unit '" + d->unit + "'");
    }
  }
  return out;
}

bool is_scan(const MessageSpec& m) {
  return m.id == dbc::kScanHeaderId || m.id == dbc::kScanInfoId || m.id == dbc::kScanDataId;
}
bool is_output(const MessageSpec& m) { return std::string(m.sender) == "ESTIMATOR"; }

// What the file must say besides the tables: its version, its nodes, why each message is there, the period of each
// periodic message, the receiver of each input, and the comments a reader of the new messages needs.
std::vector<std::string> consistency_problems(const Dbc& dbc) {
  std::vector<std::string> out;
  auto problem = [&](const std::string& where, const std::string& what) { out.push_back(where + ": " + what); };
  for (const std::string& e : dbc.errors) problem("DBC", "unparsed or dangling line '" + e + "'");
  if (dbc.version != "estimator 2") problem("VERSION", "'" + dbc.version + "', expected 'estimator 2'");
  if (dbc.comment.empty()) problem("DBC", "no comment on the network");
  const std::set<std::string> nodes(dbc.nodes.begin(), dbc.nodes.end());
  std::set<std::string> senders;
  for (const DbcMessage& m : dbc.messages) {
    senders.insert(m.sender);
    if (nodes.count(m.sender) == 0) problem(m.name, "sender " + m.sender + " is not a node of BU_");
    if (m.comment.empty()) problem(m.name, "no CM_ BO_ comment");
  }
  for (const std::string& n : dbc.nodes)
    if (senders.count(n) == 0) problem("BU_", "node " + n + " sends nothing");
  for (const MessageSpec& spec : dbc::kMessages) {
    const DbcMessage* m = dbc.message(spec.id);
    if (m == nullptr) continue;  // mismatches() says so
    const auto cycle = m->attributes.find("GenMsgCycleTime");
    if (is_scan(spec)) {
      if (cycle != m->attributes.end()) problem(spec.name, "scan frames are event-driven: no GenMsgCycleTime");
    } else if (cycle == m->attributes.end() || std::stoi(cycle->second) <= 0) {
      problem(spec.name, "periodic: needs a GenMsgCycleTime");
    }
    for (const DbcSignal& s : m->signals) {
      const bool to_estimator = s.receivers.size() == 1 && s.receivers[0] == "ESTIMATOR";
      if (!is_output(spec) && !to_estimator) problem(std::string(spec.name) + "." + s.name, "receiver is not ESTIMATOR");
    }
  }
  // The signals whose meaning the layout alone does not tell.
  const std::pair<std::uint32_t, const char*> explained[] = {
      {dbc::kWheelTicksId, "WheelCount"}, {dbc::kWheelTicksExtId, "Counter"}, {dbc::kTwistId, "V1"},
      {dbc::kTwistId, "V2"},              {dbc::kTwistId, "W"},                {dbc::kOdometryId, "X"},
      {dbc::kOdometryId, "Y"},            {dbc::kOdometryId, "Theta"}};
  for (const auto& [id, name] : explained) {
    const DbcMessage* m = dbc.message(id);
    const DbcSignal* s = m != nullptr ? m->signal(name) : nullptr;
    if (s == nullptr || s->comment.empty()) problem(std::to_string(id) + "." + name, "no CM_ SG_ comment");
  }
  return out;
}

std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// A signal of a frame decoded with the DBC alone (its message found by id, its length checked).
double dbc_value(const Dbc& dbc, const CanFrame& f, const char* signal) {
  const DbcMessage* m = dbc.message(f.id);
  REQUIRE(m != nullptr);
  REQUIRE(f.dlc == m->dlc);
  const DbcSignal* s = m->signal(signal);
  REQUIRE(s != nullptr);
  return est::test::dbc_decode(*s, f.data);
}

}  // namespace

TEST_CASE("the DBC file parses and every message and signal matches the codec's tables", "[can][dbc]") {
  REQUIRE(!dbc_text().empty());
  const Dbc dbc = est::test::parse_dbc(dbc_text());
  REQUIRE(dbc.messages.size() == std::size(dbc::kMessages));
  CHECK(dbc.messages.size() == 12u);
  const std::vector<std::string> diff = mismatches(dbc);
  for (const std::string& d : diff) UNSCOPED_INFO(d);
  CHECK(diff.empty());
}

TEST_CASE("signals stay inside their frame and never overlap", "[can][dbc]") {
  const Dbc dbc = est::test::parse_dbc(dbc_text());
  for (const DbcMessage& m : dbc.messages) {
    std::set<unsigned> used;
    for (const DbcSignal& s : m.signals) {
      for (unsigned bit : est::test::dbc_signal_bits(s)) {
        INFO(m.name << "." << s.name << " bit " << bit);
        CHECK(bit < 8 * m.dlc);
        CHECK(used.insert(bit).second);
      }
    }
  }
}

TEST_CASE("a change on one side only is caught: id, length, start bit, byte order, sign, factor, unit",
          "[can][dbc]") {
  const std::string& t = dbc_text();
  const std::vector<std::pair<std::string, std::string>> edits = {
      {"BO_ 256 WHEEL_TICKS: 8", "BO_ 260 WHEEL_TICKS: 8"},
      {"BO_ 257 STEERING: 8", "BO_ 257 STEERING: 7"},
      {"SG_ Seq : 4|12@1+", "SG_ Seq : 4|11@1+"},
      {"SG_ RangeMax : 48|16@1+", "SG_ RangeMax : 47|16@1+"},
      {"SG_ SteeringAngle : 7|16@0-", "SG_ SteeringAngle : 7|16@1-"},
      {"SG_ X : 0|22@1-", "SG_ X : 0|22@1+"},
      {"SG_ SigmaTheta : 32|16@1+ (0.0001,0)", "SG_ SigmaTheta : 32|16@1+ (0.001,0)"},
      {"SG_ AngleIncrement : 32|32@1- (1e-09,0)", "SG_ AngleIncrement : 32|32@1- (1e-09,0.1)"},
      {"[0|65.535] \"m\" Vector__XXX", "[0|65.535] \"mm\" Vector__XXX"},
      {"SG_ CorrXY : 0|16@1- (0.0001,0) [-1|1]", "SG_ CorrXY : 0|16@1- (0.0001,0) [-1|2]"},
      {" SG_ Counter : 48|4@1+ (1,0) [0|15] \"\" Vector__XXX\n\n", "\n"},  // a signal removed
      {"SG_ WheelCount : 32|3@1+", "SG_ WheelCount : 32|2@1+"},
      {"BO_ 258 WHEEL_TICKS_EXT: 8 WHEEL_ENCODERS", "BO_ 258 WHEEL_TICKS_EXT: 8 BASE_CONTROLLER"},
      {"SG_ Ticks3 : 16|16@1+", "SG_ Ticks3 : 32|16@1+"},
      {"SG_ W : 32|16@1- (0.001,0) [-32.768|32.767] \"rad/s\"", "SG_ W : 32|16@1- (0.001,0) [-32.768|32.767] \"deg/s\""},
      {"SG_ V2 : 16|16@1- (0.001,0)", "SG_ V2 : 16|16@1- (0.01,0)"},
      {"SG_ Theta : 36|16@1+ (1,0) [0|65535]", "SG_ Theta : 36|16@1- (1,0) [0|65535]"},
      {"SG_ Y : 18|18@1+ (1,0) [0|262143]", "SG_ Y : 18|18@1+ (1,0) [0|131071]"},
      {"BO_ 260 ODOMETRY: 8", "BO_ 261 ODOMETRY: 8"},
  };
  for (const auto& [from, to] : edits) {
    INFO("edit: " << from << " -> " << to);
    CHECK(!mismatches(est::test::parse_dbc(replace_once(t, from, to))).empty());
  }
}

TEST_CASE("frames from the codec decode with the DBC alone to the values encoded", "[can][dbc]") {
  const Dbc dbc = est::test::parse_dbc(dbc_text());
  auto value = [&](const CanFrame& f, const char* signal) { return dbc_value(dbc, f, signal); };
  CanFrame f;
  REQUIRE(encode(WheelTicksMsg{{65535, 7}, 2, 9}, f) == CodecStatus::ok);
  CHECK(value(f, "Ticks0") == 65535);
  CHECK(value(f, "Ticks1") == 7);
  CHECK(value(f, "WheelCount") == 2);
  CHECK(value(f, "Counter") == 9);
  REQUIRE(encode(SteeringMsg{-0.5432f, 2}, f) == CodecStatus::ok);
  CHECK(value(f, "SteeringAngle") == Approx(-0.5432).margin(1e-7));
  CHECK(value(f, "Counter") == 2);
  REQUIRE(encode(ScanHeaderMsg{9, 1081, 0x1234, 0.025f, 30.0f}, f) == CodecStatus::ok);
  CHECK(value(f, "ScanId") == 9);
  CHECK(value(f, "RangeCount") == 1081);
  CHECK(value(f, "ScanCrc") == 0x1234);
  CHECK(value(f, "ScanTime") == Approx(0.025).margin(1e-9));
  CHECK(value(f, "RangeMax") == Approx(30.0).margin(1e-9));
  REQUIRE(encode(ScanInfoMsg{9, 0.06f, -2.35619f, 0.00436332f}, f) == CodecStatus::ok);
  CHECK(value(f, "RangeMin") == Approx(0.06).margin(1e-9));
  CHECK(value(f, "AngleMin") == Approx(-2.3562).margin(1e-9));
  CHECK(value(f, "AngleIncrement") == Approx(0.00436332).margin(1e-9));
  REQUIRE(encode(ScanDataMsg{9, 360, {1234, 0, 65535}}, f) == CodecStatus::ok);
  CHECK(value(f, "Seq") == 360);
  CHECK(value(f, "Range0") == Approx(1.234).margin(1e-9));
  CHECK(value(f, "Range2") == Approx(65.535).margin(1e-9));
  REQUIRE(encode(PoseEstimateMsg{-1234.567f, 2000.001f, -3.14159f, 11}, f) == CodecStatus::ok);
  CHECK(value(f, "X") == Approx(-1234.567).margin(1e-9));
  CHECK(value(f, "Y") == Approx(2000.001).margin(1e-9));
  CHECK(value(f, "Theta") == Approx(-3.1416).margin(1e-9));
  CHECK(value(f, "Counter") == 11);
  REQUIRE(encode(PoseSigmaMsg{0.05f, 1.5f, 0.02f, 11}, f) == CodecStatus::ok);
  CHECK(value(f, "SigmaY") == Approx(1.5).margin(1e-9));
  CHECK(value(f, "SigmaTheta") == Approx(0.02).margin(1e-9));
  REQUIRE(encode(PoseCorrelationMsg{-0.25f, 0.0f, 0.9999f, 11}, f) == CodecStatus::ok);
  CHECK(value(f, "CorrXY") == Approx(-0.25).margin(1e-9));
  CHECK(value(f, "CorrYTheta") == Approx(0.9999).margin(1e-9));
  REQUIRE(encode(EstimatorStatusMsg{0x80010003u, 42, 11}, f) == CodecStatus::ok);
  CHECK(value(f, "StatusWord") == 0x80010003u);
  CHECK(value(f, "RejectedInputs") == 42);
}

TEST_CASE("the DBC is version 2, every node sends, every message is explained and every periodic one has a cycle time",
          "[can][dbc]") {
  const Dbc dbc = est::test::parse_dbc(dbc_text());
  const std::vector<std::string> problems = consistency_problems(dbc);
  for (const std::string& p : problems) UNSCOPED_INFO(p);
  CHECK(problems.empty());
  CHECK(dbc.nodes == std::vector<std::string>{"WHEEL_ENCODERS", "STEERING_SENSOR", "BASE_CONTROLLER", "RANGEFINDER",
                                              "ESTIMATOR"});
  // The comments say what a receiver must do with the new messages.
  const DbcMessage* ext = dbc.message(dbc::kWheelTicksExtId);
  REQUIRE(ext != nullptr);
  CHECK(ext->comment.find("Counter") != std::string::npos);     // paired by the alive counter
  CHECK(ext->comment.find("incomplete") != std::string::npos);  // and what happens when the pair breaks
  const DbcMessage* odometry = dbc.message(dbc::kOdometryId);
  REQUIRE(odometry != nullptr);
  CHECK(odometry->comment.find("wrapping") != std::string::npos);
  CHECK(odometry->signal("X")->comment.find("2^18") != std::string::npos);
  const DbcMessage* twist = dbc.message(dbc::kTwistId);
  REQUIRE(twist != nullptr);
  CHECK(twist->comment.find("mm/s") != std::string::npos);
  CHECK(twist->comment.find("mrad/s") != std::string::npos);
  CHECK(dbc.comment.find("GenMsgCycleTime") != std::string::npos);
  // The value tables name signals that exist (the parser reports a dangling VAL_ as an error).
  CHECK(dbc.value_tables.size() == 3u);
}

TEST_CASE("the DBC's inputs and outputs are the codec's receive filter and send list", "[can][dbc]") {
  const Dbc dbc = est::test::parse_dbc(dbc_text());
  std::set<std::uint32_t> inputs, outputs;
  for (const DbcMessage& m : dbc.messages) (m.sender == "ESTIMATOR" ? outputs : inputs).insert(m.id);
  CHECK(inputs == std::set<std::uint32_t>(std::begin(dbc::kInputIds), std::end(dbc::kInputIds)));
  CHECK(outputs == std::set<std::uint32_t>(std::begin(dbc::kOutputIds), std::end(dbc::kOutputIds)));
  for (const MessageSpec& m : dbc::kMessages) CHECK(find_message(m.id) == &m);
  CHECK(find_message(0x7FF) == nullptr);
}

TEST_CASE("a DBC missing a comment, a cycle time, a node or its version is caught", "[can][dbc]") {
  const std::string& t = dbc_text();
  REQUIRE(consistency_problems(est::test::parse_dbc(t)).empty());
  const std::vector<std::pair<std::string, std::string>> edits = {
      {"VERSION \"estimator 2\"", "VERSION \"estimator 1\""},
      {"BA_ \"GenMsgCycleTime\" BO_ 259 10;\n", ""},
      {"BU_: WHEEL_ENCODERS STEERING_SENSOR BASE_CONTROLLER", "BU_: WHEEL_ENCODERS STEERING_SENSOR"},
      {"CM_ SG_ 256 WheelCount", "CM_ SG_ 256 TicksLeft"},  // a comment left on a renamed signal
      {"CM_ BO_ 260 ", "CM_ BO_ 261 "},
      {"BU_: WHEEL_ENCODERS", "BU_: WHEEL_ENCODERS IMU"},  // a node that sends nothing
      {"SG_ V1 : 0|16@1- (0.001,0) [-32.768|32.767] \"m/s\" ESTIMATOR", "SG_ V1 : 0|16@1- (0.001,0) [-32.768|32.767] \"m/s\" Vector__XXX"},
      {"VAL_ 274 Range2", "VAL_ 274 Range3"},
  };
  for (const auto& [from, to] : edits) {
    INFO("edit: " << from << " -> " << to);
    CHECK(!consistency_problems(est::test::parse_dbc(replace_once(t, from, to))).empty());
  }
}

TEST_CASE("WHEEL_TICKS(+EXT), TWIST and ODOMETRY frames decode with the DBC alone to the values encoded", "[can][dbc]") {
  const Dbc dbc = est::test::parse_dbc(dbc_text());
  auto value = [&](const CanFrame& f, const char* signal) { return dbc_value(dbc, f, signal); };
  hal::WheelTicks four;
  four.stamp_ns = 5;
  four.wheel_count = 4;
  four.count[0] = 1;
  four.count[1] = 65535;
  four.count[2] = 4660;
  four.count[3] = 43981;
  CanFrame pair[2];
  REQUIRE(encode_wheel_ticks(four, 6, pair) == 2u);
  CHECK(value(pair[0], "Ticks0") == 1);
  CHECK(value(pair[0], "Ticks1") == 65535);
  CHECK(value(pair[0], "WheelCount") == 4);
  CHECK(value(pair[0], "Counter") == 6);
  CHECK(value(pair[1], "Ticks2") == 4660);
  CHECK(value(pair[1], "Ticks3") == 43981);
  CHECK(value(pair[1], "Counter") == 6);  // the pair shares the alive counter
  CanFrame f;
  REQUIRE(encode(TwistMsg{-1.234f, 0.5f, 2.345f, 13}, f) == CodecStatus::ok);
  CHECK(value(f, "V1") == Approx(-1.234).margin(1e-9));
  CHECK(value(f, "V2") == Approx(0.5).margin(1e-9));
  CHECK(value(f, "W") == Approx(2.345).margin(1e-9));
  CHECK(value(f, "Counter") == 13);
  OdometryMsg o;
  o.x_mm = 262143;
  o.y_mm = 70000;
  o.theta = 49152;  // three quarters of a turn
  o.counter = 15;
  REQUIRE(encode(o, f) == CodecStatus::ok);
  CHECK(value(f, "X") == 262143);
  CHECK(value(f, "Y") == 70000);
  CHECK(value(f, "Theta") == 49152);
  CHECK(value(f, "Counter") == 15);
}
