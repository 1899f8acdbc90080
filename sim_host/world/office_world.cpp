#include "world/office_world.hpp"

#include <memory>
#include <stdexcept>

namespace est::sim {
namespace {

std::unique_ptr<OfficeWorld> build() {
  auto w = std::make_unique<OfficeWorld>();
  make_office_map(w->grid_storage);
  if (w->edt_storage.build(w->grid()) != MapStatus::ok) throw std::runtime_error("office_world: distance transform");
  make_office_landmarks(w->landmark_storage);
  return w;
}

}  // namespace

const OfficeWorld& office_world() {
  static const std::unique_ptr<OfficeWorld> w = build();
  return *w;
}

}  // namespace est::sim
