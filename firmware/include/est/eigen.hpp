#pragma once
// The one way the firmware includes Eigen: fixed-size types only, and an assertion that can never reach malloc.
// Eigen's default eigen_assert goes through newlib's assert/fiprintf, which links the heap; a failed internal
// assertion in the firmware is a programming error, so it traps on the board and aborts on the host.
#ifndef eigen_assert
#define eigen_assert(x) ((x) ? (void)0 : __builtin_trap())
#endif
// EIGEN_NO_MALLOC turns any heap allocation by Eigen into that assertion. Host tools with dynamic matrices of their
// own (sim_host) define EST_EIGEN_HEAP_ALLOWED for all their files, so that the order of includes cannot decide it.
#if !defined(EIGEN_NO_MALLOC) && !defined(EST_EIGEN_HEAP_ALLOWED)
#define EIGEN_NO_MALLOC
#endif

#include <Eigen/Core>
