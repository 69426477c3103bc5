// SPDX-License-Identifier: GPL-3.0-or-later
// SubdivisionSurface on OpenSubdiv Far: feature-adaptive refinement, a double-precision
// PatchTable (regular B-spline patches, infinitely sharp patches, Gregory end caps) and a
// PatchMap to find the patch of a (ptex face, u, v). Every patch point (refined vertex or end-cap
// point) is folded back onto the cage's control vertices through a stencil table, which gives
// the basis functions phi_j of thesis (2.24)-(2.26). See README.md for the choice and accuracy.
#include "subdiv/subdivision_surface.h"

#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/status.h"
#include "subdiv/patch_basis.h"
#include "subdiv/opensubdiv_error_handler.h"
#include "subdiv/topology_refiner_factory.h"

CAGEKIT_NAMESPACE_BEGIN
namespace {

namespace Far = OpenSubdiv::Far;

// Semi-sharp creases (an extension of the thesis) are exact only once refined until their
// sharpness has decayed, so sharp features get at least that many levels; smooth
// extraordinary vertices stop at the isolation level.
int sharp_feature_level(const Cage& cage, int isolation_level) {
  float finite_max = 0.0f;
  for (const EdgeCrease& c : cage.creases)
    if (c.sharpness < kSharpnessInfinite) finite_max = std::max(finite_max, c.sharpness);
  for (const VertexCorner& c : cage.corners)
    if (c.sharpness < kSharpnessInfinite) finite_max = std::max(finite_max, c.sharpness);
  return std::min(kMaxIsolationLevel, std::max(isolation_level, static_cast<int>(std::ceil(finite_max))));
}

// The patch points and basis weights of one evaluation.
struct PatchWeights {
  int count = 0;
  Far::Index points[subdiv_detail::kMaxPatchPoints];
  subdiv_detail::PatchBasis w;  // w, wu, wv, wuu, wuv, wvv
};

// Compressed rows of weights over the control vertices, one row per derived patch point.
struct StencilRows {
  std::vector<uint32_t> offsets{0};
  std::vector<uint32_t> indices;
  std::vector<double> weights;

  void append(const Far::StencilTableReal<double>& table) {
    for (int i = 0; i < table.GetNumStencils(); ++i) {
      const auto stencil = table.GetStencil(i);
      for (int k = 0; k < stencil.GetSize(); ++k) {
        indices.push_back(static_cast<uint32_t>(stencil.GetVertexIndices()[k]));
        weights.push_back(stencil.GetWeights()[k]);
      }
      offsets.push_back(static_cast<uint32_t>(indices.size()));
    }
  }
  size_t size() const { return offsets.size() - 1; }
};

// Sums of the six basis weights per control vertex (hash table with linear probing).
class WeightAccumulator {
 public:
  double* slot(uint32_t key) {
    if (2 * (used_ + 1) > keys_.size()) grow();
    size_t i = hash(key);
    while (keys_[i] != key && keys_[i] != kEmpty) i = (i + 1) & (keys_.size() - 1);
    if (keys_[i] == kEmpty) {
      keys_[i] = key;
      ++used_;
    }
    return &sums_[6 * i];
  }

  BasisWeights sorted_weights() const {
    std::vector<std::pair<uint32_t, size_t>> order;
    order.reserve(used_);
    for (size_t i = 0; i < keys_.size(); ++i)
      if (keys_[i] != kEmpty) order.push_back({keys_[i], i});
    std::sort(order.begin(), order.end());
    BasisWeights out;
    std::vector<double>* blocks[6] = {&out.w, &out.wu, &out.wv, &out.wuu, &out.wuv, &out.wvv};
    out.indices.reserve(order.size());
    for (auto* b : blocks) b->reserve(order.size());
    for (const auto& [key, i] : order) {
      out.indices.push_back(key);
      for (int k = 0; k < 6; ++k) blocks[k]->push_back(sums_[6 * i + k]);
    }
    return out;
  }

 private:
  static constexpr uint32_t kEmpty = 0xffffffffu;  // control indices are < 2^31
  size_t hash(uint32_t key) const { return (key * 2654435761u) & (keys_.size() - 1); }
  void grow() {
    std::vector<uint32_t> keys;
    std::vector<double> sums;
    keys.swap(keys_);
    sums.swap(sums_);
    keys_.assign(std::max<size_t>(64, 2 * keys.size()), kEmpty);
    sums_.assign(6 * keys_.size(), 0.0);
    used_ = 0;
    for (size_t i = 0; i < keys.size(); ++i)
      if (keys[i] != kEmpty) std::copy_n(&sums[6 * i], 6, slot(keys[i]));
  }

  std::vector<uint32_t> keys_;
  std::vector<double> sums_;
  size_t used_ = 0;
};

}  // namespace

