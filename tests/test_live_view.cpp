// The live view's pieces in process (sim_host/view/): the Foxglove messages (the 2-sigma ellipse, the status bits,
// the map's cells through base64) and the server (the page over HTTP on a port of its own, one clear line when the
// port is taken, a producer that never waits). The protocol end to end is tests/view/ (real clients).
#include <arpa/inet.h>
#include <catch2/catch.hpp>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <thread>
#include <vector>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "hal/status_word.hpp"
#include "view/foxglove_json.hpp"
#include "view/live_view.hpp"

namespace {

// GET `path` from 127.0.0.1:port, the whole answer (headers and body).
std::string http_get(std::uint16_t port, const std::string& path) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::string answer;
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0) {
    const std::string request = "GET " + path + " HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n";
    if (::send(fd, request.data(), request.size(), 0) == static_cast<ssize_t>(request.size())) {
      char buf[4096];
      ssize_t n = 0;
      while ((n = ::recv(fd, buf, sizeof buf, 0)) > 0) answer.append(buf, static_cast<std::size_t>(n));
    }
  }
  ::close(fd);
  return answer;
}

// A WebSocket client that subscribes to `channel` and then reads nothing (its receive buffer kept small): the
// server's sends pile up behind it.
int stalled_subscriber(std::uint16_t port, std::uint32_t channel) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  const int small = 4096;
  ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) return -1;
  const std::string upgrade =
      "GET / HTTP/1.1\r\nHost: localhost\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
      "Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n\r\n";
  ::send(fd, upgrade.data(), upgrade.size(), 0);
  char buf[512];
  if (::recv(fd, buf, sizeof buf, 0) <= 0) return -1;  // 101 Switching Protocols (and maybe more)
  const std::string sub = R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":)" + std::to_string(channel) + "}]}";
  std::string frame = {'\x81', static_cast<char>(0x80 | sub.size())};  // text, masked, length < 126
  const char mask[4] = {1, 2, 3, 4};
  frame.append(mask, 4);
  for (std::size_t i = 0; i < sub.size(); ++i) frame += static_cast<char>(sub[i] ^ mask[i % 4]);
  ::send(fd, frame.data(), frame.size(), 0);
  return fd;
}

