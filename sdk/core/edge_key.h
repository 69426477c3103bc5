// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The 64-bit key of an undirected edge between two 32-bit vertex ids: the smaller id in the high
// half, so (a, b) and (b, a) give the same key and keys sort by their lower vertex first.
#include <cstdint>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN

inline uint64_t edge_key(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}

CAGEKIT_NAMESPACE_END
