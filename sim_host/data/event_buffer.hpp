#pragma once
// An import's events gathered from every file of a dataset, then written to one LCM log in time order (ties by the
// order each importer gives its streams), so that a replay sees them as a live robot would have sent them. Host only.
#include <cstdint>
#include <string>
#include <vector>

namespace sim::data {

class EventBuffer {
 public:
  template <typename Message>
  void add(std::int64_t t_ns, int order, const std::string& channel, const Message& m) {
    Event e{t_ns, order, channel, {}};
    e.data.resize(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(e.data.data(), 0, static_cast<int>(e.data.size()));
    events_.push_back(std::move(e));
  }

  // Sorts by (time, order) and writes `path`; the number of events written (throws std::runtime_error if any was
  // not). last_ns() is the latest stamp.
  std::uint64_t write_sorted(const std::string& path);
  std::int64_t last_ns() const;

 private:
  struct Event {
    std::int64_t t_ns;
    int order;
    std::string channel;
    std::vector<std::uint8_t> data;
  };
  std::vector<Event> events_;
};

}  // namespace sim::data
