// SPDX-License-Identifier: GPL-3.0-or-later
// SubdivisionSurface on OpenSubdiv Far: feature-adaptive refinement to a low isolation level, a
// double-precision PatchTable whose regular patches are exact bicubic B-splines and whose
// irregular faces (bilinear end-cap placeholders) are evaluated exactly with Stam's method when
// their extraordinary vertex is smooth and interior (stam_patch.h), and with OpenSubdiv's
// Gregory end caps otherwise (built on a sub-cage around those faces only). Every patch point
// is folded back onto the cage's control vertices through stencil rows, which gives the basis
// functions phi_j of thesis (2.24)-(2.26). See README.md for the choices and the accuracy.
#include "core/memory_budget.h"
#include "subdiv/subdivision_surface.h"

#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "core/parallel_for.h"
#include "core/status.h"
#include "subdiv/opensubdiv_error_handler.h"
#include "subdiv/patch_basis.h"
#include "subdiv/stam_patch.h"
#include "subdiv/topology_refiner_factory.h"

CAGEKIT_NAMESPACE_BEGIN
namespace {

namespace Far = OpenSubdiv::Far;
using subdiv_detail::PatchBasis;

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

// Adaptive refinement and the patch table of a cage (the refiner is refined in place).
std::unique_ptr<const Far::PatchTable> build_patches(Far::TopologyRefiner& refiner, int sharp_level,
                                                     int isolation_level,
                                                     Far::PatchTableFactory::Options::EndCapType end_caps) {
  Far::TopologyRefiner::AdaptiveOptions adaptive(sharp_level);
  adaptive.secondaryLevel = static_cast<unsigned>(isolation_level);
  adaptive.useInfSharpPatch = true;  // crease curves become exact B-spline boundaries
  adaptive.useSingleCreasePatch = false;
  subdiv_detail::begin_opensubdiv_call();
  refiner.RefineAdaptive(adaptive);

  Far::PatchTableFactory::Options patch_options(sharp_level);
  patch_options.SetEndCapType(end_caps);
  patch_options.useInfSharpPatch = true;
  patch_options.useSingleCreasePatch = false;
  patch_options.generateLegacySharpCornerPatches = false;
  patch_options.generateVaryingTables = false;
  patch_options.generateVaryingLocalPoints = false;
  patch_options.SetPatchPrecision<double>();
  std::unique_ptr<const Far::PatchTable> patches(Far::PatchTableFactory::Create(refiner, patch_options));
  if (!patches)
    fail(Status::invalid_mesh, "OpenSubdiv could not build the patches of the cage: " +
                                   subdiv_detail::last_opensubdiv_message());
  return patches;
}

// Stencils of every refined vertex of levels 1.. over the level-0 vertices (null when there
// are none).
std::unique_ptr<const Far::StencilTableReal<double>> refined_stencils(const Far::TopologyRefiner& refiner) {
  if (refiner.GetMaxLevel() == 0) return nullptr;
  using StencilFactory = Far::StencilTableFactoryReal<double>;
  StencilFactory::Options options;
  options.generateOffsets = true;
  options.generateControlVerts = false;
  options.generateIntermediateLevels = true;
  options.factorizeIntermediateLevels = true;
  options.maxLevel = static_cast<unsigned>(refiner.GetMaxLevel());
  std::unique_ptr<const Far::StencilTableReal<double>> table(StencilFactory::Create(refiner, options));
  if (!table || table->GetNumStencils() != refiner.GetNumVerticesTotal() - refiner.GetLevel(0).GetNumVertices())
    fail(Status::internal_error, "OpenSubdiv's stencil table does not cover the refined vertices: " +
                                     subdiv_detail::last_opensubdiv_message());
  return table;
}

// Compressed rows of weights over the control vertices, one row per derived patch point.
struct StencilRows {
  std::vector<uint32_t> offsets{0};
  std::vector<uint32_t> indices;
  std::vector<double> weights;

