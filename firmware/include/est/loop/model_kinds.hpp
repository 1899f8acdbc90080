#pragma once
// The choices a host program makes at run time among its instantiations of the loop (est/loop/configured_loop.hpp;
// a board states the types instead): the filter, every motion model of est/motion, and MCL's range models.
#include <cstdint>

namespace est::loop {

enum class Filter : std::uint8_t { mcl, ekf, ekf_slam };
enum class MotionModelKind : std::uint8_t { velocity, odometry, bicycle, diff_drive, omni, holonomic };
enum class RangeModelKind : std::uint8_t { likelihood_field, beam, steered };

}  // namespace est::loop
