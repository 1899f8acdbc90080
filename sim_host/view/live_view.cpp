// The live view's server (view/live_view.hpp): websocketpp on standalone asio, one thread that accepts, answers the
// page's HTTP request and the clients' subscriptions, and every 20 ms drains the hand-off to the subscribers.
#define ASIO_STANDALONE
#include "view/live_view.hpp"

#include <algorithm>
#include <cstring>
#include <future>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

#include "view_page.hpp"  // kPage: view/page/index.html, generated at build time

namespace view {

namespace {

using Server = websocketpp::server<websocketpp::config::asio>;
using Hdl = websocketpp::connection_hdl;

constexpr std::size_t kRingSize = 4096;  // estimates and truths in flight (40 s of a 100 Hz loop's outputs)
constexpr auto kDrainPeriod = std::chrono::milliseconds(20);

struct Item {
  enum class Kind : std::uint8_t { estimate, truth } kind = Kind::estimate;
  std::int32_t robot = -1;  // a team's robot, or -1 (one robot's view)
  bool with_status = true;
  EstimateSample e;
};

// Single producer (the estimator's thread), single consumer (the server's): never blocks, drops when full.
class ItemRing {
 public:
  ItemRing() : slots_(new Item[kRingSize]) {}
  bool push(const Item& item) {
    const std::size_t h = head_.load(std::memory_order_relaxed);
    if (h - tail_.load(std::memory_order_acquire) == kRingSize) return false;
    slots_[h % kRingSize] = item;
    head_.store(h + 1, std::memory_order_release);
    return true;
  }
  bool pop(Item& out) {
    const std::size_t t = tail_.load(std::memory_order_relaxed);
    if (t == head_.load(std::memory_order_acquire)) return false;
    out = slots_[t % kRingSize];
    tail_.store(t + 1, std::memory_order_release);
    return true;
  }

 private:
  std::unique_ptr<Item[]> slots_;
  std::atomic<std::size_t> head_{0}, tail_{0};
};

// Triple buffer: the producer fills its back buffer and swaps it into the middle; the consumer takes the middle
// when it is fresh. A fresh middle swapped out unread is a cloud dropped.
template <typename T>
class TripleBuffer {
 public:
  explicit TripleBuffer(void (*reserve)(T&)) {
    for (T& c : clouds_) reserve(c);
  }
  T& back() { return clouds_[back_]; }
  bool publish() {  // false: an unread cloud was overwritten
    const int old = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel);
    back_ = old & 3;
    return (old & kFresh) == 0;
  }
  const T* take() {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return nullptr;
    front_ = middle_.exchange(front_, std::memory_order_acq_rel) & 3;
    return &clouds_[front_];
  }

 private:
  static constexpr int kFresh = 4;
  T clouds_[3];
  int back_ = 0, front_ = 1;
  std::atomic<int> middle_{2};
};

void put_le(std::string& s, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) s += static_cast<char>((v >> (8 * i)) & 0xffu);
}

}  // namespace

void reserve_cloud(ParticleCloud& c) {
  c.xs.reserve(kMaxCloudPoses);
  c.ys.reserve(kMaxCloudPoses);
  c.thetas.reserve(kMaxCloudPoses);
}
void reserve_landmarks(LandmarkSet& l) { l.landmarks.reserve(kMaxViewLandmarks); }

struct LiveView::Impl {
  Impl(std::uint16_t port_wanted, const std::string& server_name, int team_robots)
      : name(server_name), team(team_robots), ids(advertised_ids(team_robots)) {
    server.clear_access_channels(websocketpp::log::alevel::all);
    server.clear_error_channels(websocketpp::log::elevel::all);
    server.init_asio(&ios);
    server.set_reuse_addr(true);
    server.set_close_handshake_timeout(1000);
    server.set_validate_handler([this](Hdl h) { return validate(h); });
    server.set_http_handler([this](Hdl h) { serve_page(h); });
    server.set_open_handler([this](Hdl h) { open(h); });
    server.set_close_handler([this](Hdl h) { close(h); });
    server.set_fail_handler([this](Hdl h) { close(h); });
    server.set_message_handler([this](Hdl h, Server::message_ptr m) { on_message(h, m); });
    std::error_code ec;
    server.listen(asio::ip::tcp::endpoint(asio::ip::address_v4::loopback(), port_wanted), ec);
    if (!ec) server.start_accept(ec);
    if (ec)
      throw std::runtime_error("view: cannot listen on 127.0.0.1:" + std::to_string(port_wanted) + ": " +
                               ec.message());
    const asio::ip::tcp::endpoint local = server.get_local_endpoint(ec);
    port = ec ? port_wanted : local.port();
    schedule_drain();
    thread = std::thread([this] {
      ios.run();
      done.set_value();
    });
  }