  // One row; `remap` (when given) maps the stencil's vertex indices to control vertices.
  void append_row(const Far::StencilReal<double>& stencil, const std::vector<uint32_t>* remap) {
    for (int k = 0; k < stencil.GetSize(); ++k) {
      const uint32_t j = static_cast<uint32_t>(stencil.GetVertexIndices()[k]);
      indices.push_back(remap ? (*remap)[j] : j);
      weights.push_back(stencil.GetWeights()[k]);
    }
    offsets.push_back(static_cast<uint32_t>(indices.size()));
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

// The patch points and basis weights of one evaluation; points are unified point ids (see Impl).
struct PatchWeights {
  int count = 0;
  std::vector<uint32_t> points;
  std::vector<double> w;  // w[k * count + i], k = value, d/du, d/dv, d2/du2, d2/dudv, d2/dv2
  void resize(int n) {
    count = n;
    points.resize(static_cast<size_t>(n));
    w.resize(6 * static_cast<size_t>(n));
  }
};

enum class PatchKind : uint8_t { regular, stam, gregory };

// A unified point id not assigned yet (refined vertices and Gregory patch points get one when a
// patch uses them).
constexpr uint32_t kUnusedPoint = std::numeric_limits<uint32_t>::max();

struct PatchInfo {
  PatchKind kind = PatchKind::regular;
  uint8_t rotation = 0;   // Stam: patch corner of the extraordinary vertex
  uint32_t matrices = 0;  // Stam: index into Impl::stam
  uint32_t first = 0;     // regular and Stam: first of its ids in Impl::patch_points
};

// OpenSubdiv's Gregory end caps for the faces whose irregular patches are not Stam patches,
// built on the sub-cage of those faces and three rings of faces around them (enough for every
// refined point of their patches to be computed from complete neighbourhoods, so the patches
// equal those of the whole cage).
// End-cap faces from which the Gregory region is built as two regions (on two threads when the
// surface options allow).
constexpr size_t kSplitGregoryRegionFaces = 64;

struct GregoryRegion {
  std::unique_ptr<const Far::PatchTable> patches;
  std::unique_ptr<const Far::PatchMap> patch_map;
  std::vector<int32_t> sub_face;       // per cage face: its face in the sub-cage, or -1
  std::vector<uint32_t> sub_first_ptex;  // per sub-cage face
  std::vector<uint32_t> point_id;      // per patch point of the sub-cage: unified point id
  StencilRows rows;                    // the region's derived rows until they join `derived`
};

// What classifying the irregular patches collects besides the Impl's tables.
struct IrregularPatches {
  std::vector<int> stam_of_valence;  // per valence: its matrices in Impl::stam, or -1
  std::vector<uint32_t> seed_faces;  // the cage faces of the Gregory patches
  std::vector<int> local;            // scratch: the points of one Stam patch
};

}  // namespace

struct SubdivisionSurface::Impl {
  std::vector<Vec3> control;           // the cage's positions
  std::vector<uint32_t> first_ptex;    // per base face, plus one past the end
  std::vector<uint32_t> ptex_to_face;  // per ptex face
  std::unique_ptr<const Far::PatchTable> patches;
  std::unique_ptr<const Far::PatchMap> patch_map;
  std::vector<PatchInfo> info;          // per patch of `patches`
  std::vector<uint32_t> patch_points;   // unified point ids of the regular and Stam patches
  std::vector<subdiv_detail::StamMatrices> stam;
  // Gregory regions (sub-cages refined around sharp extraordinary vertices) and, per cage
  // face, the region whose end caps it uses (-1: none).
  std::vector<GregoryRegion> gregory;
  std::vector<int32_t> gregory_of_face;
  // Unified point id p: a control vertex for p < control.size(), else row p - control.size() of
  // `derived` (a refined vertex some patch uses, or a Gregory end-cap point); derived_points
  // are those rows applied to `control`.
  StencilRows derived;
  std::vector<Vec3> derived_points;

  uint32_t num_ptex() const { return static_cast<uint32_t>(ptex_to_face.size()); }
  uint32_t num_control() const { return static_cast<uint32_t>(control.size()); }

  void build(const Cage& cage, const SurfaceOptions& options);
  // The steps of build().
  void index_ptex_faces(const Cage& cage, const Far::TopologyRefiner& refiner);
  // Per patch of `patches`: its kind, and the points of the regular and Stam patches in
  // `patch_points` (refined vertices by their index over all levels until derive_refined_rows).
  // Returns the cage faces of the Gregory patches.
  std::vector<uint32_t> classify_patches(const Far::TopologyRefiner& refiner, const std::vector<int>& level_offset);
  // A bilinear end cap: a Stam patch when its face's corners are those of a quad of its level
  // whose irregular corner gathers a Stam neighbourhood, else a Gregory patch.
  void classify_irregular_patch(const Far::TopologyRefiner& refiner, const std::vector<int>& level_offset,
                                const Far::StencilTableReal<double>* copies, Far::ConstIndexArray points,
                                const Far::PatchParam& param, PatchInfo& pi, IrregularPatches& irregular);
  uint32_t stam_matrices_of_valence(int valence, IrregularPatches& irregular);  // built on first use
  void derive_refined_rows(const Far::TopologyRefiner& refiner, int num_vertices_total);
  void build_gregory_regions(const Cage& cage, const SurfaceOptions& options, int sharp_level,
                             std::vector<uint32_t> seed_faces);
  void join_gregory_rows(const std::vector<std::vector<uint32_t>>& groups, size_t num_faces);
  void evaluate_derived_points();
  // Builds region `g` around `seed_faces` (3 rings added); its derived rows stay in g.rows
  // with point ids num_control() + local row (joined to `derived` afterwards). Touches nothing
  // else of the Impl, so regions can be built on several threads.
  void build_gregory_region(const Cage& cage, const std::vector<uint32_t>& seed_faces, int sharp_level,
                            int isolation_level, GregoryRegion& g) const;
  // The patch of the whole cage at a location (errors for bad faces/params/holes), and for the
  // faces of a Gregory region the sub-cage's patch there.
  const Far::PatchMap::Handle& find_patch(uint32_t ptex, double u, double v) const;
  const Far::PatchMap::Handle& find_gregory_patch(uint32_t ptex, double u, double v,
                                                  const GregoryRegion** region) const;
  PatchDomain patch_domain(uint32_t ptex, double u, double v) const;
  // kinds: 1 = only the values are needed (the derivative weights of Stam patches stay 0).
  void patch_weights(uint32_t ptex, double u, double v, PatchWeights* out, int kinds = 6) const;

