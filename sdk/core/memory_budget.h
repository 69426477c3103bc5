// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Memory budget of the current operation (hardening issue: hosts can cap what one CageKit call
// may use, so a hostile or oversized input fails with Status::out_of_memory instead of the host
// process being killed).
//
// The C API installs the calling context's budget on the calling thread for the duration of each
// call (ScopedMemoryBudget); the library checks its size estimates against it before large
// allocations and before handing work to a library (OpenSubdiv, CGAL, Draco, Eigen):
// check_memory_estimate(bytes, what) throws Error(out_of_memory) when the estimated peak of the
// step exceeds the budget. These are estimates of the dominant arrays of each step, not an
// accounting of every allocation. Budget 0 = unlimited (the default).
#include <cstdint>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN

// The budget in bytes installed on this thread (0 = unlimited).
uint64_t memory_budget();

// Throws Error(Status::out_of_memory) naming `what` when `bytes` exceeds this thread's budget.
void check_memory_estimate(uint64_t bytes, const char* what);

// Saturating arithmetic for estimates (never wraps around).
inline uint64_t estimate_product(uint64_t a, uint64_t b) {
  return (a != 0 && b > UINT64_MAX / a) ? UINT64_MAX : a * b;
}
inline uint64_t estimate_sum(uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; }

// Installs `bytes` as this thread's budget until destroyed (restores the previous one).
class ScopedMemoryBudget {
 public:
  explicit ScopedMemoryBudget(uint64_t bytes);
  ~ScopedMemoryBudget();
  ScopedMemoryBudget(const ScopedMemoryBudget&) = delete;
  ScopedMemoryBudget& operator=(const ScopedMemoryBudget&) = delete;

 private:
  uint64_t previous_;
};

CAGEKIT_NAMESPACE_END
