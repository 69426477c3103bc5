// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// 64-bit keys of edges between two 32-bit vertex ids, for hash maps and sorted edge lists.
// edge_key: undirected, the smaller id in the high half, so (a, b) and (b, a) give the same key
// and keys sort by their lower vertex first. directed_edge_key: the half-edge a -> b, `a` in the
// high half. edge_key_first / edge_key_second take either kind apart again.
#include <cstdint>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN

inline uint64_t directed_edge_key(uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; }

inline uint64_t edge_key(uint32_t a, uint32_t b) { return a < b ? directed_edge_key(a, b) : directed_edge_key(b, a); }

inline uint32_t edge_key_first(uint64_t key) { return uint32_t(key >> 32); }
inline uint32_t edge_key_second(uint64_t key) { return uint32_t(key & 0xffffffffu); }

CAGEKIT_NAMESPACE_END
