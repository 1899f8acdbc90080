// SocketCAN backend against a real kernel CAN stack (vcan0). Needs CAN in the kernel: ctest runs this binary inside
// tests/vm/run-in-vm (this machine's own kernel has none). Covers round trips of every message, kernel receive
// filters, kernel timestamps, error frames (bus-off, error-passive), reconnection, and can-utils interop.
#include <catch2/catch.hpp>
#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "hal/can/can_input.hpp"
#include "hal/can/estimate_frames.hpp"
#include "hal/can/estimator_dbc.hpp"
#include "hal/sensors/odometry/can.hpp"
#include "hal/sensors/range_scan/can_frames.hpp"
#include "hal/sensors/steering/can.hpp"
#include "hal/sensors/twist/can.hpp"
#include "hal/sensors/wheel_ticks/can.hpp"
#include "hal/socketcan/socketcan_bus.hpp"
#include "hal/status_word.hpp"

using namespace hal::can;
using hal::socketcan::monotonic_now_ns;
using hal::socketcan::RxFrame;
using hal::socketcan::SocketCanBus;

namespace {

const char* kIface = "vcan0";

hal::socketcan::Config estimator_config() {
  hal::socketcan::Config c;
  c.interface = kIface;
  c.receive_ids.assign(std::begin(dbc::kInputIds), std::end(dbc::kInputIds));
  c.reconnect_interval_ns = 0;
  return c;
}

hal::socketcan::Config peer_config() {  // the rest of the bus: sensors and a logger, no filter
  hal::socketcan::Config c;
  c.interface = kIface;
  c.reconnect_interval_ns = 0;
  return c;
}

// Waits (poll on the socket, at most timeout_ms in all) until `want` frames arrived or time is up.
std::vector<RxFrame> receive(SocketCanBus& bus, std::size_t want, int timeout_ms = 2000) {
  std::vector<RxFrame> got;
  const hal::TimeNs end = monotonic_now_ns() + timeout_ms * hal::kNsPerMs;
  while (got.size() < want && bus.is_open()) {
    const hal::TimeNs left = end - monotonic_now_ns();
    if (left <= 0) break;
    pollfd p{bus.fd(), POLLIN, 0};
    ::poll(&p, 1, static_cast<int>(left / hal::kNsPerMs) + 1);
    RxFrame buf[64];
    const std::size_t n = bus.receive(buf, 64);
    got.insert(got.end(), buf, buf + n);
  }
  return got;
}

// Gives the kernel a moment to deliver anything still in flight, then returns it (to show nothing came).
std::vector<RxFrame> drain(SocketCanBus& bus) { return receive(bus, 1000, 200); }

bool same(const CanFrame& a, const CanFrame& b) {
  return a.id == b.id && a.dlc == b.dlc && std::memcmp(a.data, b.data, a.dlc) == 0;
}

int sh(const std::string& cmd) {
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string hex(const CanFrame& f) {
  char buf[64];
  std::string s;
  std::snprintf(buf, sizeof buf, "%03X#", f.id);
  s = buf;
  for (int i = 0; i < f.dlc; ++i) {
    std::snprintf(buf, sizeof buf, "%02X", f.data[i]);
    s += buf;
  }
  return s;
}

// One frame of every message of the DBC: the inputs first (kInputs of them), then the outputs.
constexpr std::size_t kInputs = std::size(dbc::kInputIds);
constexpr std::size_t kOutputs = std::size(dbc::kOutputIds);

std::vector<CanFrame> one_of_each() {
  std::vector<CanFrame> f(kInputs + kOutputs);
  REQUIRE(encode(WheelTicksMsg{{65535, 12}, 4, 3}, f[0]) == CodecStatus::ok);
  REQUIRE(encode(WheelTicksExtMsg{{7, 8}, 3}, f[1]) == CodecStatus::ok);
  REQUIRE(encode(SteeringMsg{-0.25f, 4}, f[2]) == CodecStatus::ok);
  REQUIRE(encode(TwistMsg{0.5f, -0.1f, 0.25f, 4}, f[3]) == CodecStatus::ok);
  OdometryMsg odometry;
  odometry.x_mm = 262000;
  odometry.y_mm = 1500;
  odometry.theta = 16384;
  REQUIRE(encode(odometry, f[4]) == CodecStatus::ok);
  REQUIRE(encode(ScanHeaderMsg{2, 30, 0xABCD, 0.1f, 30.0f}, f[5]) == CodecStatus::ok);
  REQUIRE(encode(ScanInfoMsg{2, 0.06f, -2.0f, 0.01f}, f[6]) == CodecStatus::ok);
  REQUIRE(encode(ScanDataMsg{2, 0, {1000, 2000, 0xFFFF}}, f[7]) == CodecStatus::ok);
  REQUIRE(encode(PoseEstimateMsg{1.5f, -2.5f, 0.75f, 5}, f[8]) == CodecStatus::ok);
  REQUIRE(encode(PoseSigmaMsg{0.1f, 0.2f, 0.05f, 5}, f[9]) == CodecStatus::ok);
  REQUIRE(encode(PoseCorrelationMsg{0.1f, -0.2f, 0.3f, 5}, f[10]) == CodecStatus::ok);
  REQUIRE(encode(EstimatorStatusMsg{hal::status::kScanTimeout, 17, 5}, f[11]) == CodecStatus::ok);
  return f;
}

struct Recorder final : hal::PortImplementation<Recorder, hal::SensorPort> {
  std::vector<hal::WheelTicks> wheels;
  std::vector<hal::SteeringSample> steering;
  std::vector<hal::TwistSample> twists;
  std::vector<hal::OdometrySample> odometry;
  std::vector<std::size_t> scans;
  void handle(const hal::WheelTicks& s) { wheels.push_back(s); }
  void handle(const hal::SteeringSample& s) { steering.push_back(s); }
  void handle(const hal::TwistSample& s) { twists.push_back(s); }
  void handle(const hal::OdometrySample& s) { odometry.push_back(s); }
  void handle(const hal::RangeScanView& s) { scans.push_back(s.count); }
  void handle(const hal::LandmarkSightingView&) {}
};

// Writes one raw frame (error frames included) on vcan0 from a socket of its own.
void write_raw(canid_t id, std::initializer_list<std::uint8_t> data) {
  const int fd = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  REQUIRE(fd >= 0);
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, kIface, IFNAMSIZ - 1);
  REQUIRE(::ioctl(fd, SIOCGIFINDEX, &ifr) == 0);
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
  can_frame cf{};
  cf.can_id = id;
  cf.can_dlc = static_cast<std::uint8_t>(data.size());
  std::copy(data.begin(), data.end(), cf.data);
  CHECK(::write(fd, &cf, sizeof cf) == static_cast<ssize_t>(sizeof cf));
  ::close(fd);
}

}  // namespace

