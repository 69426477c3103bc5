// SPDX-License-Identifier: GPL-3.0-or-later
// SubdivisionSurface on OpenSubdiv Bfr: one Bfr::Surface<double> per base face, built once at
// construction; evaluation asks it for limit stencils over the cage's control vertices
// (Surface::EvaluateStencil), which gives position, derivatives and basis weights alike.
// See README.md for why Bfr rather than Far::PatchTable, and for the accuracy measured.
#include "subdiv/subdivision_surface.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/ptexIndices.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/status.h"
#include "subdiv/opensubdiv_error_handler.h"
#include "subdiv/topology_refiner_factory.h"

CAGEKIT_NAMESPACE_BEGIN
namespace {

namespace Bfr = OpenSubdiv::Bfr;
namespace Far = OpenSubdiv::Far;

constexpr int kMaxIsolationLevel = 10;

// Semi-sharp creases (an extension of the thesis) are only exact once refined until their
// sharpness has decayed, so the sharp features get at least that many levels.
int sharp_feature_level(const Cage& cage, int isolation_level) {
  float finite_max = 0.0f;
  for (const EdgeCrease& c : cage.creases)
    if (c.sharpness < kSharpnessInfinite) finite_max = std::max(finite_max, c.sharpness);
  for (const VertexCorner& c : cage.corners)
    if (c.sharpness < kSharpnessInfinite) finite_max = std::max(finite_max, c.sharpness);
  return std::min(kMaxIsolationLevel, std::max(isolation_level, static_cast<int>(std::ceil(finite_max))));
}

// The weights of one evaluation, over the control points of one face's Bfr::Surface.
struct Stencil {
  std::vector<int> indices;
  std::vector<double> weights;  // 6 blocks of indices.size(): w, wu, wv, wuu, wuv, wvv
  size_t size() const { return indices.size(); }
  const double* block(int k) const { return weights.data() + k * indices.size(); }
};

}  // namespace

struct SubdivisionSurface::Impl {
  std::vector<Vec3> control;                 // the cage's positions
  std::vector<Bfr::Surface<double>> faces;   // per base face; invalid for holes
  std::vector<uint32_t> first_ptex;          // per base face, plus one past the end
  std::vector<uint32_t> ptex_to_face;        // per ptex face

  uint32_t num_ptex() const { return static_cast<uint32_t>(ptex_to_face.size()); }

  void stencil(uint32_t ptex, double u, double v, Stencil* out) const {
    if (ptex >= num_ptex())
      fail(Status::invalid_argument, "ptex face " + std::to_string(ptex) + " out of range (the surface has " +
                                         std::to_string(num_ptex()) + ")");
    if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0))
      fail(Status::invalid_argument, "(u, v) = (" + std::to_string(u) + ", " + std::to_string(v) +
                                         ") is outside [0,1]^2");
    const uint32_t face = ptex_to_face[ptex];
    const Bfr::Surface<double>& surface = faces[face];
    if (!surface.IsValid())
      fail(Status::invalid_argument, "ptex face " + std::to_string(ptex) + " lies in hole face " +
                                         std::to_string(face) + ", which has no limit surface");
    double uv[2] = {u, v};
    double scale = 1.0;  // d(face coordinate) / d(ptex coordinate)
    const Bfr::Parameterization param = surface.GetParameterization();
    if (param.HasSubFaces()) {
      // Bfr tiles an n-gon's sub-faces at half size in one (u,v) domain; its normalized
      // sub-face coordinates are the ptex coordinates.
      const double sub[2] = {u, v};
      param.ConvertNormalizedSubFaceToCoord<double>(static_cast<int>(ptex - first_ptex[face]), sub, uv);
      scale = 0.5;
    }
    const size_t n = static_cast<size_t>(surface.GetNumControlPoints());
    out->indices.resize(n);
    out->weights.resize(6 * n);
    surface.GetControlPointIndices(out->indices.data());
    double* w = out->weights.data();
    surface.EvaluateStencil(uv, w, w + n, w + 2 * n, w + 3 * n, w + 4 * n, w + 5 * n);
    if (scale != 1.0) {
      for (size_t i = n; i < 3 * n; ++i) w[i] *= scale;
      for (size_t i = 3 * n; i < 6 * n; ++i) w[i] *= scale * scale;
    }
  }
};