  ~Impl() { stop(); }

  void stop() {
    if (!thread.joinable()) return;
    ios.post([this] {
      drain();
      timer.cancel();
      std::error_code ec;
      server.stop_listening(ec);
      for (auto& [hdl, client] : clients) server.close(hdl, websocketpp::close::status::going_away, "done", ec);
    });
    // A client that never answers the close handshake must not hold the program: give up after 3 s.
    if (done.get_future().wait_for(std::chrono::seconds(3)) != std::future_status::ready) ios.stop();
    thread.join();
  }

  // --- server thread -------------------------------------------------------------------------------------------

  struct Client {
    std::map<std::uint32_t, std::uint32_t> subscriptions;  // subscription id -> channel id
  };

  bool validate(Hdl h) {
    std::error_code ec;
    Server::connection_ptr con = server.get_con_from_hdl(h, ec);
    if (ec) return false;
    for (const std::string& p : con->get_requested_subprotocols())
      if (p == kSubprotocol) {
        con->select_subprotocol(kSubprotocol, ec);
        return !ec;
      }
    return false;
  }

  void serve_page(Hdl h) {
    std::error_code ec;
    Server::connection_ptr con = server.get_con_from_hdl(h, ec);
    if (ec) return;
    const std::string resource = con->get_resource();
    if (resource == "/" || resource == "/index.html") {
      con->set_status(websocketpp::http::status_code::ok);
      con->append_header("Content-Type", "text/html; charset=utf-8");
      con->append_header("Cache-Control", "no-store");
      con->set_body(kPage);
      pages.fetch_add(1, std::memory_order_relaxed);
    } else {
      con->set_status(websocketpp::http::status_code::not_found);
      con->append_header("Content-Type", "text/plain");
      con->set_body("not found: the view is at /\n");
    }
  }

  void open(Hdl h) {
    clients[h];
    client_count.fetch_add(1, std::memory_order_relaxed);
    send_text(h, server_info_json(name));
    send_text(h, advertise_json(team));
  }

  void close(Hdl h) {
    clients.erase(h);
    count_subscribed();
  }

  void on_message(Hdl h, const Server::message_ptr& m) {
    const auto it = clients.find(h);
    if (it == clients.end() || m->get_opcode() != websocketpp::frame::opcode::text) return;
    const nlohmann::json j = nlohmann::json::parse(m->get_payload(), nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("op")) {
      send_text(h, status_json(2, "not a JSON object with an op"));
      return;
    }
    const std::string op = j.value("op", "");
    if (op == "subscribe" && j.contains("subscriptions") && j["subscriptions"].is_array()) {
      for (const nlohmann::json& s : j["subscriptions"]) {
        const std::uint32_t id = s.value("id", 0u), channel = s.value("channelId", 0u);
        if (std::find(ids.begin(), ids.end(), channel) == ids.end()) {
          send_text(h, status_json(1, "no channel " + std::to_string(channel)));
          continue;
        }
        if (!it->second.subscriptions.emplace(id, channel).second) {
          send_text(h, status_json(1, "subscription id " + std::to_string(id) + " in use"));
          continue;
        }
        if (team == 0 && static_cast<Channel>(channel) == Channel::map) send_map(h, id);
      }
    } else if (op == "unsubscribe" && j.contains("subscriptionIds") && j["subscriptionIds"].is_array()) {
      for (const nlohmann::json& id : j["subscriptionIds"])
        if (id.is_number_unsigned()) it->second.subscriptions.erase(id.get<std::uint32_t>());
    } else {
      send_text(h, status_json(1, "unsupported op '" + op + "'"));
    }
    count_subscribed();
  }

  void count_subscribed() {
    std::uint32_t n = 0;
    for (const auto& [hdl, c] : clients) n += c.subscriptions.empty() ? 0u : 1u;
    subscribed.store(n, std::memory_order_relaxed);
  }

  void send_text(Hdl h, const std::string& text) {
    std::error_code ec;
    server.send(h, text, websocketpp::frame::opcode::text, ec);
  }

  static std::string frame(std::uint32_t subscription, TimeNs stamp_ns, const std::string& payload) {
    std::string f;
    f.reserve(13 + payload.size());
    f += '\x01';  // message data
    put_le(f, subscription, 4);
    put_le(f, static_cast<std::uint64_t>(stamp_ns < 0 ? 0 : stamp_ns), 8);
    f += payload;
    return f;
  }

