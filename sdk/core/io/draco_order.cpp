// SPDX-License-Identifier: GPL-3.0-or-later
// The "cagekit.order" blob of a Draco file (see draco_layout.h). Layout:
//   u8 version (1), varint num_vertices, varint num_faces, varint num_triangles, u8 flags,
//   [flags & 1] face sizes - 3                  (Draco symbol coding, num_faces values)
//   [flags & 2] zigzag(original - previous - 1) (per decoded triangle)
//   [flags & 4] rotation                        (per decoded triangle)
// The streams use Draco's own entropy coder (draco::EncodeSymbols), which it uses for its own
// connectivity, so the side data costs a few bits per triangle.
#include <draco/compression/config/compression_shared.h>
#include <draco/compression/config/draco_options.h>
#include <draco/compression/entropy/symbol_decoding.h>
#include <draco/compression/entropy/symbol_encoding.h>
#include <draco/core/decoder_buffer.h>
#include <draco/core/encoder_buffer.h>

#include "core/io/draco_layout.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN
namespace io_detail {

namespace {

enum : uint8_t { kHasFaceSizes = 1, kHasPermutation = 2, kHasRotation = 4 };
constexpr uint8_t kOrderVersion = 1;

void put_varint(std::vector<uint8_t>& out, uint64_t v) {
  while (v >= 0x80) {
    out.push_back(uint8_t(v | 0x80));
    v >>= 7;
  }
  out.push_back(uint8_t(v));
}

bool get_varint(const std::vector<uint8_t>& in, size_t& pos, uint64_t& v) {
  v = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    if (pos >= in.size()) return false;
    const uint8_t byte = in[pos++];
    v |= uint64_t(byte & 0x7F) << shift;
    if (!(byte & 0x80)) return true;
  }
  return false;
}

void put_symbols(std::vector<uint8_t>& out, const std::vector<uint32_t>& symbols) {
  draco::EncoderBuffer buffer;
  draco::Options options;
  if (!draco::EncodeSymbols(symbols.data(), int(symbols.size()), 1, &options, &buffer))
    fail(Status::internal_error, "Draco symbol encoding failed");
  put_varint(out, buffer.size());
  out.insert(out.end(), buffer.data(), buffer.data() + buffer.size());
}

bool get_symbols(const std::vector<uint8_t>& in, size_t& pos, uint32_t count, std::vector<uint32_t>& symbols) {
  uint64_t bytes = 0;
  if (!get_varint(in, pos, bytes) || bytes > in.size() - pos) return false;
  symbols.assign(count, 0);
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(in.data() + pos), size_t(bytes));
  buffer.set_bitstream_version(draco::kDracoMeshBitstreamVersion);  // the symbol format written today
  pos += size_t(bytes);
  return count == 0 || draco::DecodeSymbols(count, 1, &buffer, symbols.data());
}

uint32_t zigzag(int64_t v) { return v >= 0 ? uint32_t(2 * v) : uint32_t(-2 * v - 1); }
int64_t unzigzag(uint32_t v) { return (v & 1) ? -int64_t(v >> 1) - 1 : int64_t(v >> 1); }

Status check_face_sizes(DracoOrder& order, uint32_t max_face_size, std::string& error) {
  uint64_t triangles = 0;
  for (uint32_t& size : order.face_sizes) {
    if (uint64_t(size) + 3 > max_face_size) {
      error = "a face has " + std::to_string(uint64_t(size) + 3) + " vertices, more than ReadOptions::max_face_size";
      return Status::limit_exceeded;
    }
    size += 3;
    triangles += size - 2;
  }
  if (triangles != order.num_triangles) {
    error = "cagekit.order: face sizes do not add up to the triangle count";
    return Status::parse_error;
  }
  return Status::success;
}

