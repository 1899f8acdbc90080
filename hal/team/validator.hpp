#pragma once
// Judges a teammate's message as it arrives, for a team of R robots, in front of the team window: its content
// (est::team::check), its sender (in the team, and not the receiving robot itself: its own message coming back from
// the network), and its place in the sender's sequence. A (robot, seq) already received is a duplicate; one older
// than the sender's newest but not received yet is out of order: accepted (the window reorders it) and counted.
// Late (a step the window already closed) only the window can tell, and it counts it. Every outcome is counted by
// reason, over the team and per sender. Board-safe: fixed storage, no heap.
//
// Per sender the newest seq accepted is kept with a bitmask of the 64 seqs ending at it (bit i: newest - i), as in
// IPsec's anti-replay window (RFC 4303, 3.4.3). A seq 64 or more below the newest cannot be told from a duplicate:
// it is accepted as out of order, and the window, which closed its step long before, refuses it as late.
#include <cstdint>

#include "est/team/team_message.hpp"
#include "hal/fault.hpp"

namespace hal::team {

using TeamRejectCounters = ReasonCounters<est::team::TeamReject, est::team::kTeamRejectCount>;

inline constexpr std::int32_t kNoRobot = -1;  // a receiver that is no robot of the team (a logger, a monitor)

class TeamValidator {
 public:
  // A team of `robots` (ids 0..robots-1, at most est::team::kMaxTeamRobots: more, and every message is refused as
  // unknown_robot); `self` is the receiving robot's id, whose own messages are refused when they come back.
  TeamValidator(std::int32_t robots, std::int32_t self) : robots_(robots), self_(self) {}

  // none or out_of_order: accepted, pass it on; malformed, unknown_robot or duplicate: refused. Counted either way.
  est::team::TeamReject check(const est::team::TeamMessage& m) {
    using est::team::TeamReject;
    if (self_ != kNoRobot && m.robot == self_) return count(TeamReject::unknown_robot, m.robot);  // own echo
    const TeamReject content = est::team::check(m, robots_);
    if (content != TeamReject::none) return count(content, m.robot);
    return count(sequence(senders_[m.robot], m.seq), m.robot);  // check() bounded m.robot to the team
  }

  static bool accepted(est::team::TeamReject r) {
    return r == est::team::TeamReject::none || r == est::team::TeamReject::out_of_order;
  }

  // Every message checked, by outcome: [none] accepted in order, [out_of_order] accepted out of order, [malformed],
  // [unknown_robot], [duplicate] refused; [late] and [capacity] stay 0 (the window's).
  const TeamRejectCounters& counts() const { return counts_; }
  // The same, of one sender; zero for an id outside the team (its messages are in counts() only).
  TeamRejectCounters counts(std::int32_t robot) const {
    return in_team(robot) ? per_sender_[robot] : TeamRejectCounters{};
  }
  std::uint32_t accepted() const {
    return saturated(std::uint64_t{counts_[est::team::TeamReject::none]} +
                     counts_[est::team::TeamReject::out_of_order]);
  }
  std::uint32_t rejected() const {
    return saturated(std::uint64_t{counts_[est::team::TeamReject::malformed]} +
                     counts_[est::team::TeamReject::unknown_robot] + counts_[est::team::TeamReject::duplicate]);
  }

  std::int32_t robots() const { return robots_; }
  std::int32_t self() const { return self_; }

 private:
  struct Sender {
    bool any = false;
    std::uint32_t newest = 0;
    std::uint64_t seen = 0;  // bit i: newest - i received
  };

  bool in_team(std::int32_t robot) const {
    return robot >= 0 && robot < robots_ && robot < est::team::kMaxTeamRobots;
  }
  static std::uint32_t saturated(std::uint64_t n) {
    return n > UINT32_MAX ? UINT32_MAX : static_cast<std::uint32_t>(n);
  }

  est::team::TeamReject count(est::team::TeamReject r, std::int32_t robot) {
    counts_.add(r);
    if (in_team(robot)) per_sender_[robot].add(r);
    return r;
  }

  static est::team::TeamReject sequence(Sender& s, std::uint32_t seq) {
    using est::team::TeamReject;
    if (!s.any || seq > s.newest) {
      const std::uint32_t ahead = s.any ? seq - s.newest : 64u;
      s.seen = ahead >= 64u ? 1u : (s.seen << ahead) | 1u;
      s.newest = seq;
      s.any = true;
      return TeamReject::none;
    }
    const std::uint32_t behind = s.newest - seq;
    if (behind >= 64u) return TeamReject::out_of_order;
    const std::uint64_t bit = std::uint64_t{1} << behind;
    if ((s.seen & bit) != 0u) return TeamReject::duplicate;
    s.seen |= bit;
    return TeamReject::out_of_order;
  }

  std::int32_t robots_;
  std::int32_t self_;
  Sender senders_[est::team::kMaxTeamRobots] = {};
  TeamRejectCounters counts_;
  TeamRejectCounters per_sender_[est::team::kMaxTeamRobots] = {};
};

}  // namespace hal::team