  void send_map(Hdl h, std::uint32_t subscription) {
    std::string payload;
    {
      const std::lock_guard<std::mutex> lock(map_mutex);
      payload = map_payload;
    }
    if (payload.empty()) return;
    std::error_code ec;
    server.send(h, frame(subscription, 0, payload), websocketpp::frame::opcode::binary, ec);
    if (!ec) sent.fetch_add(1, std::memory_order_relaxed);
  }

  bool wanted(Channel ch) const { return wanted(static_cast<std::uint32_t>(ch)); }
  bool wanted(std::uint32_t ch) const {
    for (const auto& [hdl, c] : clients)
      for (const auto& [id, sub] : c.subscriptions)
        if (sub == ch) return true;
    return false;
  }

  void broadcast(Channel ch, TimeNs stamp_ns, const std::string& payload) {
    broadcast(static_cast<std::uint32_t>(ch), stamp_ns, payload);
  }
  void broadcast(std::uint32_t ch, TimeNs stamp_ns, const std::string& payload) {
    for (const auto& [hdl, c] : clients) {
      for (const auto& [id, sub] : c.subscriptions) {
        if (sub != ch) continue;
        std::error_code ec;
        Server::connection_ptr con = server.get_con_from_hdl(hdl, ec);
        if (ec) continue;
        if (con->get_buffered_amount() > kMaxBufferedBytes) {
          dropped_slow.fetch_add(1, std::memory_order_relaxed);
          continue;
        }
        con->send(frame(id, stamp_ns, payload), websocketpp::frame::opcode::binary);
        sent.fetch_add(1, std::memory_order_relaxed);
      }
    }
  }

  void drain() {
    Item item;
    while (ring.pop(item)) {
      const EstimateSample& e = item.e;
      if (item.robot >= 0) {
        drain_team(item);
        continue;
      }
      if (item.kind == Item::Kind::truth) {
        if (wanted(Channel::truth)) broadcast(Channel::truth, e.stamp_ns, pose_json(e.stamp_ns, e.pose));
        continue;
      }
      if (wanted(Channel::estimate)) broadcast(Channel::estimate, e.stamp_ns, pose_json(e.stamp_ns, e.pose));
      if (wanted(Channel::ellipse)) broadcast(Channel::ellipse, e.stamp_ns, ellipse_json(e));
      if (wanted(Channel::status))
        broadcast(Channel::status, e.stamp_ns, status_json(e, dropped_handoff.load(std::memory_order_relaxed)));
    }
    if (const ParticleCloud* c = clouds.take(); c != nullptr && wanted(Channel::particles))
      broadcast(Channel::particles, c->stamp_ns, particles_json(*c));
    if (const LandmarkSet* l = landmark_sets.take(); l != nullptr && wanted(kLandmarksChannel))
      broadcast(kLandmarksChannel, l->stamp_ns, landmarks_json(*l));
  }

  void drain_team(const Item& item) {
    const EstimateSample& e = item.e;
    if (item.kind == Item::Kind::truth) {
      const std::uint32_t ch = team_channel(item.robot, 0);
      if (wanted(ch)) broadcast(ch, e.stamp_ns, pose_json(e.stamp_ns, e.pose));
      return;
    }
    if (wanted(team_channel(item.robot, 1)))
      broadcast(team_channel(item.robot, 1), e.stamp_ns, pose_json(e.stamp_ns, e.pose));
    if (wanted(team_channel(item.robot, 2))) broadcast(team_channel(item.robot, 2), e.stamp_ns, ellipse_json(e));
    if (item.with_status && wanted(Channel::status))
      broadcast(Channel::status, e.stamp_ns, status_json(e, dropped_handoff.load(std::memory_order_relaxed)));
  }

  void schedule_drain() {
    timer.expires_after(kDrainPeriod);
    timer.async_wait([this](const std::error_code& ec) {
      if (ec) return;  // cancelled: shutting down
      drain();
      schedule_drain();
    });
  }

  std::string name;
  int team = 0;
  std::vector<std::uint32_t> ids;  // advertised
  asio::io_service ios;
  asio::steady_timer timer{ios};
  Server server;
  std::uint16_t port = 0;
  std::map<Hdl, Client, std::owner_less<Hdl>> clients;  // server thread only
  std::thread thread;
  std::promise<void> done;