bool decode_permutation(DracoOrder& order, std::string& error) {
  std::vector<uint8_t> seen(order.num_triangles, 0);
  int64_t previous = -1;
  for (uint32_t& t : order.original_triangle) {
    const int64_t value = previous + 1 + unzigzag(t);
    if (value < 0 || value >= int64_t(order.num_triangles) || seen[size_t(value)]) {
      error = "cagekit.order: triangle order is not a permutation";
      return false;
    }
    seen[size_t(value)] = 1;
    t = uint32_t(value);
    previous = value;
  }
  return true;
}

}  // namespace

std::vector<uint8_t> encode_draco_order(const DracoOrder& order) {
  std::vector<uint8_t> out;
  out.push_back(kOrderVersion);
  put_varint(out, order.num_vertices);
  put_varint(out, order.num_faces);
  put_varint(out, order.num_triangles);
  const uint8_t flags = uint8_t((order.face_sizes.empty() ? 0 : kHasFaceSizes) |
                                (order.original_triangle.empty() ? 0 : kHasPermutation) |
                                (order.rotation.empty() ? 0 : kHasRotation));
  out.push_back(flags);
  if (flags & kHasFaceSizes) {
    std::vector<uint32_t> sizes(order.face_sizes.size());
    for (size_t f = 0; f < sizes.size(); ++f) sizes[f] = order.face_sizes[f] - 3;
    put_symbols(out, sizes);
  }
  if (flags & kHasPermutation) {
    std::vector<uint32_t> deltas(order.original_triangle.size());
    int64_t previous = -1;
    for (size_t j = 0; j < deltas.size(); ++j) {
      deltas[j] = zigzag(int64_t(order.original_triangle[j]) - previous - 1);
      previous = order.original_triangle[j];
    }
    put_symbols(out, deltas);
  }
  if (flags & kHasRotation) put_symbols(out, order.rotation);
  return out;
}

Status decode_draco_order(const std::vector<uint8_t>& blob, uint32_t decoded_triangles, const ReadOptions& limits,
                          DracoOrder& order, std::string& error) {
  size_t pos = 0;
  uint64_t nv = 0, nf = 0, nt = 0;
  error = "malformed cagekit.order data";
  if (blob.empty() || blob[pos++] != kOrderVersion) return Status::parse_error;
  if (!get_varint(blob, pos, nv) || !get_varint(blob, pos, nf) || !get_varint(blob, pos, nt) || pos >= blob.size())
    return Status::parse_error;
  if (nt != decoded_triangles || nf > nt || nv > UINT32_MAX) {
    error = "cagekit.order does not match the decoded mesh";
    return Status::parse_error;
  }
  if (nv > limits.max_vertices || nf > limits.max_faces) {
    error = std::to_string(nv) + " vertices / " + std::to_string(nf) + " faces exceed the ReadOptions limits";
    return Status::limit_exceeded;
  }
  order.num_vertices = uint32_t(nv);
  order.num_faces = uint32_t(nf);
  order.num_triangles = uint32_t(nt);
  const uint8_t flags = blob[pos++];
  if (flags & ~(kHasFaceSizes | kHasPermutation | kHasRotation)) return Status::parse_error;
  if (flags & kHasFaceSizes) {
    if (!get_symbols(blob, pos, order.num_faces, order.face_sizes)) return Status::parse_error;
    const Status sizes = check_face_sizes(order, limits.max_face_size, error);
    if (sizes != Status::success) return sizes;
  } else if (nf != nt) {
    error = "cagekit.order: face count differs from triangle count but no face sizes";
    return Status::parse_error;
  }
  if (flags & kHasPermutation) {
    if (!get_symbols(blob, pos, order.num_triangles, order.original_triangle)) return Status::parse_error;
    if (!decode_permutation(order, error)) return Status::parse_error;
  }
  if (flags & kHasRotation) {
    if (!get_symbols(blob, pos, order.num_triangles, order.rotation)) return Status::parse_error;
    for (uint32_t r : order.rotation)
      if (r > 2) return Status::parse_error;
  }
  return pos == blob.size() ? Status::success : Status::parse_error;
}

}  // namespace io_detail
CAGEKIT_NAMESPACE_END