struct SubdivisionSurface::Impl {
  std::vector<Vec3> control;           // the cage's positions
  std::vector<uint32_t> first_ptex;    // per base face, plus one past the end
  std::vector<uint32_t> ptex_to_face;  // per ptex face
  std::unique_ptr<const Far::PatchTable> patches;
  std::unique_ptr<const Far::PatchMap> patch_map;
  // Patch point p >= control.size() (a vertex of a refined level or a local end-cap point) is
  // row p - control.size() of `derived`; derived_points are those rows applied to `control`.
  StencilRows derived;
  std::vector<Vec3> derived_points;

  uint32_t num_ptex() const { return static_cast<uint32_t>(ptex_to_face.size()); }
  uint32_t num_control() const { return static_cast<uint32_t>(control.size()); }

  void build(const Cage& cage, const SurfaceOptions& options);
  void patch_weights(uint32_t ptex, double u, double v, PatchWeights* out) const;

  template <typename Visit>  // visit(control index, weight) for the stencil of one patch point
  void for_each_control(Far::Index point, double weight, Visit&& visit) const {
    if (point < static_cast<Far::Index>(control.size())) {
      visit(static_cast<uint32_t>(point), weight);
      return;
    }
    const size_t row = static_cast<size_t>(point) - control.size();
    for (uint32_t k = derived.offsets[row]; k < derived.offsets[row + 1]; ++k)
      visit(derived.indices[k], weight * derived.weights[k]);
  }
};

void SubdivisionSurface::Impl::build(const Cage& cage, const SurfaceOptions& options) {
  auto refiner = subdiv_detail::create_topology_refiner(cage);
  control = cage.mesh.positions;

  const size_t num_faces = cage.mesh.num_faces();
  const Far::PtexIndices ptex(*refiner);
  first_ptex.resize(num_faces + 1);
  ptex_to_face.resize(static_cast<size_t>(ptex.GetNumFaces()));
  for (size_t f = 0; f < num_faces; ++f) {
    const uint32_t first = static_cast<uint32_t>(ptex.GetFaceId(static_cast<Far::Index>(f)));
    const uint32_t count = cage.mesh.face_size(f) == 4 ? 1 : cage.mesh.face_size(f);
    first_ptex[f] = first;
    for (uint32_t k = 0; k < count; ++k) ptex_to_face[first + k] = static_cast<uint32_t>(f);
  }
  first_ptex[num_faces] = num_ptex();

  const int sharp_level = sharp_feature_level(cage, options.isolation_level);
  Far::TopologyRefiner::AdaptiveOptions adaptive(sharp_level);
  adaptive.secondaryLevel = static_cast<unsigned>(options.isolation_level);
  adaptive.useInfSharpPatch = true;  // crease curves become exact B-spline boundaries
  adaptive.useSingleCreasePatch = false;
  subdiv_detail::begin_opensubdiv_call();
  refiner->RefineAdaptive(adaptive);

  Far::PatchTableFactory::Options patch_options(sharp_level);
  patch_options.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
  patch_options.useInfSharpPatch = true;
  patch_options.useSingleCreasePatch = false;
  patch_options.generateLegacySharpCornerPatches = false;
  patch_options.generateVaryingTables = false;
  patch_options.generateVaryingLocalPoints = false;
  patch_options.SetPatchPrecision<double>();
  patches.reset(Far::PatchTableFactory::Create(*refiner, patch_options));
  if (!patches)
    fail(Status::invalid_mesh, "OpenSubdiv could not build the patches of the cage: " +
                                   subdiv_detail::last_opensubdiv_message());
  patch_map.reset(new Far::PatchMap(*patches));

  // Stencils of every refined vertex over the control vertices, then of the end-cap points.
  using StencilFactory = Far::StencilTableFactoryReal<double>;
  StencilFactory::Options stencil_options;
  stencil_options.generateOffsets = true;
  stencil_options.generateControlVerts = false;
  stencil_options.generateIntermediateLevels = true;
  stencil_options.factorizeIntermediateLevels = true;
  stencil_options.maxLevel = static_cast<unsigned>(refiner->GetMaxLevel());
  std::unique_ptr<const Far::StencilTableReal<double>> refined(StencilFactory::Create(*refiner, stencil_options));
  const Far::StencilTableReal<double>* local = patches->GetLocalPointStencilTable<double>();
  std::unique_ptr<const Far::StencilTableReal<double>> all;
  if (local && local->GetNumStencils() > 0)
    all.reset(StencilFactory::AppendLocalPointStencilTable(*refiner, refined.get(), local));
  const Far::StencilTableReal<double>* table = all ? all.get() : refined.get();
  const size_t expected = static_cast<size_t>(refiner->GetNumVerticesTotal()) - control.size() +
                          static_cast<size_t>(local ? local->GetNumStencils() : 0);
  if (!table || static_cast<size_t>(table->GetNumStencils()) != expected)
    fail(Status::internal_error, "OpenSubdiv's stencil tables do not cover the patch points: " +
                                     subdiv_detail::last_opensubdiv_message());
  subdiv_detail::fail_on_opensubdiv_error(Status::invalid_mesh, "OpenSubdiv could not build the limit surface");
  derived.append(*table);

  derived_points.assign(derived.size(), Vec3());
  for (size_t row = 0; row < derived.size(); ++row)
    for (uint32_t k = derived.offsets[row]; k < derived.offsets[row + 1]; ++k)
      derived_points[row] += control[derived.indices[k]] * derived.weights[k];
}