  // Shared between the threads.
  ItemRing ring;
  TripleBuffer<ParticleCloud> clouds{reserve_cloud};
  TripleBuffer<LandmarkSet> landmark_sets{reserve_landmarks};
  std::mutex map_mutex;
  std::string map_payload;
  std::atomic<std::uint32_t> subscribed{0};
  std::atomic<std::uint64_t> client_count{0}, pages{0}, sent{0}, dropped_handoff{0}, dropped_slow{0};
};

LiveView::LiveView(std::uint16_t port, const std::string& name, int team_robots)
    : impl_(std::make_unique<Impl>(port, name, team_robots)) {}
LiveView::~LiveView() = default;
void LiveView::stop() { impl_->stop(); }

void LiveView::set_map(const MapGrid& map) {
  std::string payload = map_json(map);
  const std::lock_guard<std::mutex> lock(impl_->map_mutex);
  impl_->map_payload = std::move(payload);
}

void LiveView::publish_estimate(const EstimateSample& e) {
  Item item;
  item.e = e;
  if (!impl_->ring.push(item)) impl_->dropped_handoff.fetch_add(1, std::memory_order_relaxed);
}

void LiveView::publish_truth(TimeNs stamp_ns, const Pose& p) {
  Item item;
  item.kind = Item::Kind::truth;
  item.e.stamp_ns = stamp_ns;
  item.e.pose = p;
  if (!impl_->ring.push(item)) impl_->dropped_handoff.fetch_add(1, std::memory_order_relaxed);
}

bool LiveView::particles_due() {
  if (impl_->subscribed.load(std::memory_order_relaxed) == 0) return false;
  const auto now = std::chrono::steady_clock::now();
  if (now < next_cloud_) return false;
  next_cloud_ = now + kParticlePeriod;
  return true;
}

void LiveView::publish_particles(TimeNs stamp_ns, const float* x, const float* y, const float* theta,
                                 std::uint32_t count) {
  ParticleCloud& c = impl_->clouds.back();
  c.stamp_ns = stamp_ns;
  c.total = count;
  c.xs.clear();
  c.ys.clear();
  c.thetas.clear();
  const std::uint32_t stride = static_cast<std::uint32_t>((count + kMaxCloudPoses - 1) / kMaxCloudPoses);
  for (std::uint32_t i = 0; i < count; i += stride > 0 ? stride : 1u) {
    c.xs.push_back(x[i]);
    c.ys.push_back(y[i]);
    c.thetas.push_back(theta[i]);
  }
  if (!impl_->clouds.publish()) impl_->dropped_handoff.fetch_add(1, std::memory_order_relaxed);
}

void LiveView::publish_team_estimate(int robot, const EstimateSample& e, bool with_status) {
  Item item;
  item.robot = robot;
  item.with_status = with_status;
  item.e = e;
  if (!impl_->ring.push(item)) impl_->dropped_handoff.fetch_add(1, std::memory_order_relaxed);
}

void LiveView::publish_team_truth(int robot, TimeNs stamp_ns, const Pose& p) {
  Item item;
  item.kind = Item::Kind::truth;
  item.robot = robot;
  item.e.stamp_ns = stamp_ns;
  item.e.pose = p;
  if (!impl_->ring.push(item)) impl_->dropped_handoff.fetch_add(1, std::memory_order_relaxed);
}

bool LiveView::landmarks_due() {
  if (impl_->subscribed.load(std::memory_order_relaxed) == 0) return false;
  const auto now = std::chrono::steady_clock::now();
  if (now < next_landmarks_) return false;
  next_landmarks_ = now + kParticlePeriod;
  return true;
}

void LiveView::publish_landmarks(TimeNs stamp_ns, const LandmarkSample* landmarks, std::size_t count) {
  LandmarkSet& l = impl_->landmark_sets.back();
  l.stamp_ns = stamp_ns;
  l.landmarks.assign(landmarks, landmarks + std::min(count, kMaxViewLandmarks));
  if (!impl_->landmark_sets.publish()) impl_->dropped_handoff.fetch_add(1, std::memory_order_relaxed);
}

std::uint32_t LiveView::subscribers() const { return impl_->subscribed.load(std::memory_order_relaxed); }

ViewCounters LiveView::counters() const {
  ViewCounters c;
  c.clients = impl_->client_count.load();
  c.pages = impl_->pages.load();
  c.messages_sent = impl_->sent.load();
  c.dropped_handoff = impl_->dropped_handoff.load();
  c.dropped_slow = impl_->dropped_slow.load();
  return c;
}

std::uint16_t LiveView::port() const { return impl_->port; }

}  // namespace view
