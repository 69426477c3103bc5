// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Private to sdk/core/io: the per-format readers and writers behind mesh_io.h, and the helpers
// they share (error messages that name the source and location, progress, validation).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/io/mesh_io.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

// Everything a reader needs besides the bytes: where they came from (for messages), the limits
// and the monitor. Error helpers format "source:line: message" / "source: byte N: message".
struct ReadContext {
  const std::string& source;
  const ReadOptions& options;
  const TaskMonitor& monitor;

  [[noreturn]] void fail_at_line(size_t line, const std::string& message,
                                 Status status = Status::parse_error) const;
  [[noreturn]] void fail_at_byte(size_t offset, const std::string& message,
                                 Status status = Status::parse_error) const;
  [[noreturn]] void fail_here(const std::string& message, Status status = Status::parse_error) const;

  // limit_exceeded unless count <= limit; `what` is e.g. "vertices".
  void check_limit(uint64_t count, uint64_t limit, const char* what, size_t line_or_byte,
                   bool is_line) const;
};

// Calls monitor.report(stage, fraction) once every kProgressInterval ticks.
class ProgressTicker {
 public:
  static constexpr uint32_t kProgressInterval = 1u << 16;
  ProgressTicker(const TaskMonitor& monitor, const char* stage) : monitor_(monitor), stage_(stage) {}
  void tick(double fraction) {
    if (++count_ == kProgressInterval) {
      count_ = 0;
      monitor_.report(stage_, fraction < 0 ? 0 : (fraction > 1 ? 1 : fraction));
    }
  }

 private:
  const TaskMonitor& monitor_;
  const char* stage_;
  uint32_t count_ = 0;
};

// Final checks every reader applies: at least one vertex and one face ("no vertices" / "no faces").
void check_not_empty(const Cage& cage, const ReadContext& context);

// Throws Status::invalid_mesh / invalid_argument when `cage` or `options` cannot be written.
void validate_for_writing(const Cage& cage, const WriteOptions& options);

// Largest distance between positions of `a` and `b` (same vertex count required).
double max_position_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

class TextWriter;
// The vertex lines ("x y z") then the face lines ("n i0 i1 ...") shared by ascii PLY and OFF;
// returns the largest position change the decimal printing caused.
double write_ascii_vertices_and_faces(const PolygonMesh& mesh, ProgressTicker& progress, TextWriter& w);

// Readers (data may be null only when size == 0).
Cage read_obj(const uint8_t* data, size_t size, const ReadContext& context);
Cage read_ply(const uint8_t* data, size_t size, const ReadContext& context);
Cage read_off(const uint8_t* data, size_t size, const ReadContext& context);
Cage read_draco(const uint8_t* data, size_t size, const ReadContext& context);
Cage read_stl(const uint8_t* data, size_t size, const ReadContext& context);

// True when `size` is exactly 84 + 50 * (the little-endian uint32 at byte 80): a binary STL.
// Decided before anything else because many binary STL headers start with "solid".
bool is_binary_stl_size(const uint8_t* data, size_t size);

// Writers append to `out` and return the largest position error of what they wrote (measured).
double write_obj(const Cage& cage, const WriteOptions& options, const TaskMonitor& monitor,
                 std::vector<uint8_t>& out);
double write_ply(const Cage& cage, const WriteOptions& options, const TaskMonitor& monitor,
                 std::vector<uint8_t>& out);
double write_off(const Cage& cage, const WriteOptions& options, const TaskMonitor& monitor,
                 std::vector<uint8_t>& out);
double write_draco(const Cage& cage, const WriteOptions& options, const TaskMonitor& monitor,
                   std::vector<uint8_t>& out);

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
