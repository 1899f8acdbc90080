#pragma once
// Progress of a long run on stderr when it is a terminal, redrawn in place at most ten times a second; nothing when
// stderr is not a terminal or when asked to be quiet. Two forms: a count ("label: 42 % (630 / 1500), 3.1 s, ETA 4 s")
// and simulated time ("label: t 12.0 / 60.0 s, 4.1x real time, ETA 12 s"). Host only.
#include <string>

namespace sim {

class Progress {
 public:
  enum class Unit { count, simulated_s };
  // `show_after_s`: nothing is drawn before this much wall time (a short run stays silent).
  Progress(std::string label, double total, bool quiet = false, Unit unit = Unit::count, double show_after_s = 0.0);
  void update(double done, const std::string& note = "");  // redraws at most ten times a second; `note` after it
  void finish();             // the final line, then a newline (only when something was drawn)
  bool enabled() const { return enabled_; }

 private:
  std::string label_;
  double total_;
  bool enabled_;
  Unit unit_;
  double show_after_s_;
  double last_draw_s_ = -1.0;
  double start_s_;
};

}  // namespace sim
