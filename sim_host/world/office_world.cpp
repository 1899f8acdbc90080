#include "world/office_world.hpp"

#include <memory>
#include <stdexcept>

namespace est::sim {
namespace {

std::unique_ptr<OfficeWorld> build() {
  auto w = std::make_unique<OfficeWorld>();
  make_office_map(w->grid_storage);
  if (w->edt_storage.build(w->grid()) != MapStatus::ok) throw std::runtime_error("office_world: distance transform");
  const float posts[16][2] = {{0.5f, 8.0f},  {4.5f, 6.5f},  {8.5f, 8.1f},   {12.0f, 6.5f}, {17.0f, 8.0f}, {19.3f, 6.6f},
                              {13.5f, 9.0f}, {16.8f, 9.2f}, {11.0f, 11.0f}, {8.5f, 13.5f}, {7.5f, 9.2f},  {4.5f, 12.0f},
                              {2.0f, 9.0f},  {6.0f, 14.0f}, {18.5f, 12.5f}, {9.7f, 5.0f}};
  for (int i = 0; i < 16; ++i)
    if (w->landmark_storage.add({posts[i][0], posts[i][1], static_cast<float>(i + 1)}) != MapStatus::ok)
      throw std::runtime_error("office_world: landmark map");
  return w;
}

}  // namespace

const OfficeWorld& office_world() {
  static const std::unique_ptr<OfficeWorld> w = build();
  return *w;
}

}  // namespace est::sim
