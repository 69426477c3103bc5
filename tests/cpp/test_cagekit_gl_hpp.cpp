// SPDX-License-Identifier: GPL-3.0-or-later
// cagekit::GlDeformer (<cagekit/cagekit_gl.hpp>) in a headless EGL context (Mesa's surfaceless
// platform; llvmpipe without a GPU): the GPU deformation read back equals the CPU deformer's,
// the C++ loader's exception comes back from create, and GL errors are exceptions. Exits 77
// (skipped) when no GL 4.3 context can be made.
#define CAGEKIT_ENABLE_EXPERIMENTAL
#include <cagekit/cagekit_gl.hpp>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "egl_context.h"
#include "cpp_check.h"
#include "test_geometry.h"

namespace {

struct LoaderFailure {};

}  // namespace

int main() {
  EglContext egl(EglContext::Api::desktop_core, 4, 3);
  if (!egl.ok()) {
    std::printf("skipped: no EGL context: %s\n", egl.error().c_str());
    return 77;
  }
  cagekit::Context context = cagekit::Context::create();
  const Geometry g = sphere_geometry();
  cagekit::Mesh scan = context.create_mesh(g.positions, g.triangles);
  cagekit::Cage cube = context.create_mesh(kCube, kCubeQuads, 4).create_cage();
  cagekit::Cage fitted = cube.fit(scan).cage;
  cagekit::Binding binding = fitted.bind(scan);
  const cagekit_binding_info info = binding.info();
  std::vector<double> control = fitted.mesh().positions();
  control[3 * 7 + 0] += 0.2;
  control[3 * 2 + 2] -= 0.1;

  // The C++ loader: eglGetProcAddress behind a std::function.
  cagekit::GlDeformer gpu = cagekit::GlDeformer::create(
      binding, &scan, [](const char* name) -> cagekit_gl_proc { return eglGetProcAddress(name); });
  const cagekit_gl_deformer_info gl_info = gpu.info();
  const cagekit_gl_deformer_buffers buffers = gpu.buffers();
  CHECK(gl_info.vertex_count == kSphereVertices && gl_info.control_count == 8 &&
        gl_info.index_count == 3 * kSphereTriangles);
  CHECK(buffers.vertex_count == kSphereVertices && buffers.position_buffer != 0 && buffers.index_buffer != 0);
  gpu.deform(control);
  const cagekit::Deformed<double> read = gpu.read_back();
  CHECK(read.vertex_count == kSphereVertices && read.positions.size() == 3 * kSphereVertices);
  const cagekit::Deformed<double> cpu = binding.create_cpu_deformer(1).deform(control);
  double worst = 0;
  for (size_t i = 0; i < cpu.positions.size(); ++i) worst = std::max(worst, std::fabs(cpu.positions[i] - read.positions[i]));
  std::printf("%s (%s): GPU vs CPU positions %.3g of the diagonal\n", gl_info.renderer, gl_info.version,
              worst / info.bbox_diagonal);
  CHECK(worst < 1e-5 * info.bbox_diagonal);
  std::vector<double> positions(3 * kSphereVertices);
  CHECK(gpu.read_back(positions, nullptr) == kSphereVertices && positions == read.positions);

  // The C loader, and a shared second owner.
  cagekit::GlDeformer second = cagekit::GlDeformer::create(binding, nullptr, EglContext::get_proc_address, nullptr);
  cagekit::GlDeformer third = second.share();
  second.reset();
  third.deform(control);
  CHECK(third.buffers().index_buffer == 0);

  // Errors: exact normals are not done on the GPU; the loader's own exception comes back.
  bool caught = false;
  try {
    gpu.deform(control, CAGEKIT_NORMALS_EXACT);
  } catch (const cagekit::Error& e) {
    caught = e.status() == CAGEKIT_ERROR_UNSUPPORTED_FEATURE && std::string(e.message()).size() > 0;
  }
  CHECK(caught);
  caught = false;
  try {
    cagekit::GlDeformer::create(binding, &scan, [](const char* name) -> cagekit_gl_proc {
      if (std::string(name) == "glDispatchCompute") throw LoaderFailure();
      return eglGetProcAddress(name);
    });
  } catch (const LoaderFailure&) {
    caught = true;
  }
  CHECK(caught);

  // The experimental affine reference mode: frame points at their rest pose give the CPU rest pose.
  const std::vector<double> rest = fitted.mesh().positions();
  const std::vector<double> frame = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  gpu.set_reference_affine({7u}, frame, rest);
  gpu.deform_reference_affine(frame);
  const cagekit::Deformed<double> affine = gpu.read_back();
  const cagekit::Deformed<double> cpu_rest = binding.create_cpu_deformer(1).deform(rest);
  worst = 0;
  for (size_t i = 0; i < cpu_rest.positions.size(); ++i)
    worst = std::max(worst, std::fabs(cpu_rest.positions[i] - affine.positions[i]));
  CHECK(worst < 1e-5 * info.bbox_diagonal);
  gpu.set_reference_set({7u}, rest);
  gpu.deform_reference(rest);
  CHECK(gpu.read_back().vertex_count == kSphereVertices);

  if (g_failures != 0) {
    std::fprintf(stderr, "test_cagekit_gl_hpp: %d checks failed\n", g_failures);
    return 1;
  }
  std::printf("test_cagekit_gl_hpp: all checks passed\n");
  return 0;
}
