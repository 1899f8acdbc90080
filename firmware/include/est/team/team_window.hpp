#pragma once
// The team loop's reorder window: team messages (est/team/team_message.hpp) are held by (step, robot) and a step is
// handed to the estimator once, in step order, with the messages of every robot that sent one, robot 0 first. So
// the estimate depends only on which messages a step had, never on the order or the moment they arrived.
//
// A step k closes when every robot's message for k is in, or when a message of step k + Window arrived from anyone
// (the reorder rule of est/loop/filter_loop.hpp, counted in steps): a robot still missing then is handed over as
// absent (the estimator predicts it only), and its message, if it comes later, is late. Nodes that receive the
// same messages within Window steps of each other therefore close every step with the same messages and reach the
// same estimate bit for bit; the price is a latency of up to Window steps while a robot is silent.
//
// Bounded: a push closes at most max_jump steps (a sequence number further ahead of the newest is refused as
// malformed, so a corrupted seq cannot make the team predict for hours); storage is Window x R_max messages.
#include <cstdint>

#include "est/team/team_message.hpp"

namespace est::team {

struct TeamWindowCounters {
  std::uint32_t accepted = 0;
  std::uint32_t rejected[kTeamRejectCount] = {};    // by TeamReject (none unused)
  std::uint32_t steps_closed = 0;
  std::uint32_t steps_complete = 0;                 // closed with every robot's message
  std::uint32_t missing[kMaxTeamRobots] = {};       // steps closed without robot a's message
  std::uint32_t of(TeamReject r) const { return rejected[static_cast<std::uint8_t>(r)]; }
  std::uint32_t rejected_total() const {
    std::uint32_t s = 0;
    for (std::uint32_t r : rejected) s += r;
    return s;
  }
};

template <int R_max, int Window>
class TeamWindow {
  static_assert(R_max >= 1 && R_max <= kMaxTeamRobots, "a team has 1..kMaxTeamRobots robots");
  static_assert(Window >= 1 && Window <= 64, "the window holds 1..64 steps");

 public:
  static constexpr std::uint32_t kDefaultMaxJump = 3000;  // steps (5 min at 10 Hz)

  // A team of `robots` whose first step is `first_seq` (every node of the team must use the same). False, and the
  // window closed to every message, for a bad count.
  bool start(std::int32_t robots, std::uint32_t first_seq = 1, std::uint32_t max_jump = kDefaultMaxJump) {
    robots_ = (robots >= 1 && robots <= R_max) ? robots : 0;
    next_ = first_seq;
    newest_ = first_seq;
    max_jump_ = max_jump;
    counters_ = TeamWindowCounters{};
    for (Slot& s : slots_) s.present = 0u;
    return robots_ != 0;
  }

  // Holds m; closes the steps it completes or pushes out of the window, calling close(seq, msgs) for each, where
  // msgs[a] is robot a's message or nullptr (a < robots()). Returns why m was refused, or TeamReject::none.
  template <typename Close>
  TeamReject push(const TeamMessage& m, Close&& close) {
    TeamReject r = robots_ == 0 ? TeamReject::unknown_robot : check(m, robots_);
    if (r == TeamReject::none && m.seq < next_) r = TeamReject::late;
    if (r == TeamReject::none && m.seq > newest_ && m.seq - newest_ > max_jump_) r = TeamReject::malformed;
    if (r == TeamReject::none && has(m.seq, m.robot)) r = TeamReject::duplicate;
    if (r != TeamReject::none) {
      ++counters_.rejected[static_cast<std::uint8_t>(r)];
      return r;
    }
    if (m.seq > newest_) newest_ = m.seq;
    // Steps that fell out of the window close first (at most max_jump of them), then m takes its slot.
    while (newest_ - next_ >= static_cast<std::uint32_t>(Window)) close_next(close);
    Slot& s = slot(m.seq);
    if (s.seq != m.seq) {  // the slot's previous step is closed: reuse it
      s.seq = m.seq;
      s.present = 0u;
    }
    s.msgs[m.robot] = m;
    s.present |= 1u << static_cast<std::uint32_t>(m.robot);
    ++counters_.accepted;
    while (next_ <= newest_ && complete(next_)) close_next(close);
    return TeamReject::none;
  }

  // Closes every open step up to the newest (end of a log, or a node shutting down).
  template <typename Close>
  void flush(Close&& close) {
    while (next_ <= newest_) close_next(close);
  }

  std::int32_t robots() const { return robots_; }
  std::uint32_t next_step() const { return next_; }  // the oldest open step
  std::uint32_t newest_step() const { return newest_; }
  const TeamWindowCounters& counters() const { return counters_; }

 private:
  struct Slot {
    std::uint32_t seq = 0;
    std::uint32_t present = 0u;  // bit a: robot a's message is in
    TeamMessage msgs[static_cast<unsigned>(R_max)];
  };

  Slot& slot(std::uint32_t seq) { return slots_[seq % static_cast<std::uint32_t>(Window)]; }
  bool has(std::uint32_t seq, std::int32_t robot) {
    const Slot& s = slot(seq);
    return s.seq == seq && (s.present & (1u << static_cast<std::uint32_t>(robot))) != 0u;
  }
  bool complete(std::uint32_t seq) {
    const Slot& s = slot(seq);
    return s.seq == seq && s.present == (1u << static_cast<std::uint32_t>(robots_)) - 1u;
  }

  template <typename Close>
  void close_next(Close& close) {
    Slot& s = slot(next_);
    const bool mine = s.seq == next_;
    const TeamMessage* msgs[static_cast<unsigned>(R_max)] = {};
    for (std::int32_t a = 0; a < robots_; ++a) {
      const bool in = mine && (s.present & (1u << static_cast<std::uint32_t>(a))) != 0u;
      msgs[a] = in ? &s.msgs[a] : nullptr;
      if (!in) ++counters_.missing[a];
    }
    if (mine && s.present == (1u << static_cast<std::uint32_t>(robots_)) - 1u) ++counters_.steps_complete;
    close(next_, static_cast<const TeamMessage* const*>(msgs));
    s.present = 0u;
    ++counters_.steps_closed;
    ++next_;
  }

  std::int32_t robots_ = 0;
  std::uint32_t next_ = 1, newest_ = 1, max_jump_ = kDefaultMaxJump;
  TeamWindowCounters counters_{};
  Slot slots_[static_cast<unsigned>(Window)];
};

}  // namespace est::team
