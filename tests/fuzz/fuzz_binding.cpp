// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: saved bindings (.ckb) from arbitrary bytes through the C API:
//   cagekit_binding_read_memory -> get_info -> get_cage -> CPU deformer (deform with the cage's
//   own positions) -> write_memory -> read that back -> write again (must give the same bytes)
//   -> release everything.
// Must never crash, trip a sanitizer or leak; INVALID_INTERNAL is treated as a bug.
// Seeds: tests/fuzz/corpus/fuzz_binding (small bindings written by `cagekit bind`).
#include <cagekit/cagekit.h>

#include <cstdint>
#include <cstring>
#include <vector>

#define FUZZ_CHECK(cond) \
  do {                   \
    if (!(cond)) __builtin_trap(); \
  } while (0)

namespace {

cagekit_context context() {
  static cagekit_context c = [] {
    cagekit_context made = nullptr;
    cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
    desc.memory_budget_bytes = uint64_t(512) << 20;  // hostile counts must fail, not exhaust memory
    FUZZ_CHECK(cagekit_context_create(&desc, &made) == CAGEKIT_SUCCESS);
    return made;
  }();
  return c;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  cagekit_binding binding = nullptr;
  const cagekit_status s = cagekit_binding_read_memory(context(), data, size, 1, &binding);
  FUZZ_CHECK(s != CAGEKIT_ERROR_INTERNAL);
  if (s != CAGEKIT_SUCCESS) {
    FUZZ_CHECK(binding == nullptr);
    return 0;
  }
  cagekit_binding_info info;
  info.struct_size = sizeof(info);
  FUZZ_CHECK(cagekit_binding_get_info(binding, &info) == CAGEKIT_SUCCESS);
  cagekit_cage cage = nullptr;
  FUZZ_CHECK(cagekit_binding_get_cage(binding, &cage) == CAGEKIT_SUCCESS);
  cagekit_mesh mesh = nullptr;
  FUZZ_CHECK(cagekit_cage_get_mesh(cage, &mesh) == CAGEKIT_SUCCESS);
  uint32_t count = 0;
  FUZZ_CHECK(cagekit_mesh_get_positions(mesh, CAGEKIT_SCALAR_FLOAT64, 0, &count, nullptr) == CAGEKIT_SUCCESS);
  FUZZ_CHECK(count == info.control_count);
  std::vector<double> control(3 * size_t(count));
  FUZZ_CHECK(cagekit_mesh_get_positions(mesh, CAGEKIT_SCALAR_FLOAT64, count, &count, control.data()) ==
             CAGEKIT_SUCCESS);
  cagekit_cpu_deformer deformer = nullptr;
  FUZZ_CHECK(cagekit_cpu_deformer_create(binding, 1, &deformer) == CAGEKIT_SUCCESS);
  std::vector<double> positions(3 * size_t(info.vertex_count)), normals(positions.size());
  uint32_t written = 0;
  const cagekit_status d = cagekit_cpu_deformer_deform(deformer, control.data(), count, CAGEKIT_NORMALS_APPROXIMATE,
                                                       info.vertex_count, &written, positions.data(), normals.data());
  FUZZ_CHECK(d != CAGEKIT_ERROR_INTERNAL);
  // Round trip: what the library writes it reads back, and writes again byte for byte.
  cagekit_blob first = nullptr, second = nullptr;
  FUZZ_CHECK(cagekit_binding_write_memory(binding, &first) == CAGEKIT_SUCCESS);
  cagekit_binding again = nullptr;
  FUZZ_CHECK(cagekit_binding_read_memory(context(), cagekit_blob_data(first), cagekit_blob_size(first), 1, &again) ==
             CAGEKIT_SUCCESS);
  FUZZ_CHECK(cagekit_binding_write_memory(again, &second) == CAGEKIT_SUCCESS);
  FUZZ_CHECK(cagekit_blob_size(first) == cagekit_blob_size(second) &&
             std::memcmp(cagekit_blob_data(first), cagekit_blob_data(second), cagekit_blob_size(first)) == 0);
  cagekit_blob_release(second);
  cagekit_blob_release(first);
  cagekit_binding_release(again);
  cagekit_cpu_deformer_release(deformer);
  cagekit_mesh_release(mesh);
  cagekit_cage_release(cage);
  cagekit_binding_release(binding);
  return 0;
}
