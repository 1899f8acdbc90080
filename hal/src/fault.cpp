// Names of the rejection reasons (hal/fault.hpp).
#include "hal/fault.hpp"

namespace hal {

const char* to_string(Fault f) {
  switch (f) {
    case Fault::none: return "none";
    case Fault::not_finite: return "not_finite";
    case Fault::out_of_range: return "out_of_range";
    case Fault::time_backwards: return "time_backwards";
    case Fault::duplicate: return "duplicate";
    case Fault::stale: return "stale";
    case Fault::from_future: return "from_future";
    case Fault::bad_geometry: return "bad_geometry";
    case Fault::too_few_valid_beams: return "too_few_valid_beams";
    case Fault::kCount: break;
  }
  return "unknown";
}

}  // namespace hal