std::string base64_decode(const std::string& s) {
  const std::string k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned v = 0;
  int bits = 0;
  for (char c : s) {
    if (c == '=') break;
    v = (v << 6) | static_cast<unsigned>(k.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((v >> bits) & 0xffu);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("the 2-sigma ellipse has the covariance's principal axes, rotated with it", "[view]") {
  view::EstimateSample e;
  e.pose = {3.0, 4.0, 0.0};
  // Variances 0.04 and 0.01 m^2 (sigmas 0.2 and 0.1 m) along axes rotated by 30 degrees.
  const double phi = M_PI / 6.0, c = std::cos(phi), s = std::sin(phi), l1 = 0.04, l2 = 0.01;
  e.covariance[0] = l1 * c * c + l2 * s * s;
  e.covariance[1] = e.covariance[3] = (l1 - l2) * c * s;
  e.covariance[4] = l1 * s * s + l2 * c * c;
  const std::vector<double> xy = view::ellipse_points(e, 36);
  REQUIRE(xy.size() == 72u);
  // Point 0 is the end of the major axis (2 sigma = 0.4 m along phi), point 9 of the minor (0.2 m).
  CHECK(xy[0] == Approx(3.0 + 0.4 * c).margin(1e-9));
  CHECK(xy[1] == Approx(4.0 + 0.4 * s).margin(1e-9));
  CHECK(std::hypot(xy[18] - 3.0, xy[19] - 4.0) == Approx(0.2).margin(1e-9));
  // A degenerate (non-finite, negative) covariance gives a point, not NaN.
  e.covariance[0] = std::nan("");
  e.covariance[4] = -1.0;
  for (double v : view::ellipse_points(e, 8)) CHECK(std::isfinite(v));
}

TEST_CASE("the status word is named bit by bit, unknown bits by number", "[view]") {
  CHECK(view::status_bit_names(0u).empty());
  const std::vector<std::string> names =
      view::status_bit_names(hal::status::kNotInitialized | hal::status::kScanTimeout | hal::status::kLcmDecodeError |
                             (1u << 30));
  CHECK(names == std::vector<std::string>{"scan_timeout", "not_initialized", "lcm_decode_error", "bit_30"});
  const nlohmann::json j = nlohmann::json::parse(view::status_json(view::EstimateSample{}, 7));
  CHECK(j.at("word_hex") == "0x00000000");
  CHECK(j.at("view_dropped") == 7);
  CHECK(j.at("covariance").size() == 9u);
}

TEST_CASE("the map travels as a foxglove.Grid whose base64 cells are the grid's, bottom row first", "[view]") {
  view::MapGrid m;
  m.width = 3;
  m.height = 2;
  m.resolution_m = 0.05;
  m.origin_x = -1.0;
  m.origin_y = 2.0;
  m.cells = {0, 100, 255, 50, 0, 7};
  const nlohmann::json j = nlohmann::json::parse(view::map_json(m));
  CHECK(j.at("column_count") == 3);
  CHECK(j.at("row_stride") == 3);
  CHECK(j.at("cell_size").at("x") == 0.05);
  CHECK(j.at("pose").at("position").at("x") == -1.0);
  CHECK(j.at("fields").at(0).at("type") == 1);  // UINT8
  const std::string cells = base64_decode(j.at("data").get<std::string>());
  CHECK(std::vector<std::uint8_t>(cells.begin(), cells.end()) == m.cells);
  // Every channel is advertised as JSON with a JSON schema titled with its schema name.
  const nlohmann::json ad = nlohmann::json::parse(view::advertise_json());
  REQUIRE(ad.at("channels").size() == 6u);
  for (const nlohmann::json& ch : ad.at("channels")) {
    CHECK(ch.at("encoding") == "json");
    CHECK(ch.at("schemaEncoding") == "jsonschema");
    CHECK(nlohmann::json::parse(ch.at("schema").get<std::string>()).at("title") == ch.at("schemaName"));
  }
}

TEST_CASE("the server gives its page over HTTP, 404 elsewhere, and says in one line when its port is taken",
          "[view]") {
  view::LiveView v(0, "test");  // 0: a port of the system's choosing
  REQUIRE(v.port() != 0);
  const std::string page = http_get(v.port(), "/");
  CHECK(page.rfind("HTTP/1.1 200", 0) == 0);
  CHECK(page.find("<canvas") != std::string::npos);
  CHECK(page.find("foxglove.websocket.v1") != std::string::npos);
  CHECK(http_get(v.port(), "/nothing").rfind("HTTP/1.1 404", 0) == 0);
  CHECK(v.counters().pages == 1u);
  try {
    view::LiveView second(v.port(), "test");
    FAIL("a second server on the same port");
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    CHECK(what.rfind("view: cannot listen on 127.0.0.1:" + std::to_string(v.port()) + ": ", 0) == 0);
    CHECK(what.find('\n') == std::string::npos);
  }
}

TEST_CASE("the producer never waits: a burst beyond the hand-off is dropped and counted", "[view]") {
  view::LiveView v(0, "test");
  view::EstimateSample e;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 20000; ++i) {
    e.stamp_ns = i;
    v.publish_estimate(e);
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(s < 0.5);  // 20000 hand-offs of ~100 bytes: microseconds each at most, never a wait for the server
  v.stop();
  const view::ViewCounters c = v.counters();
  CHECK(c.dropped_handoff > 0u);  // the ring holds 4096, drained every 20 ms
  CHECK(c.dropped_handoff < 20000u);
  CHECK_FALSE(v.particles_due());  // nobody subscribed: no cloud is copied
}

TEST_CASE("a client that stops reading is skipped and counted, the others and the producer go on", "[view]") {
  view::LiveView v(0, "test");
  const int fd = stalled_subscriber(v.port(), static_cast<std::uint32_t>(view::Channel::particles));
  REQUIRE(fd >= 0);
  for (int i = 0; i < 100 && v.subscribers() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  REQUIRE(v.subscribers() == 1u);
  // 2000-particle clouds (~150 kB of JSON each) every 5 ms until the server skips the client: a socket that is never
  // read holds a few MB, reached in ~2 s here (the server sends the newest cloud it has; under the sanitizers it
  // makes fewer a second, so the bound is 30 s, not a count of clouds).
  std::vector<float> x(2000, 1.0f), y(2000, 2.0f), theta(2000, 0.5f);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  for (int i = 0; v.counters().dropped_slow == 0u && std::chrono::steady_clock::now() < deadline; ++i) {
    v.publish_particles(i, x.data(), y.data(), theta.data(), 2000);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const view::ViewCounters c = v.counters();
  CHECK(c.dropped_slow > 0u);
  CHECK(c.messages_sent > 0u);
  v.stop();  // returns although the client never answers the close handshake
  ::close(fd);
}