  template <typename Visit>  // visit(control index, weight) for the stencil of one point id
  void for_each_control(uint32_t point, double weight, Visit&& visit) const {
    if (point < control.size()) {
      visit(point, weight);
      return;
    }
    const size_t row = static_cast<size_t>(point) - control.size();
    for (uint32_t k = derived.offsets[row]; k < derived.offsets[row + 1]; ++k)
      visit(derived.indices[k], weight * derived.weights[k]);
  }
};

namespace {

// Measured peaks (bunny cages with crease tags): ~12 KB per face-vertex at isolation level 2,
// plus ~10 KB per face-vertex and level of the isolation around sharp extraordinary vertices.
void check_surface_memory(const Cage& cage, const SurfaceOptions& options) {
  const bool sharp = !cage.creases.empty() || !cage.corners.empty() || !cage.holes.empty();
  const uint64_t per_face_vertex =
      12 * 1024 + (sharp ? uint64_t(std::max(0, options.sharp_extraordinary_isolation_level - 2)) * 10 * 1024 : 0);
  check_memory_estimate(estimate_product(cage.mesh.num_face_vertices(), per_face_vertex),
                        "the limit surface's patch table");
}

// Per refinement level, the index of its first vertex over all levels; back(): all vertices.
std::vector<int> refined_level_offsets(const Far::TopologyRefiner& refiner) {
  std::vector<int> level_offset{0};
  for (int l = 0; l <= refiner.GetMaxLevel(); ++l)
    level_offset.push_back(level_offset.back() + refiner.GetLevel(l).GetNumVertices());
  return level_offset;
}

// The corner vertices of a bilinear end cap's face in the patch's order, as vertex indices of
// its refinement level `level` (v); false when one of them is not a vertex of that level.
bool end_cap_corners(Far::ConstIndexArray points, const Far::StencilTableReal<double>* copies,
                     const std::vector<int>& level_offset, int level, const Far::TopologyLevel& topology, int v[4]) {
  bool same_level = true;
  for (int i = 0; i < 4; ++i) {
    v[i] = points[i];
    if (v[i] >= level_offset.back()) {
      // A local point: the limit point of the face's corner; its stencil (over the
      // refined vertices) weighs that corner most.
      if (!copies || v[i] - level_offset.back() >= copies->GetNumStencils())
        fail(Status::internal_error, "unexpected bilinear end-cap point");
      const auto limit = copies->GetStencil(v[i] - level_offset.back());
      int best = 0;
      for (int k = 1; k < limit.GetSize(); ++k)
        if (limit.GetWeights()[k] > limit.GetWeights()[best]) best = k;
      v[i] = limit.GetSize() > 0 ? limit.GetVertexIndices()[best] : -1;
    }
    v[i] -= level_offset[level];
    same_level = same_level && v[i] >= 0 && v[i] < topology.GetNumVertices();
  }
  return same_level;
}

// The quad of `topology` with corners v[0..3] in this cyclic order (v[0] its corner `shift`);
// -1 when there is none.
int find_quad(const Far::TopologyLevel& topology, const int v[4], int& shift) {
  int face = -1;
  for (int f : topology.GetVertexFaces(v[0])) {
    const auto fv = topology.GetFaceVertices(f);
    if (fv.size() != 4) continue;
    for (int k = 0; k < 4 && face < 0; ++k)
      if (fv[k] == v[0] && fv[(k + 1) % 4] == v[1] && fv[(k + 2) % 4] == v[2] && fv[(k + 3) % 4] == v[3])
        face = f, shift = k;
  }
  return face;
}

// The first of the corners v[0..3] at an extraordinary or boundary vertex (0 when none is).
int irregular_corner(const Far::TopologyLevel& topology, const int v[4]) {
  int corner = 0;
  for (int r = 3; r >= 0; --r)
    if (topology.GetVertexFaces(v[r]).size() != 4 || topology.IsVertexBoundary(v[r])) corner = r;
  return corner;
}

// The seed faces of the Gregory regions (sorted, unique) as one group, or with many end-cap
// faces two groups (two regions, built at once when options.threads allows), split at the
// median of the faces' centroids along the bounding box's longest axis. The split does not
// depend on the thread count, so neither do the results.
std::vector<std::vector<uint32_t>> gregory_region_groups(const PolygonMesh& mesh, std::vector<uint32_t> seed_faces) {
  std::sort(seed_faces.begin(), seed_faces.end());
  seed_faces.erase(std::unique(seed_faces.begin(), seed_faces.end()), seed_faces.end());
  std::vector<std::vector<uint32_t>> groups(1, seed_faces);
  if (seed_faces.size() >= kSplitGregoryRegionFaces) {
    std::vector<Vec3> centroid(mesh.num_faces());
    BoundingBox box;
    for (uint32_t f : seed_faces) {
      Vec3 c;
      for (uint32_t k = 0; k < mesh.face_size(f); ++k) c += mesh.positions[mesh.face_vertex(f, k)];
      centroid[f] = c * (1.0 / mesh.face_size(f));
      box.extend(centroid[f]);
    }
    const Vec3 extent = box.max - box.min;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    std::vector<uint32_t> order = seed_faces;
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
      return centroid[a][axis] < centroid[b][axis] || (centroid[a][axis] == centroid[b][axis] && a < b);
    });
    const size_t half = order.size() / 2;
    groups = {std::vector<uint32_t>(order.begin(), order.begin() + long(half)),
              std::vector<uint32_t>(order.begin() + long(half), order.end())};
  }
  return groups;
}

}  // namespace

void SubdivisionSurface::Impl::build(const Cage& cage, const SurfaceOptions& options) {
  check_surface_memory(cage, options);
  auto refiner = subdiv_detail::create_topology_refiner(cage);
  control = cage.mesh.positions;
  index_ptex_faces(cage, *refiner);
  // Irregular faces get bilinear placeholders (their four corner vertices, no local points):
  // CageKit replaces them by Stam patches or Gregory end caps.
  const int sharp_level = sharp_feature_level(cage, options.isolation_level);
  patches = build_patches(*refiner, sharp_level, options.isolation_level,
                          Far::PatchTableFactory::Options::ENDCAP_BILINEAR_BASIS);
  patch_map.reset(new Far::PatchMap(*patches));
  const std::vector<int> level_offset = refined_level_offsets(*refiner);
  std::vector<uint32_t> seed_faces = classify_patches(*refiner, level_offset);
  derive_refined_rows(*refiner, level_offset.back());
  refiner.reset();
  subdiv_detail::fail_on_opensubdiv_error(Status::invalid_mesh, "OpenSubdiv could not build the limit surface");
  if (!seed_faces.empty()) build_gregory_regions(cage, options, sharp_level, std::move(seed_faces));
  evaluate_derived_points();
}