TEST_CASE("every message of the DBC round-trips through vcan0 with its bytes intact and a kernel stamp",
          "[socketcan]") {
  SocketCanBus estimator(estimator_config());
  SocketCanBus peer(peer_config());
  REQUIRE(estimator.open());
  REQUIRE(peer.open());
  const std::vector<CanFrame> frames = one_of_each();

  REQUIRE(frames.size() == std::size(dbc::kMessages));
  const hal::TimeNs before = monotonic_now_ns();
  for (const CanFrame& f : frames) REQUIRE(peer.send(f));
  const std::vector<RxFrame> at_estimator = receive(estimator, kInputs);  // the inputs pass its filter
  const hal::TimeNs after = monotonic_now_ns();
  REQUIRE(at_estimator.size() == kInputs);
  for (std::size_t i = 0; i < kInputs; ++i) {
    INFO("frame " << hex(frames[i]));
    CHECK(same(at_estimator[i].frame, frames[i]));
    CHECK(at_estimator[i].kernel_realtime_ns != 0);
    // Kernel stamp mapped to the monotonic clock: between the first send and the end of the read (1 ms slack for
    // the realtime-to-monotonic offset taken once per read).
    CHECK(at_estimator[i].stamp_ns >= before - hal::kNsPerMs);
    CHECK(at_estimator[i].stamp_ns <= after);
  }
  CHECK(drain(estimator).empty());  // the four outputs were filtered out by the kernel

  for (std::size_t i = kInputs; i < frames.size(); ++i) REQUIRE(estimator.send(frames[i]));
  const std::vector<RxFrame> at_peer = receive(peer, kOutputs);
  REQUIRE(at_peer.size() == kOutputs);
  for (std::size_t i = 0; i < kOutputs; ++i) CHECK(same(at_peer[i].frame, frames[kInputs + i]));

  // Decoded on the estimator's side into HAL samples.
  Recorder port;
  ScanReassembler<64> scans;
  CanInput input(scans, port);
  for (const RxFrame& r : at_estimator) input.on_frame(r.frame, r.stamp_ns);
  REQUIRE(port.wheels.size() == 1);  // WHEEL_TICKS and its WHEEL_TICKS_EXT: one four-wheel sample
  CHECK(port.wheels[0].wheel_count == 4);
  CHECK(port.wheels[0].count[0] == 65535);
  CHECK(port.wheels[0].count[3] == 8);
  REQUIRE(port.steering.size() == 1);
  CHECK(port.steering[0].angle_rad == Approx(-0.25).margin(1e-4));
  REQUIRE(port.twists.size() == 1);
  CHECK(port.twists[0].w_rps == Approx(0.25).margin(1e-4));
  REQUIRE(port.odometry.size() == 1);
  CHECK(port.odometry[0].pose.x == Approx(262.0).margin(1e-4));
  CHECK(port.odometry[0].pose.theta == Approx(0.5 * M_PI).margin(1e-4));
  CHECK(input.rejects().total() == 0);
  CHECK(estimator.counters().rx_frames == kInputs);
  CHECK(estimator.counters().tx_frames == kOutputs);
}

