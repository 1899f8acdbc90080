#include "world/route.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace est::sim {

Route::Route(std::vector<Waypoint> points) : pts_(std::move(points)) {
  if (pts_.size() < 2) throw std::invalid_argument("Route: a route needs at least two waypoints");
}

Pose2 Route::pose_on_segment(std::size_t i, float fraction) const {
  const Waypoint& a = (*this)[i];
  const Waypoint& b = (*this)[i + 1];
  return {a.x + fraction * (b.x - a.x), a.y + fraction * (b.y - a.y), std::atan2(b.y - a.y, b.x - a.x)};
}

float Route::length() const {
  float l = 0.0f;
  for (std::size_t i = 0; i < pts_.size(); ++i)
    l += std::hypot((*this)[i + 1].x - (*this)[i].x, (*this)[i + 1].y - (*this)[i].y);
  return l;
}

Waypoint RouteFollower::target(float x, float y) {
  // Bounded: at most one switch per call, so a waypoint cluster cannot spin.
  const Waypoint& t = (*route_)[next_];
  if (std::hypot(t.x - x, t.y - y) < reach_) ++next_;
  return (*route_)[next_];
}

float RouteFollower::speed(float cruise) const {
  const float v = (*route_)[next_ + route_->size() - 1].speed_mps;
  return v > 0.0f ? v : cruise;
}

}  // namespace est::sim
