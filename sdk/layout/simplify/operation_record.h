// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The progressive hierarchy of the face-merge simplifier (thesis §3.3: "browsed up- and
// down-stream"). Every face state that ever existed is one FaceRecord (loops flattened into a
// shared pool, proxy, and the index of the same face's previous record). A level step lists
// the records it installs, so applying a step sets current[face] = record and undoing it sets
// current[face] = record.prev: O(number of faces the step touched). A merge step also sets the
// absorbed face's cluster parent (union by cluster size keeps parent chains O(log n) deep).
// Private to sdk/layout.
#include <cstdint>
#include <vector>

#include "core/vec3.h"

CAGEKIT_NAMESPACE_BEGIN
namespace detail {

constexpr uint32_t kNoRecord = 0xffffffffu;

struct FaceRecord {
  uint32_t face = 0;
  uint32_t prev = kNoRecord;  // the face's record before this one
  uint64_t pool_begin = 0;    // [num_loops, size_0, v..., size_1, v...]
  uint32_t pool_size = 0;
  bool alive = false;
  Vec3 normal, centroid;
  double area = 0;
};

struct LevelStep {
  uint32_t record_begin = 0, record_end = 0;  // records installed by the step
  uint32_t merged_from = kNoRecord;           // absorbed face (merges), else kNoRecord
  uint32_t merged_into = kNoRecord;
};

struct HierarchyRecords {
  std::vector<FaceRecord> records;
  std::vector<uint32_t> pool;
  std::vector<LevelStep> steps;  // step k turns level k into level k+1
  std::vector<uint32_t> current;  // face id -> record at the current level
  std::vector<uint32_t> parent;   // face id -> face it was merged into (at the current level)
  size_t level = 0;

  uint32_t add_record(uint32_t face, bool alive, const std::vector<std::vector<uint32_t>>& loops,
                      const Vec3& normal, const Vec3& centroid, double area) {
    FaceRecord r;
    r.face = face;
    r.prev = face < current.size() ? current[face] : kNoRecord;
    r.alive = alive;
    r.normal = normal;
    r.centroid = centroid;
    r.area = area;
    r.pool_begin = pool.size();
    pool.push_back(static_cast<uint32_t>(loops.size()));
    for (const auto& l : loops) {
      pool.push_back(static_cast<uint32_t>(l.size()));
      pool.insert(pool.end(), l.begin(), l.end());
    }
    r.pool_size = static_cast<uint32_t>(pool.size() - r.pool_begin);
    records.push_back(r);
    const uint32_t id = static_cast<uint32_t>(records.size() - 1);
    if (face >= current.size()) current.resize(face + 1, kNoRecord);
    current[face] = id;
    return id;
  }

  void loops_of(const FaceRecord& r, std::vector<std::vector<uint32_t>>& loops) const {
    const uint32_t* p = pool.data() + r.pool_begin;
    loops.assign(p[0], {});
    ++p;
    for (auto& l : loops) {
      l.assign(p + 1, p + 1 + p[0]);
      p += 1 + p[0];
    }
  }

  void apply(size_t k) {
    const LevelStep& s = steps[k];
    for (uint32_t r = s.record_begin; r < s.record_end; ++r) current[records[r].face] = r;
    if (s.merged_from != kNoRecord) parent[s.merged_from] = s.merged_into;
  }
  void undo(size_t k) {
    const LevelStep& s = steps[k];
    for (uint32_t r = s.record_end; r-- > s.record_begin;) current[records[r].face] = records[r].prev;
    if (s.merged_from != kNoRecord) parent[s.merged_from] = kNoRecord;
  }
};

}  // namespace detail
CAGEKIT_NAMESPACE_END
