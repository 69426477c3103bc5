// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The GPU part of `cagekit bench-deform`: a headless EGL context (Mesa surfaceless: llvmpipe
// without a GPU), a cagekit::GlDeformer of the binding, `frames` full deformations (each waited
// for with glFinish). Never throws; when no context can be made, `why` says so.
#include <string>
#include <vector>

#include <cagekit/cagekit.hpp>

namespace cli {

struct GpuBench {
  bool ran = false;
  double fps = 0;
  std::string renderer, version;
  std::string why;  // when !ran
};

GpuBench bench_gpu_deformer(const cagekit::Context& context, const cagekit::Binding& binding,
                            const cagekit::Mesh& scan, std::vector<double> control, int frames, double step);

}  // namespace cli