TEST_CASE("a whole scan of 1081 beams crosses vcan0 and reassembles", "[socketcan]") {
  SocketCanBus estimator(estimator_config());
  SocketCanBus lidar(peer_config());
  REQUIRE(estimator.open());
  REQUIRE(lidar.open());
  std::vector<float> ranges(1081);
  for (std::size_t i = 0; i < ranges.size(); ++i) ranges[i] = 0.5f + 0.02f * static_cast<float>(i % 500);
  hal::RangeScanView v{0, {-2.35619f, 0.00436332f, 0.06f, 30.0f, 0.025f}, ranges.data(), ranges.size()};
  std::vector<CanFrame> frames(scan_frame_count(ranges.size()));
  REQUIRE(split_scan(v, 7, frames.data(), frames.size()).frames == frames.size());
  Recorder port;
  ScanReassembler<1081> scans;
  CanInput input(scans, port);
  // In bursts the size of the default socket buffers, reading as we go (a sensor paces its frames too).
  std::size_t sent = 0, received = 0;
  while (sent < frames.size()) {
    for (std::size_t k = 0; k < 50 && sent < frames.size(); ++k) REQUIRE(lidar.send(frames[sent++]));
    for (const RxFrame& r : receive(estimator, sent - received)) {
      input.on_frame(r.frame, r.stamp_ns);
      ++received;
    }
  }
  CHECK(received == frames.size());
  REQUIRE(port.scans.size() == 1);
  CHECK(port.scans[0] == 1081);
  CHECK(scans.rejects().total() == 0);
  CHECK(estimator.counters().rx_dropped == 0);
}