void SubdivisionSurface::Impl::patch_weights(uint32_t ptex, double u, double v, PatchWeights* out) const {
  if (ptex >= num_ptex())
    fail(Status::invalid_argument, "ptex face " + std::to_string(ptex) + " out of range (the surface has " +
                                       std::to_string(num_ptex()) + ")");
  if (!(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0))
    fail(Status::invalid_argument, "(u, v) = (" + std::to_string(u) + ", " + std::to_string(v) +
                                       ") is outside [0,1]^2");
  const Far::PatchMap::Handle* handle = patch_map->FindPatch(static_cast<int>(ptex), u, v);
  if (!handle)
    fail(Status::invalid_argument, "ptex face " + std::to_string(ptex) + " lies in hole face " +
                                       std::to_string(ptex_to_face[ptex]) + ", which has no limit surface");
  const auto points = patches->GetPatchVertices(*handle);
  out->count = subdiv_detail::patch_basis(patches->GetPatchDescriptor(*handle).GetType(),
                                          patches->GetPatchParam(*handle), u, v, out->w);
  if (points.size() < out->count)
    fail(Status::internal_error, "OpenSubdiv patch with " + std::to_string(points.size()) + " points");
  for (int i = 0; i < out->count; ++i) out->points[i] = points[i];
}

SubdivisionSurface::SubdivisionSurface(const Cage& cage, const SurfaceOptions& options) : impl_(new Impl) {
  if (options.isolation_level < 1 || options.isolation_level > kMaxIsolationLevel)
    fail(Status::invalid_argument, "isolation_level must be in [1, " + std::to_string(kMaxIsolationLevel) +
                                       "], got " + std::to_string(options.isolation_level));
  impl_->build(cage, options);
}

SubdivisionSurface::~SubdivisionSurface() = default;
SubdivisionSurface::SubdivisionSurface(SubdivisionSurface&&) noexcept = default;
SubdivisionSurface& SubdivisionSurface::operator=(SubdivisionSurface&&) noexcept = default;

uint32_t SubdivisionSurface::num_control_vertices() const { return impl_->num_control(); }

uint32_t SubdivisionSurface::num_ptex_faces() const { return impl_->num_ptex(); }

uint32_t SubdivisionSurface::ptex_face(uint32_t base_face, uint32_t corner) const {
  const uint32_t num_faces = static_cast<uint32_t>(impl_->first_ptex.size() - 1);
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
  PatchWeights pw;
  impl_->patch_weights(ptex_face, u, v, &pw);
  Vec3 result[6];
  const Far::Index num_control = static_cast<Far::Index>(impl_->control.size());
  for (int i = 0; i < pw.count; ++i) {
    const Far::Index p = pw.points[i];
    const Vec3& point = p < num_control ? impl_->control[p] : impl_->derived_points[p - num_control];
    for (int k = 0; k < 6; ++k) result[k] += point * pw.w[k][i];
  }
  return {result[0], result[1], result[2], result[3], result[4], result[5]};
}

SurfacePoint SubdivisionSurface::evaluate(uint32_t ptex_face, double u, double v,
                                          const std::vector<Vec3>& control) const {
  if (control.size() != impl_->control.size())
    fail(Status::invalid_argument, "expected " + std::to_string(impl_->control.size()) +
                                       " control positions, got " + std::to_string(control.size()));
  PatchWeights pw;
  impl_->patch_weights(ptex_face, u, v, &pw);
  Vec3 result[6];
  for (int i = 0; i < pw.count; ++i) {
    Vec3 point;
    impl_->for_each_control(pw.points[i], 1.0, [&](uint32_t j, double weight) { point += control[j] * weight; });
    for (int k = 0; k < 6; ++k) result[k] += point * pw.w[k][i];
  }
  return {result[0], result[1], result[2], result[3], result[4], result[5]};
}

BasisWeights SubdivisionSurface::basis(uint32_t ptex_face, double u, double v) const {
  PatchWeights pw;
  impl_->patch_weights(ptex_face, u, v, &pw);
  // phi_j = sum over patch points i of (basis weight of i) * (stencil weight of j in i). Near
  // extraordinary vertices the patch points' stencils overlap heavily (a thousand terms over
  // about a hundred control vertices), so terms are summed in a small open-addressing table.
  WeightAccumulator sums;
  for (int i = 0; i < pw.count; ++i)
    impl_->for_each_control(pw.points[i], 1.0, [&](uint32_t j, double weight) {
      double* slot = sums.slot(j);
      for (int k = 0; k < 6; ++k) slot[k] += weight * pw.w[k][i];
    });
  return sums.sorted_weights();
}

CAGEKIT_NAMESPACE_END