SubdivisionSurface::SubdivisionSurface(const Cage& cage, const SurfaceOptions& options) : impl_(new Impl) {
  if (options.isolation_level < 0 || options.isolation_level > kMaxIsolationLevel)
    fail(Status::invalid_argument, "isolation_level must be in [0, " + std::to_string(kMaxIsolationLevel) +
                                       "], got " + std::to_string(options.isolation_level));
  auto refiner = subdiv_detail::create_topology_refiner(cage);
  impl_->control = cage.mesh.positions;

  const size_t num_faces = cage.mesh.num_faces();
  Far::PtexIndices ptex(*refiner);
  impl_->first_ptex.resize(num_faces + 1);
  impl_->ptex_to_face.resize(static_cast<size_t>(ptex.GetNumFaces()));
  for (size_t f = 0; f < num_faces; ++f) {
    const uint32_t first = static_cast<uint32_t>(ptex.GetFaceId(static_cast<Far::Index>(f)));
    const uint32_t count = cage.mesh.face_size(f) == 4 ? 1 : cage.mesh.face_size(f);
    impl_->first_ptex[f] = first;
    for (uint32_t k = 0; k < count; ++k) impl_->ptex_to_face[first + k] = static_cast<uint32_t>(f);
  }
  impl_->first_ptex[num_faces] = impl_->num_ptex();

  Bfr::RefinerSurfaceFactory<>::Options factory_options;
  factory_options.SetApproxLevelSmooth(options.isolation_level);
  factory_options.SetApproxLevelSharp(sharp_feature_level(cage, options.isolation_level));
  subdiv_detail::begin_opensubdiv_call();
  const Bfr::RefinerSurfaceFactory<> factory(*refiner, factory_options);
  impl_->faces.resize(num_faces);
  for (size_t f = 0; f < num_faces; ++f) {
    const auto face = static_cast<Bfr::SurfaceFactory::Index>(f);
    if (!factory.FaceHasLimitSurface(face)) continue;  // a hole
    if (!factory.InitVertexSurface<double>(face, &impl_->faces[f])) {
      const std::string why = subdiv_detail::last_opensubdiv_message();
      fail(Status::invalid_mesh, "OpenSubdiv could not build the limit surface of face " + std::to_string(f) +
                                     (why.empty() ? std::string() : ": " + why));
    }
  }
}

SubdivisionSurface::~SubdivisionSurface() = default;
SubdivisionSurface::SubdivisionSurface(SubdivisionSurface&&) noexcept = default;
SubdivisionSurface& SubdivisionSurface::operator=(SubdivisionSurface&&) noexcept = default;

uint32_t SubdivisionSurface::num_control_vertices() const { return static_cast<uint32_t>(impl_->control.size()); }

uint32_t SubdivisionSurface::num_ptex_faces() const { return impl_->num_ptex(); }

uint32_t SubdivisionSurface::ptex_face(uint32_t base_face, uint32_t corner) const {
  const uint32_t num_faces = static_cast<uint32_t>(impl_->faces.size());
  if (base_face >= num_faces)
    fail(Status::invalid_argument, "base face " + std::to_string(base_face) + " out of range (the cage has " +
                                       std::to_string(num_faces) + ")");
  const uint32_t count = impl_->first_ptex[base_face + 1] - impl_->first_ptex[base_face];
  if (corner >= count)
    fail(Status::invalid_argument, "base face " + std::to_string(base_face) + " has " + std::to_string(count) +
                                       " ptex faces; corner " + std::to_string(corner) + " does not exist");
  return impl_->first_ptex[base_face] + corner;
}

uint32_t SubdivisionSurface::base_face_of_ptex(uint32_t ptex_face) const {
  if (ptex_face >= impl_->num_ptex())
    fail(Status::invalid_argument, "ptex face " + std::to_string(ptex_face) + " out of range");
  return impl_->ptex_to_face[ptex_face];
}

SurfacePoint SubdivisionSurface::evaluate(uint32_t ptex_face, double u, double v) const {
  return evaluate(ptex_face, u, v, impl_->control);
}

SurfacePoint SubdivisionSurface::evaluate(uint32_t ptex_face, double u, double v,
                                          const std::vector<Vec3>& control) const {
  if (control.size() != impl_->control.size())
    fail(Status::invalid_argument, "expected " + std::to_string(impl_->control.size()) +
                                       " control positions, got " + std::to_string(control.size()));
  Stencil stencil;
  impl_->stencil(ptex_face, u, v, &stencil);
  Vec3 result[6];
  for (int k = 0; k < 6; ++k) {
    const double* w = stencil.block(k);
    for (size_t i = 0; i < stencil.size(); ++i) result[k] += control[stencil.indices[i]] * w[i];
  }
  return {result[0], result[1], result[2], result[3], result[4], result[5]};
}

BasisWeights SubdivisionSurface::basis(uint32_t ptex_face, double u, double v) const {
  Stencil stencil;
  impl_->stencil(ptex_face, u, v, &stencil);
  // A control vertex may occur more than once among a surface's control points (small or
  // non-manifold cages): merge its weights so that each phi_j appears once.
  std::vector<std::pair<int, size_t>> order(stencil.size());
  for (size_t i = 0; i < stencil.size(); ++i) order[i] = {stencil.indices[i], i};
  std::sort(order.begin(), order.end());
  BasisWeights out;
  std::vector<double>* blocks[6] = {&out.w, &out.wu, &out.wv, &out.wuu, &out.wuv, &out.wvv};
  for (size_t i = 0; i < order.size(); ++i) {
    const bool same_as_previous = i > 0 && order[i].first == order[i - 1].first;
    if (!same_as_previous) {
      out.indices.push_back(static_cast<uint32_t>(order[i].first));
      for (auto* b : blocks) b->push_back(0.0);
    }
    for (int k = 0; k < 6; ++k) blocks[k]->back() += stencil.block(k)[order[i].second];
  }
  return out;
}

CAGEKIT_NAMESPACE_END