TEST_CASE("the kernel receive filter drops ids outside the DBC's inputs; without it the codec counts them",
          "[socketcan]") {
  SocketCanBus estimator(estimator_config());
  SocketCanBus logger(peer_config());
  SocketCanBus peer(peer_config());
  REQUIRE(estimator.open());
  REQUIRE(logger.open());
  REQUIRE(peer.open());
  CanFrame unknown;
  unknown.id = 0x123;
  unknown.dlc = 8;
  CanFrame near_miss = unknown;
  near_miss.id = 0x105;  // one past ODOMETRY
  CanFrame wheels;
  REQUIRE(encode(WheelTicksMsg{{1, 2}, 2, 0}, wheels) == CodecStatus::ok);
  REQUIRE(peer.send(unknown));
  REQUIRE(peer.send(near_miss));
  REQUIRE(peer.send(wheels));
  const std::vector<RxFrame> got = receive(estimator, 1);
  REQUIRE(got.size() == 1);
  CHECK(got[0].frame.id == dbc::kWheelTicksId);
  CHECK(drain(estimator).empty());

  const std::vector<RxFrame> all = receive(logger, 3);
  REQUIRE(all.size() == 3);
  Recorder port;
  ScanReassembler<16> scans;
  CanInput input(scans, port);
  for (const RxFrame& r : all) input.on_frame(r.frame, r.stamp_ns);
  CHECK(input.rejects()[FrameReject::unknown_id] == 2);
  CHECK(port.wheels.size() == 1);
}

TEST_CASE("a frame written with cansend is decoded by the backend", "[socketcan][can-utils]") {
  SocketCanBus estimator(estimator_config());
  REQUIRE(estimator.open());
  CanFrame f;
  REQUIRE(encode(SteeringMsg{0.1234f, 9}, f) == CodecStatus::ok);
  REQUIRE(sh("cansend " + std::string(kIface) + " " + hex(f)) == 0);
  const std::vector<RxFrame> got = receive(estimator, 1);
  REQUIRE(got.size() == 1);
  SteeringMsg m;
  REQUIRE(decode(got[0].frame, m) == CodecStatus::ok);
  CHECK(m.angle_rad == Approx(0.1234).margin(1e-7));
  CHECK(m.counter == 9);
}