void SubdivisionSurface::Impl::index_ptex_faces(const Cage& cage, const Far::TopologyRefiner& refiner) {
  const size_t num_faces = cage.mesh.num_faces();
  const Far::PtexIndices ptex(refiner);
  first_ptex.resize(num_faces + 1);
  ptex_to_face.resize(static_cast<size_t>(ptex.GetNumFaces()));
  for (size_t f = 0; f < num_faces; ++f) {
    const uint32_t first = static_cast<uint32_t>(ptex.GetFaceId(static_cast<Far::Index>(f)));
    const uint32_t count = cage.mesh.face_size(f) == 4 ? 1 : cage.mesh.face_size(f);
    first_ptex[f] = first;
    for (uint32_t k = 0; k < count; ++k) ptex_to_face[first + k] = static_cast<uint32_t>(f);
  }
  first_ptex[num_faces] = num_ptex();
}

std::vector<uint32_t> SubdivisionSurface::Impl::classify_patches(const Far::TopologyRefiner& refiner,
                                                                 const std::vector<int>& level_offset) {
  // OpenSubdiv 3.5 gives bilinear end caps local points (the limit points of their corners).
  const Far::StencilTableReal<double>* copies = patches->GetLocalPointStencilTable<double>();
  IrregularPatches irregular;
  info.resize(static_cast<size_t>(patches->GetNumPatchesTotal()));
  size_t patch = 0;
  for (int a = 0; a < patches->GetNumPatchArrays(); ++a) {
    const Far::PatchDescriptor::Type type = patches->GetPatchArrayDescriptor(a).GetType();
    for (int p = 0; p < patches->GetNumPatches(a); ++p, ++patch) {
      const auto points = patches->GetPatchVertices(a, p);
      PatchInfo& pi = info[patch];
      pi.first = static_cast<uint32_t>(patch_points.size());
      if (type == Far::PatchDescriptor::REGULAR) {
        for (int i = 0; i < 16; ++i) patch_points.push_back(static_cast<uint32_t>(points[i]));
        continue;
      }
      const Far::PatchParam param = patches->GetPatchParam(a, p);
      if (type != Far::PatchDescriptor::QUADS || points.size() != 4)
        fail(Status::internal_error, "unexpected OpenSubdiv patch type " + std::to_string(static_cast<int>(type)));
      classify_irregular_patch(refiner, level_offset, copies, points, param, pi, irregular);
    }
  }
  return std::move(irregular.seed_faces);
}

void SubdivisionSurface::Impl::classify_irregular_patch(const Far::TopologyRefiner& refiner,
                                                        const std::vector<int>& level_offset,
                                                        const Far::StencilTableReal<double>* copies,
                                                        Far::ConstIndexArray points, const Far::PatchParam& param,
                                                        PatchInfo& pi, IrregularPatches& irregular) {
  // The irregular face: its level, and its corner vertices in the patch's order.
  const int level = param.GetDepth();
  if (level > refiner.GetMaxLevel()) fail(Status::internal_error, "end cap below the refined levels");
  const Far::TopologyLevel& topology = refiner.GetLevel(level);
  int v[4];
  const bool same_level = end_cap_corners(points, copies, level_offset, level, topology, v);
  int shift = 0;
  const int face = same_level ? find_quad(topology, v, shift) : -1;
  const int corner = face >= 0 ? irregular_corner(topology, v) : 0;
  std::vector<int>& local = irregular.local;
  if (face >= 0 && subdiv_detail::gather_stam_points(topology, face, (corner + shift) % 4, false, &local)) {
    const uint32_t matrices = stam_matrices_of_valence((static_cast<int>(local.size()) - 8) / 2, irregular);
    pi.kind = PatchKind::stam;
    pi.rotation = static_cast<uint8_t>(corner);
    pi.matrices = matrices;
    for (int x : local) patch_points.push_back(static_cast<uint32_t>(x + level_offset[level]));
  } else {
    pi.kind = PatchKind::gregory;
    irregular.seed_faces.push_back(ptex_to_face.at(static_cast<size_t>(param.GetFaceId())));
  }
}

uint32_t SubdivisionSurface::Impl::stam_matrices_of_valence(int valence, IrregularPatches& irregular) {
  std::vector<int>& stam_of_valence = irregular.stam_of_valence;
  if (static_cast<int>(stam_of_valence.size()) <= valence) stam_of_valence.resize(valence + 1, -1);
  if (stam_of_valence[valence] < 0) {
    stam_of_valence[valence] = static_cast<int>(stam.size());
    stam.push_back(subdiv_detail::build_stam_matrices(valence));
  }
  return static_cast<uint32_t>(stam_of_valence[valence]);
}

// Unified ids: cage vertices keep theirs, the refined vertices the patches use get rows.
void SubdivisionSurface::Impl::derive_refined_rows(const Far::TopologyRefiner& refiner, int num_vertices_total) {
  std::vector<uint32_t> refined_id(static_cast<size_t>(num_vertices_total), kUnusedPoint);
  std::unique_ptr<const Far::StencilTableReal<double>> table = refined_stencils(refiner);
  const uint32_t nc = num_control();
  for (uint32_t& p : patch_points) {
    if (p < nc) continue;
    uint32_t& id = refined_id[p];
    if (id == kUnusedPoint) {
      id = nc + static_cast<uint32_t>(derived.size());
      derived.append_row(table->GetStencil(static_cast<Far::Index>(p - nc)), nullptr);
    }
    p = id;
  }
}

