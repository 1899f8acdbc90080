#include "data/event_buffer.hpp"

#include <algorithm>
#include <stdexcept>

#include "node/lcm_log_io.hpp"

namespace sim::data {

std::uint64_t EventBuffer::write_sorted(const std::string& path) {
  std::stable_sort(events_.begin(), events_.end(), [](const Event& a, const Event& b) {
    return a.t_ns != b.t_ns ? a.t_ns < b.t_ns : a.order < b.order;
  });
  node::LogWriter log(path);
  for (const Event& e : events_) log.write_raw(e.channel, e.t_ns, e.data.data(), static_cast<int>(e.data.size()));
  if (log.failures() != 0)
    throw std::runtime_error(path + ": " + std::to_string(log.failures()) + " events not written");
  return log.events();
}

std::int64_t EventBuffer::last_ns() const {
  std::int64_t t = 0;
  for (const Event& e : events_) t = std::max(t, e.t_ns);
  return t;
}

}  // namespace sim::data
