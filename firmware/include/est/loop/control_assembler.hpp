#pragma once
// How the loop's gathered motion (est/loop/motion_input.hpp) becomes a motion model's control: one assembler per
// model, in est/loop/controls/, each a specialization of ControlAssembler<Model> with
//   struct Config;                       what the robot's inputs mean (encoder resolution, which wheel, the source)
//   static InputKinds inputs(const Config&);            the motion kinds it reads
//   static ControlStatus make(const MotionInput&, const Config&, typename Model::Params&, typename Model::Control&);
// `make` may set the parameters that depend on the interval (dt) or on the inputs, starting from the estimator's
// configured ones. `still` means no motion was measured: the filter neither moves nor diffuses (a robot standing
// still does not become less certain of where it is).
#include <cstdint>

#include "est/loop/input_kinds.hpp"
#include "est/loop/motion_input.hpp"

namespace est::loop {

enum class ControlStatus : std::uint8_t { ok, still, rejected };

template <typename Model>
struct ControlAssembler;

}  // namespace est::loop
