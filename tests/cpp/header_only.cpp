// SPDX-License-Identifier: GPL-3.0-or-later
// Compiles the C++ layer alone with -std=c++17 -Wall -Wextra -pedantic -Werror: both headers, the GL
// one with its experimental part, and (never run) a use of every handle type's and View's templates
// so that their bodies are checked too.
#define CAGEKIT_ENABLE_EXPERIMENTAL
#include <cagekit/cagekit_gl.hpp>
#include <cagekit/cagekit.hpp>  // twice: include guards

#include <array>
#include <vector>

namespace {

template <class H>
void use_handle(const cagekit::Context& context) {
  H empty;
  H shared = empty.share();
  H adopted = H::adopt(shared.release(), context);
  H borrowed = H::borrow(adopted.get(), context);
  borrowed = std::move(adopted);
  borrowed.reset();
}

}  // namespace

void instantiate_everything() {
  cagekit::Context context = cagekit::Context::create();
  use_handle<cagekit::Mesh>(context);
  use_handle<cagekit::Cage>(context);
  use_handle<cagekit::Surface>(context);
  use_handle<cagekit::Hierarchy>(context);
  use_handle<cagekit::Binding>(context);
  use_handle<cagekit::CpuDeformer>(context);
  use_handle<cagekit::LimitPatches>(context);
  use_handle<cagekit::LimitSurfaces>(context);
  use_handle<cagekit::Blob>(context);
  use_handle<cagekit::GlDeformer>(context);
  cagekit::Context second = context.share();

  std::vector<double> values(9);
  const std::vector<double> inputs(9);
  std::array<uint32_t, 3> indices = {0, 1, 2};
  double raw[3] = {0, 0, 0};
  cagekit::View<double> out = values;
  cagekit::View<const double> in = inputs;
  cagekit::View<const double> from_out = out;
  cagekit::View<const uint32_t> list = {0u, 1u};
  cagekit::View<const uint32_t> array = indices;
  cagekit::View<double> c_array = raw;
  (void)from_out, (void)list, (void)array, (void)c_array, (void)in;

  cagekit::Mesh mesh = context.create_mesh(inputs, indices);
  cagekit::CpuDeformer deformer;
  deformer.deform(inputs, CAGEKIT_NORMALS_APPROXIMATE, values, nullptr);
  deformer.deform_f32(inputs);
  std::vector<float> floats(9);
  deformer.update_f32(inputs, {0u}, CAGEKIT_NORMALS_APPROXIMATE, floats, floats);
  cagekit::GlDeformer gl = cagekit::GlDeformer::create(cagekit::Binding(), &mesh,
                                                       [](const char*) -> cagekit_gl_proc { return nullptr; });
  gl.read_back(values, nullptr);
  gl.set_reference_affine({0u}, std::vector<double>(12), inputs);
  cagekit::Cage::ScanToCage result = cagekit::scan_to_cage(mesh);
  (void)result;
}

int main() { return 0; }
