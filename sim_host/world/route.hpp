#pragma once
// A closed route through a world: waypoints visited in order, the last joined to the first, each segment at its
// first waypoint's speed or the robot's cruise speed. Start poses for runs are taken on its segments, heading along
// them.
#include <cstddef>
#include <vector>

#include "est/geometry/pose2.hpp"

namespace est::sim {

struct Waypoint {
  float x, y;
  float speed_mps = 0.0f;  // from this waypoint to the next; 0: the robot's cruise speed
};

class Route {
 public:
  explicit Route(std::vector<Waypoint> points);  // at least two points; throws std::invalid_argument otherwise

  std::size_t size() const { return pts_.size(); }
  const Waypoint& operator[](std::size_t i) const { return pts_[i % pts_.size()]; }
  // The pose at `fraction` in [0, 1) along segment i (waypoint i -> i + 1), heading along the segment.
  Pose2 pose_on_segment(std::size_t i, float fraction) const;
  float length() const;

 private:
  std::vector<Waypoint> pts_;
};

// Follows a route: the target is the next waypoint, switched to the one after when closer than `reach`.
class RouteFollower {
 public:
  RouteFollower(const Route& route, std::size_t next_waypoint, float reach)
      : route_(&route), next_(next_waypoint), reach_(reach) {}
  // Advances the target if the position has reached it; returns the current target.
  Waypoint target(float x, float y);
  // The speed of the segment being driven (its first waypoint's), or `cruise` when it names none.
  float speed(float cruise) const;
  void set_next(std::size_t i) { next_ = i; }
  std::size_t next() const { return next_; }
  std::size_t laps() const { return next_ / route_->size(); }

 private:
  const Route* route_;
  std::size_t next_;
  float reach_;
};

}  // namespace est::sim