void SubdivisionSurface::Impl::build_gregory_regions(const Cage& cage, const SurfaceOptions& options, int sharp_level,
                                                     std::vector<uint32_t> seed_faces) {
  const std::vector<std::vector<uint32_t>> groups = gregory_region_groups(cage.mesh, std::move(seed_faces));
  const int region_level = std::max(options.isolation_level, options.sharp_extraordinary_isolation_level);
  gregory.resize(groups.size());
  const size_t workers = std::min<size_t>(groups.size(), size_t(std::max(options.threads, 1)));
  run_ranges(groups.size(), workers, [&](size_t begin, size_t end, size_t) {
    for (size_t r = begin; r < end; ++r) {
      subdiv_detail::begin_opensubdiv_call();  // per-thread diagnostics
      build_gregory_region(cage, groups[r], std::max(sharp_level, region_level), region_level, gregory[r]);
    }
  });
  join_gregory_rows(groups, cage.mesh.num_faces());
}

// Joins the regions' rows to `derived`, in region order.
void SubdivisionSurface::Impl::join_gregory_rows(const std::vector<std::vector<uint32_t>>& groups, size_t num_faces) {
  const uint32_t nc = num_control();
  gregory_of_face.assign(num_faces, -1);
  for (size_t r = 0; r < gregory.size(); ++r) {
    GregoryRegion& g = gregory[r];
    const uint32_t base = static_cast<uint32_t>(derived.size());
    for (uint32_t& id : g.point_id)
      if (id != kUnusedPoint && id >= nc) id += base;
    for (size_t row = 0; row < g.rows.size(); ++row) {
      derived.indices.insert(derived.indices.end(), g.rows.indices.begin() + g.rows.offsets[row],
                             g.rows.indices.begin() + g.rows.offsets[row + 1]);
      derived.weights.insert(derived.weights.end(), g.rows.weights.begin() + g.rows.offsets[row],
                             g.rows.weights.begin() + g.rows.offsets[row + 1]);
      derived.offsets.push_back(static_cast<uint32_t>(derived.indices.size()));
    }
    g.rows = StencilRows();
    for (uint32_t f : groups[r]) gregory_of_face[f] = static_cast<int32_t>(r);
  }
}

void SubdivisionSurface::Impl::evaluate_derived_points() {
  derived_points.assign(derived.size(), Vec3());
  for (size_t row = 0; row < derived.size(); ++row)
    for (uint32_t k = derived.offsets[row]; k < derived.offsets[row + 1]; ++k)
      derived_points[row] += control[derived.indices[k]] * derived.weights[k];
}

