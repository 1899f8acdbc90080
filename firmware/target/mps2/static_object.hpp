#pragma once
// An object in static storage, built when its inputs are known and never destroyed (an image's main ends in
// board::exit): estimators and loops too big for the stack (board support).
#include <new>
#include <utility>

namespace board {

template <typename T>
class Static {
 public:
  template <typename... Args>
  T& emplace(Args&&... args) {
    return *new (bytes_) T(std::forward<Args>(args)...);
  }

 private:
  alignas(T) unsigned char bytes_[sizeof(T)];
};

}  // namespace board
