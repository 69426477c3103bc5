// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/memory_budget.h"

#include <string>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {
thread_local uint64_t tls_budget = 0;

std::string megabytes(uint64_t bytes) {
  if (bytes == UINT64_MAX) return "more than 16 EiB";
  return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB";
}
}  // namespace

uint64_t memory_budget() { return tls_budget; }

void check_memory_estimate(uint64_t bytes, const char* what) {
  if (tls_budget != 0 && bytes > tls_budget)
    fail(Status::out_of_memory, std::string(what) + " needs about " + megabytes(bytes) +
                                    ", more than the context's memory budget of " + megabytes(tls_budget));
}

ScopedMemoryBudget::ScopedMemoryBudget(uint64_t bytes) : previous_(tls_budget) { tls_budget = bytes; }
ScopedMemoryBudget::~ScopedMemoryBudget() { tls_budget = previous_; }

CAGEKIT_NAMESPACE_END
