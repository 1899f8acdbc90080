#include "sim/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace sim {
namespace {

double now_s() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

}  // namespace

Progress::Progress(std::string label, double total, bool quiet, Unit unit, double show_after_s)
    : label_(std::move(label)),
      total_(total),
      enabled_(!quiet && isatty(2) != 0),
      unit_(unit),
      show_after_s_(show_after_s),
      start_s_(now_s()) {}

void Progress::update(double done, const std::string& note) {
  if (!enabled_) return;
  const double now = now_s();
  const double elapsed = now - start_s_;
  if (elapsed < show_after_s_) return;
  if (last_draw_s_ >= 0.0 && now - last_draw_s_ < 0.1) return;
  last_draw_s_ = now;
  const double share = total_ > 0.0 ? std::clamp(done / total_, 0.0, 1.0) : 0.0;
  const double eta = share > 0.0 ? elapsed * (1.0 - share) / share : 0.0;
  if (unit_ == Unit::simulated_s)
    std::fprintf(stderr, "\r%s: t %.1f / %.1f s, %.1fx real time, ETA %.0f s   ", label_.c_str(), done, total_,
                 elapsed > 0.0 ? done / elapsed : 0.0, eta);
  else
    std::fprintf(stderr, "\r%s: %3.0f %% (%.0f / %.0f), %.1f s, ETA %.0f s%s%s   ", label_.c_str(), 100.0 * share,
                 done, total_, elapsed, eta, note.empty() ? "" : ", ", note.c_str());
  std::fflush(stderr);
}

void Progress::finish() {
  if (!enabled_ || last_draw_s_ < 0.0) return;
  std::fprintf(stderr, "\r%s: done in %.1f s%40s\n", label_.c_str(), now_s() - start_s_, "");
  last_draw_s_ = -1.0;
}

}  // namespace sim
