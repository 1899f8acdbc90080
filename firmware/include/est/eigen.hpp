#pragma once
// The one way the firmware includes Eigen: fixed-size types only, and an assertion that can never reach malloc.
// Eigen's default eigen_assert goes through newlib's assert/fiprintf, which links the heap; a failed internal
// assertion in the firmware is a programming error, so it traps on the board and aborts on the host.
#ifndef eigen_assert
#define eigen_assert(x) ((x) ? (void)0 : __builtin_trap())
#endif
#ifndef EIGEN_NO_MALLOC
#define EIGEN_NO_MALLOC
#endif

#include <Eigen/Core>
