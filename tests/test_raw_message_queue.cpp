// The bounded queue between estimator_node's LCM receive thread and its loop (node/raw_message_queue.hpp): fixed
// capacity, the oldest gives way when full, every drop counted by channel, received = handed + dropped + queued.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

#include "node/raw_message_queue.hpp"

namespace {

std::vector<std::uint8_t> payload(std::uint8_t v, std::size_t n) { return std::vector<std::uint8_t>(n, v); }

}  // namespace

TEST_CASE("a full raw message queue drops the oldest and counts it on its channel", "[raw_queue]") {
  node::RawMessageQueue q(3, 16);
  for (std::uint8_t i = 0; i < 5; ++i) {
    const auto p = payload(i, 4);
    q.push(i % 2 == 0 ? 0 : 1, p.data(), p.size(), 100 + i);
  }
  node::RawQueueCounters c = q.counters();
  CHECK(c.received[0] == 3u);
  CHECK(c.received[1] == 2u);
  CHECK(c.dropped_full[0] == 1u);  // message 0
  CHECK(c.dropped_full[1] == 1u);  // message 1
  CHECK(c.high_water == 3u);
  CHECK(c.queued == 3u);
  node::RawMessage m;
  for (std::uint8_t want = 2; want < 5; ++want) {
    REQUIRE(q.pop(m));
    CHECK(m.bytes[0] == want);
    CHECK(m.size == 4u);
    CHECK(m.receive_ns == 100 + want);
    CHECK(m.channel == (want % 2 == 0 ? 0 : 1));
  }
  CHECK(!q.pop(m));
  c = q.counters();
  CHECK(node::RawQueueCounters::sum(c.received) ==
        node::RawQueueCounters::sum(c.handed) + node::RawQueueCounters::sum(c.dropped_full) + c.queued);
}

TEST_CASE("a raw message larger than a slot is dropped and counted as oversize, the queue untouched", "[raw_queue]") {
  node::RawMessageQueue q(2, 8);
  const auto big = payload(7, 9), fits = payload(8, 8);
  q.push(3, big.data(), big.size(), 1);
  q.push(3, fits.data(), fits.size(), 2);
  const node::RawQueueCounters c = q.counters();
  CHECK(c.received[3] == 2u);
  CHECK(c.dropped_oversize[3] == 1u);
  CHECK(c.queued == 1u);
  node::RawMessage m;
  REQUIRE(q.pop(m));
  CHECK(m.bytes[7] == 8);
}

TEST_CASE("a producer and a consumer on two threads: every message handed over or counted as dropped, in order",
          "[raw_queue]") {
  node::RawMessageQueue q(16, 8);
  constexpr std::uint32_t kMessages = 200000;
  std::thread producer([&] {
    for (std::uint32_t i = 0; i < kMessages; ++i) q.push(0, &i, sizeof i, i);
  });
  std::uint64_t handed = 0;
  std::int64_t last = -1;
  bool in_order = true;
  node::RawMessage m;
  for (;;) {
    if (q.pop(m)) {
      ++handed;
      std::uint32_t v = 0;
      std::memcpy(&v, m.bytes.data(), sizeof v);
      in_order = in_order && static_cast<std::int64_t>(v) > last;
      last = v;
      if (v == kMessages - 1) break;
    }
  }
  producer.join();
  const node::RawQueueCounters c = q.counters();
  CHECK(in_order);
  CHECK(c.received[0] == kMessages);
  CHECK(c.handed[0] == handed);
  CHECK(c.handed[0] + c.dropped_full[0] + c.queued == kMessages);
}