void SubdivisionSurface::Impl::build_gregory_region(const Cage& cage, const std::vector<uint32_t>& seed_faces,
                                                    int sharp_level, int isolation_level, GregoryRegion& g) const {
  const PolygonMesh& mesh = cage.mesh;
  const size_t num_faces = mesh.num_faces();
  std::vector<uint32_t> vertex_face_offsets(mesh.num_vertices() + 1, 0), vertex_faces;
  for (uint32_t v : mesh.face_vertices) ++vertex_face_offsets[v + 1];
  for (size_t v = 0; v < mesh.num_vertices(); ++v) vertex_face_offsets[v + 1] += vertex_face_offsets[v];
  vertex_faces.resize(mesh.face_vertices.size());
  {
    std::vector<uint32_t> fill(vertex_face_offsets.begin(), vertex_face_offsets.end() - 1);
    for (size_t f = 0; f < num_faces; ++f)
      for (uint32_t k = 0; k < mesh.face_size(f); ++k) vertex_faces[fill[mesh.face_vertex(f, k)]++] = static_cast<uint32_t>(f);
  }
  std::vector<char> in_region(num_faces, 0);
  std::vector<uint32_t> frontier;
  for (uint32_t f : seed_faces)
    if (!in_region[f]) in_region[f] = 1, frontier.push_back(f);
  for (int ring = 0; ring < 3; ++ring) {
    std::vector<uint32_t> next;
    for (uint32_t f : frontier)
      for (uint32_t k = 0; k < mesh.face_size(f); ++k) {
        const uint32_t v = mesh.face_vertex(f, k);
        for (uint32_t i = vertex_face_offsets[v]; i < vertex_face_offsets[v + 1]; ++i)
          if (!in_region[vertex_faces[i]]) in_region[vertex_faces[i]] = 1, next.push_back(vertex_faces[i]);
      }
    frontier.swap(next);
  }

  Cage sub;
  sub.boundary = cage.boundary;
  std::vector<int64_t> sub_vertex(mesh.num_vertices(), -1);
  std::vector<uint32_t> cage_vertex;
  g.sub_face.assign(num_faces, -1);
  std::vector<uint32_t> face;
  for (size_t f = 0; f < num_faces; ++f) {
    if (!in_region[f]) continue;
    face.clear();
    for (uint32_t k = 0; k < mesh.face_size(f); ++k) {
      const uint32_t v = mesh.face_vertex(f, k);
      if (sub_vertex[v] < 0) {
        sub_vertex[v] = static_cast<int64_t>(cage_vertex.size());
        cage_vertex.push_back(v);
        sub.mesh.add_vertex(mesh.positions[v]);
      }
      face.push_back(static_cast<uint32_t>(sub_vertex[v]));
    }
    g.sub_face[f] = static_cast<int32_t>(sub.mesh.num_faces());
    sub.mesh.add_face(face.data(), face.size());
  }
  // Tags inside the region: creases on edges of the sub-cage, corners, holes.
  std::vector<std::pair<uint32_t, uint32_t>> sub_edges;
  for (size_t f = 0; f < sub.mesh.num_faces(); ++f)
    for (uint32_t k = 0, n = sub.mesh.face_size(f); k < n; ++k) {
      const uint32_t a = sub.mesh.face_vertex(f, k), b = sub.mesh.face_vertex(f, (k + 1) % n);
      sub_edges.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(sub_edges.begin(), sub_edges.end());
  for (const EdgeCrease& c : cage.creases) {
    if (c.v0 >= sub_vertex.size() || c.v1 >= sub_vertex.size() || sub_vertex[c.v0] < 0 || sub_vertex[c.v1] < 0) continue;
    const uint32_t a = static_cast<uint32_t>(sub_vertex[c.v0]), b = static_cast<uint32_t>(sub_vertex[c.v1]);
    if (std::binary_search(sub_edges.begin(), sub_edges.end(), std::make_pair(std::min(a, b), std::max(a, b))))
      sub.creases.push_back({a, b, c.sharpness});
  }
  for (const VertexCorner& c : cage.corners)
    if (c.vertex < sub_vertex.size() && sub_vertex[c.vertex] >= 0)
      sub.corners.push_back({static_cast<uint32_t>(sub_vertex[c.vertex]), c.sharpness});
  for (uint32_t h : cage.holes)
    if (h < num_faces && g.sub_face[h] >= 0) sub.holes.push_back(static_cast<uint32_t>(g.sub_face[h]));

  auto refiner = subdiv_detail::create_topology_refiner(sub);
  const Far::PtexIndices ptex(*refiner);
  for (size_t f = 0; f < sub.mesh.num_faces(); ++f)
    g.sub_first_ptex.push_back(static_cast<uint32_t>(ptex.GetFaceId(static_cast<Far::Index>(f))));
  g.patches = build_patches(*refiner, sharp_level, isolation_level,
                            Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
  g.patch_map.reset(new Far::PatchMap(*g.patches));

  // Ids of the sub-cage's patch points: its vertices are cage vertices, its refined vertices
  // and local end-cap points get rows (over cage vertices) when a patch uses them.
  std::unique_ptr<const Far::StencilTableReal<double>> table = refined_stencils(*refiner);
  const Far::StencilTableReal<double>* local_points = g.patches->GetLocalPointStencilTable<double>();
  std::unique_ptr<const Far::StencilTableReal<double>> local;
  if (local_points && local_points->GetNumStencils() > 0) {
    local.reset(Far::StencilTableFactoryReal<double>::AppendLocalPointStencilTable(*refiner, table.get(),
                                                                                   local_points));
    if (!local) fail(Status::internal_error, "OpenSubdiv could not fold the end-cap points onto the cage");
  }
  const size_t sub_control = cage_vertex.size();
  const size_t num_refined = static_cast<size_t>(refiner->GetNumVerticesTotal()) - sub_control;
  const size_t num_local = local_points ? static_cast<size_t>(local_points->GetNumStencils()) : 0;
  g.point_id.assign(sub_control + num_refined + num_local, kUnusedPoint);
  for (size_t v = 0; v < sub_control; ++v) g.point_id[v] = cage_vertex[v];
  const auto all_points = g.patches->GetPatchControlVerticesTable();
  for (int p : all_points) {
    uint32_t& id = g.point_id.at(static_cast<size_t>(p));
    if (id != kUnusedPoint) continue;
    id = num_control() + static_cast<uint32_t>(g.rows.size());
    const size_t row = static_cast<size_t>(p) - sub_control;
    if (!local && !table) fail(Status::internal_error, "Gregory patch point without a stencil");
    // AppendLocalPointStencilTable returns the refined rows followed by the local ones.
    g.rows.append_row(local ? local->GetStencil(static_cast<Far::Index>(row))
                             : table->GetStencil(static_cast<Far::Index>(row)),
                       &cage_vertex);
  }
  subdiv_detail::fail_on_opensubdiv_error(Status::invalid_mesh, "OpenSubdiv could not build the limit surface");
}

const Far::PatchMap::Handle& SubdivisionSurface::Impl::find_patch(uint32_t ptex, double u, double v) const {
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
  return *handle;
}

const Far::PatchMap::Handle& SubdivisionSurface::Impl::find_gregory_patch(uint32_t ptex, double u, double v,
                                                                         const GregoryRegion** region) const {
  const uint32_t face = ptex_to_face[ptex];
  if (gregory_of_face.empty() || gregory_of_face[face] < 0)
    fail(Status::internal_error, "end-cap face outside the Gregory regions");
  const GregoryRegion& g = gregory[static_cast<size_t>(gregory_of_face[face])];
  const int32_t sub_face = g.sub_face[face];
  if (sub_face < 0) fail(Status::internal_error, "end-cap face outside the Gregory region");
  const uint32_t sub_ptex = g.sub_first_ptex[static_cast<size_t>(sub_face)] + (ptex - first_ptex[face]);
  const Far::PatchMap::Handle* sub_handle = g.patch_map->FindPatch(static_cast<int>(sub_ptex), u, v);
  if (!sub_handle) fail(Status::internal_error, "no Gregory patch found for an end-cap face");
  *region = &g;
  return *sub_handle;
}

PatchDomain SubdivisionSurface::Impl::patch_domain(uint32_t ptex, double u, double v) const {
  const Far::PatchMap::Handle& handle = find_patch(ptex, u, v);
  const PatchInfo& pi = info[static_cast<size_t>(handle.patchIndex)];
  Far::PatchParam param = patches->GetPatchParam(handle);
  bool polynomial = pi.kind == PatchKind::regular;
  if (pi.kind == PatchKind::gregory) {
    const GregoryRegion* g = nullptr;
    const Far::PatchMap::Handle& sub = find_gregory_patch(ptex, u, v, &g);
    param = g->patches->GetPatchParam(sub);
    polynomial = g->patches->GetPatchDescriptor(sub).GetType() == Far::PatchDescriptor::REGULAR;
  }
  PatchDomain d;
  d.size = param.GetParamFraction();
  d.u0 = param.GetU() * d.size;
  d.v0 = param.GetV() * d.size;
  d.polynomial = polynomial;
  return d;
}

void SubdivisionSurface::Impl::patch_weights(uint32_t ptex, double u, double v, PatchWeights* out, int kinds) const {
  const Far::PatchMap::Handle* handle = &find_patch(ptex, u, v);
  const PatchInfo& pi = info[static_cast<size_t>(handle->patchIndex)];
  const Far::PatchParam param = patches->GetPatchParam(*handle);
  const double scale = 1.0 / param.GetParamFraction();  // d(patch) / d(ptex)
  if (pi.kind == PatchKind::regular) {
    PatchBasis w;
    subdiv_detail::patch_basis(Far::PatchDescriptor::REGULAR, param, u, v, w);
    out->resize(16);
    for (int i = 0; i < 16; ++i) {
      out->points[i] = patch_points[pi.first + i];
      for (int k = 0; k < 6; ++k) out->w[k * 16 + i] = w[k][i];
    }
    return;
  }
  if (pi.kind == PatchKind::stam) {
    const subdiv_detail::StamMatrices& m = stam[pi.matrices];
    const int n = m.size();
    double x = u, y = v;
    param.Normalize(x, y);
    // (s, t): the patch's frame rotated so that the extraordinary corner is at (0, 0);
    // J = d(s, t) / d(x, y).
    static constexpr double kJ[4][4] = {{1, 0, 0, 1}, {0, 1, -1, 0}, {-1, 0, 0, -1}, {0, -1, 1, 0}};
    const double* j = kJ[pi.rotation];  // s_x, s_y, t_x, t_y
    const double s = pi.rotation == 0 ? x : pi.rotation == 1 ? y : pi.rotation == 2 ? 1 - x : 1 - y;
    const double t = pi.rotation == 0 ? y : pi.rotation == 1 ? 1 - x : pi.rotation == 2 ? 1 - y : x;
    thread_local std::vector<double> w;  // scratch: no allocation per evaluation
    w.resize(6 * static_cast<size_t>(n));
    subdiv_detail::stam_basis(m, std::clamp(s, 0.0, 1.0), std::clamp(t, 0.0, 1.0), w.data(), kinds);
    out->resize(n);
    for (int i = 0; i < n; ++i) {
      out->points[i] = patch_points[pi.first + i];
      const double gs = w[n + i], gt = w[2 * n + i], gss = w[3 * n + i], gst = w[4 * n + i], gtt = w[5 * n + i];
      out->w[i] = w[i];
      out->w[n + i] = scale * (gs * j[0] + gt * j[2]);
      out->w[2 * n + i] = scale * (gs * j[1] + gt * j[3]);
      out->w[3 * n + i] = scale * scale * (gss * j[0] * j[0] + 2 * gst * j[0] * j[2] + gtt * j[2] * j[2]);
      out->w[4 * n + i] = scale * scale * (gss * j[0] * j[1] + gst * (j[0] * j[3] + j[1] * j[2]) + gtt * j[2] * j[3]);
      out->w[5 * n + i] = scale * scale * (gss * j[1] * j[1] + 2 * gst * j[1] * j[3] + gtt * j[3] * j[3]);
    }
    return;
  }
  // Gregory end cap (or a regular patch) of the sub-cage.
  const GregoryRegion* region = nullptr;
  const Far::PatchMap::Handle* sub_handle = &find_gregory_patch(ptex, u, v, &region);
  const GregoryRegion& g = *region;
  const auto points = g.patches->GetPatchVertices(*sub_handle);
  PatchBasis w;
  const int count = subdiv_detail::patch_basis(g.patches->GetPatchDescriptor(*sub_handle).GetType(),
                                               g.patches->GetPatchParam(*sub_handle), u, v, w);
  if (points.size() < count)
    fail(Status::internal_error, "OpenSubdiv patch with " + std::to_string(points.size()) + " points");
  out->resize(count);
  for (int i = 0; i < count; ++i) {
    out->points[i] = g.point_id[static_cast<size_t>(points[i])];
    for (int k = 0; k < 6; ++k) out->w[k * count + i] = w[k][i];
  }
}

SubdivisionSurface::SubdivisionSurface(const Cage& cage, const SurfaceOptions& options) : impl_(new Impl) {
  if (options.sharp_extraordinary_isolation_level < 1 ||
      options.sharp_extraordinary_isolation_level > kMaxIsolationLevel)
    fail(Status::invalid_argument, "sharp_extraordinary_isolation_level must be in [1, " +
                                       std::to_string(kMaxIsolationLevel) + "]");
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

bool SubdivisionSurface::has_limit_surface(uint32_t ptex_face) const {
  if (ptex_face >= impl_->num_ptex())
    fail(Status::invalid_argument, "ptex face " + std::to_string(ptex_face) + " out of range");
  return impl_->patch_map->FindPatch(static_cast<int>(ptex_face), 0.5, 0.5) != nullptr;
}

SurfacePoint SubdivisionSurface::evaluate(uint32_t ptex_face, double u, double v) const {
  thread_local PatchWeights pw;
  impl_->patch_weights(ptex_face, u, v, &pw);
  Vec3 result[6];
  const uint32_t num_control = impl_->num_control();
  for (int i = 0; i < pw.count; ++i) {
    const uint32_t p = pw.points[i];
    const Vec3& point = p < num_control ? impl_->control[p] : impl_->derived_points[p - num_control];
    for (int k = 0; k < 6; ++k) result[k] += point * pw.w[k * pw.count + i];
  }
  return {result[0], result[1], result[2], result[3], result[4], result[5]};
}

SurfacePoint SubdivisionSurface::evaluate(uint32_t ptex_face, double u, double v,
                                          const std::vector<Vec3>& control) const {
  if (control.size() != impl_->control.size())
    fail(Status::invalid_argument, "expected " + std::to_string(impl_->control.size()) +
                                       " control positions, got " + std::to_string(control.size()));
  thread_local PatchWeights pw;
  impl_->patch_weights(ptex_face, u, v, &pw);
  Vec3 result[6];
  for (int i = 0; i < pw.count; ++i) {
    Vec3 point;
    impl_->for_each_control(pw.points[i], 1.0, [&](uint32_t j, double weight) { point += control[j] * weight; });
    for (int k = 0; k < 6; ++k) result[k] += point * pw.w[k * pw.count + i];
  }
  return {result[0], result[1], result[2], result[3], result[4], result[5]};
}

std::vector<Vec3> SubdivisionSurface::patch_points(const std::vector<Vec3>& control) const {
  const Impl& m = *impl_;
  if (control.size() != m.control.size())
    fail(Status::invalid_argument, "expected " + std::to_string(m.control.size()) + " control positions, got " +
                                       std::to_string(control.size()));
  std::vector<Vec3> points(control.size() + m.derived.size());
  std::copy(control.begin(), control.end(), points.begin());
  for (size_t row = 0; row < m.derived.size(); ++row) {
    Vec3 p;
    for (uint32_t k = m.derived.offsets[row]; k < m.derived.offsets[row + 1]; ++k)
      p += control[m.derived.indices[k]] * m.derived.weights[k];
    points[control.size() + row] = p;
  }
  return points;
}

SurfacePoint SubdivisionSurface::evaluate_patch_points(uint32_t ptex_face, double u, double v,
                                                       const std::vector<Vec3>& points) const {
  if (points.size() != impl_->control.size() + impl_->derived.size())
    fail(Status::invalid_argument, "patch point array of the wrong size");
  thread_local PatchWeights pw;
  impl_->patch_weights(ptex_face, u, v, &pw);
  Vec3 result[6];
  for (int i = 0; i < pw.count; ++i) {
    const Vec3& point = points[pw.points[i]];
    for (int k = 0; k < 6; ++k) result[k] += point * pw.w[k * pw.count + i];
  }
  return {result[0], result[1], result[2], result[3], result[4], result[5]};
}

Vec3 SubdivisionSurface::evaluate_position(uint32_t ptex_face, double u, double v,
                                           const std::vector<Vec3>& points) const {
  if (points.size() != impl_->control.size() + impl_->derived.size())
    fail(Status::invalid_argument, "patch point array of the wrong size");
  thread_local PatchWeights pw;
  impl_->patch_weights(ptex_face, u, v, &pw, 1);
  Vec3 result;
  for (int i = 0; i < pw.count; ++i) result += points[pw.points[i]] * pw.w[i];
  return result;
}

void SubdivisionSurface::patch_point_weights(uint32_t ptex_face, double u, double v, std::vector<uint32_t>& points,
                                             std::vector<double>& weights) const {
  thread_local PatchWeights pw;
  impl_->patch_weights(ptex_face, u, v, &pw, 1);
  points.assign(pw.points.begin(), pw.points.begin() + pw.count);
  weights.assign(pw.w.begin(), pw.w.begin() + pw.count);
}

void SubdivisionSurface::basis_values(uint32_t ptex_face, double u, double v, std::vector<uint32_t>& indices,
                                      std::vector<double>& weights) const {
  thread_local PatchWeights pw;
  impl_->patch_weights(ptex_face, u, v, &pw, 1);
  // Dense per-thread accumulator over the control vertices; slot[j] = position in the output + 1.
  thread_local std::vector<uint32_t> slot;
  if (slot.size() < impl_->control.size()) slot.assign(impl_->control.size(), 0);
  indices.clear();
  weights.clear();
  for (int i = 0; i < pw.count; ++i) {
    const double wi = pw.w[i];
    if (wi == 0) continue;
    impl_->for_each_control(pw.points[i], wi, [&](uint32_t j, double weight) {
      if (slot[j] == 0) {
        indices.push_back(j);
        weights.push_back(0.0);
        slot[j] = static_cast<uint32_t>(indices.size());
      }
      weights[slot[j] - 1] += weight;
    });
  }
  for (uint32_t j : indices) slot[j] = 0;
}

PatchDomain SubdivisionSurface::patch_domain(uint32_t ptex_face, double u, double v) const {
  return impl_->patch_domain(ptex_face, u, v);
}

BasisWeights SubdivisionSurface::basis(uint32_t ptex_face, double u, double v) const {
  thread_local PatchWeights pw;
  impl_->patch_weights(ptex_face, u, v, &pw);
  // phi_j = sum over patch points i of (basis weight of i) * (stencil weight of j in i). Near
  // extraordinary vertices the patch points' stencils overlap heavily, so terms are summed in a
  // small open-addressing table.
  WeightAccumulator sums;
  for (int i = 0; i < pw.count; ++i)
    impl_->for_each_control(pw.points[i], 1.0, [&](uint32_t j, double weight) {
      double* slot = sums.slot(j);
      for (int k = 0; k < 6; ++k) slot[k] += weight * pw.w[k * pw.count + i];
    });
  return sums.sorted_weights();
}

CAGEKIT_NAMESPACE_END
