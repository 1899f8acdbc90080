#pragma once
// The input ports. A backend (CAN, LCM, board driver, replay) calls a SensorPort with raw decoded samples;
// ValidatedInputs checks them and calls a ValidatedSensorPort, which is what the filter loop's adapter implements.
// Each port has one `on(const Sample&)` per entry of its sample list (hal/samples.hpp); PortImplementation<Derived,
// Port> implements all of them with one member template `Derived::handle(const Sample&)`, so a class that treats
// every sample alike (a gate, a recorder, a forwarder) is written once for every sensor.
// Views passed in are valid only during the call: copy what you keep.
#include "hal/samples.hpp"

namespace hal {

template <typename Sample>
class Receives {
 public:
  virtual void on(const Sample& sample) = 0;

 protected:
  ~Receives() = default;
};

template <typename List>
class PortOf;
template <typename... Samples>
class PortOf<SampleList<Samples...>> : public Receives<Samples>... {
 public:
  using List = SampleList<Samples...>;
  using Receives<Samples>::on...;

 protected:
  ~PortOf() = default;
};

using SensorPort = PortOf<RawSamples>;
using ValidatedSensorPort = PortOf<CheckedSamples>;

namespace detail {
template <typename Derived, typename Port, typename List>
class Implement;
template <typename Derived, typename Port>
class Implement<Derived, Port, SampleList<>> : public Port {};
template <typename Derived, typename Port, typename Sample, typename... Rest>
class Implement<Derived, Port, SampleList<Sample, Rest...>> : public Implement<Derived, Port, SampleList<Rest...>> {
 public:
  using Port::on;
  void on(const Sample& s) override { static_cast<Derived*>(this)->handle(s); }
};
}  // namespace detail

template <typename Derived, typename Port>
using PortImplementation = detail::Implement<Derived, Port, typename Port::List>;

}  // namespace hal