TEST_CASE("a frame sent by the backend appears in candump with the expected bytes", "[socketcan][can-utils]") {
  SocketCanBus estimator(estimator_config());
  REQUIRE(estimator.open());
  CanFrame f;
  REQUIRE(encode(PoseEstimateMsg{1.5f, -2.0f, 0.5f, 9}, f) == CodecStatus::ok);

  int out[2];
  REQUIRE(::pipe(out) == 0);
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    ::dup2(out[1], 1);
    ::close(out[0]);
    ::execlp("candump", "candump", "-L", "-n", "1", "vcan0,300:7FF", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::close(out[1]);
  ::fcntl(out[0], F_SETFL, O_NONBLOCK);
  // candump needs a moment to open its socket: send once every 20 ms until it has printed a line (3 s at most).
  std::string line;
  for (int i = 0; i < 150 && line.find('\n') == std::string::npos; ++i) {
    REQUIRE(estimator.send(f));
    pollfd p{out[0], POLLIN, 0};
    if (::poll(&p, 1, 20) > 0) {
      char buf[256];
      const ssize_t n = ::read(out[0], buf, sizeof buf);
      if (n > 0) line.append(buf, static_cast<std::size_t>(n));
    }
  }
  ::kill(pid, SIGTERM);
  ::waitpid(pid, nullptr, 0);
  ::close(out[0]);
  INFO("candump printed: " << line);
  // Log format: "(1700000000.123456) vcan0 300#DC05...".
  CHECK(line.find(" vcan0 " + hex(f)) != std::string::npos);
  CHECK(hex(f) == "300#DC05000CFE8F3891");  // x 1500 mm, y -2000 mm, theta 5000, counter 9 (LE)
}

TEST_CASE("error frames set bus-off and error-passive in the status word; a restart clears them",
          "[socketcan]") {
  SocketCanBus estimator(estimator_config());
  REQUIRE(estimator.open());
  CHECK((estimator.status() & (hal::status::kCanBusOff | hal::status::kCanErrorPassive)) == 0);
  write_raw(CAN_ERR_FLAG | CAN_ERR_CRTL, {0, CAN_ERR_CRTL_TX_PASSIVE, 0, 0, 0, 0, 0, 0});
  write_raw(CAN_ERR_FLAG | CAN_ERR_BUSOFF, {0, 0, 0, 0, 0, 0, 0, 0});
  CHECK(receive(estimator, 1, 300).empty());  // error frames are not data
  CHECK(estimator.counters().error_frames == 2);
  CHECK(estimator.counters().bus_off_events == 1);
  CHECK((estimator.status() & hal::status::kCanBusOff) != 0);
  CHECK((estimator.status() & hal::status::kCanErrorPassive) != 0);
  write_raw(CAN_ERR_FLAG | CAN_ERR_PROT, {0, 0, CAN_ERR_PROT_BIT, 0, 0, 0, 0, 0});
  write_raw(CAN_ERR_FLAG | CAN_ERR_RESTARTED, {0, 0, 0, 0, 0, 0, 0, 0});
  receive(estimator, 1, 300);
  CHECK((estimator.status() & (hal::status::kCanBusOff | hal::status::kCanErrorPassive)) == 0);
  CHECK((estimator.take_status() & hal::status::kCanProtocolError) != 0);
  CHECK((estimator.status() & hal::status::kCanProtocolError) == 0);  // an event: taken once
}

TEST_CASE("the backend reconnects after vcan0 goes down and up, and after it is deleted and re-added",
          "[socketcan][reconnect]") {
  SocketCanBus estimator(estimator_config());
  SocketCanBus peer(peer_config());
  REQUIRE(estimator.open());
  REQUIRE(peer.open());
  CanFrame wheels;
  REQUIRE(encode(WheelTicksMsg{{10, 20}, 2, 0}, wheels) == CodecStatus::ok);

  auto round_trip = [&] {
    REQUIRE(peer.send(wheels));
    const std::vector<RxFrame> got = receive(estimator, 1);
    return got.size() == 1 && same(got[0].frame, wheels);
  };
  REQUIRE(round_trip());

  REQUIRE(sh("ip link set vcan0 down") == 0);
  estimator.service(monotonic_now_ns());
  peer.service(monotonic_now_ns());
  CHECK(!estimator.is_open());
  CHECK((estimator.status() & hal::status::kCanLinkDown) != 0);
  CHECK(estimator.counters().link_lost == 1);
  CHECK(!estimator.send(wheels));  // counted, not thrown away silently
  CHECK(estimator.counters().tx_failed == 1);
  estimator.service(monotonic_now_ns());  // still down: stays closed
  CHECK(!estimator.is_open());

  REQUIRE(sh("ip link set vcan0 up") == 0);
  estimator.service(monotonic_now_ns());
  peer.service(monotonic_now_ns());
  REQUIRE(estimator.is_open());
  CHECK((estimator.status() & hal::status::kCanLinkDown) == 0);
  CHECK(estimator.counters().reconnects == 1);
  CHECK(round_trip());

  REQUIRE(sh("ip link del vcan0 && ip link add dev vcan0 type vcan && ip link set vcan0 up") == 0);
  estimator.service(monotonic_now_ns());  // notices the new interface index
  peer.service(monotonic_now_ns());
  CHECK(estimator.counters().link_lost == 2);
  estimator.service(monotonic_now_ns());
  peer.service(monotonic_now_ns());
  REQUIRE(estimator.is_open());
  REQUIRE(peer.is_open());
  CHECK(estimator.counters().reconnects == 2);
  CHECK(round_trip());
}

TEST_CASE("a missing interface fails to open with a reason and keeps retrying", "[socketcan][reconnect]") {
  hal::socketcan::Config c = estimator_config();
  c.interface = "vcan9";
  c.reconnect_interval_ns = hal::kNsPerS;
  SocketCanBus bus(c);
  CHECK(!bus.open());
  CHECK(bus.last_error().find("vcan9") != std::string::npos);
  CHECK((bus.status() & hal::status::kCanLinkDown) != 0);
  REQUIRE(sh("ip link add dev vcan9 type vcan && ip link set vcan9 up") == 0);
  bus.service(0);  // the first retry is due at once
  CHECK(bus.is_open());
  REQUIRE(sh("ip link del vcan9") == 0);
}
