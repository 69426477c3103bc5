// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// SubdivisionSurface: the Catmull-Clark limit surface of a cage, evaluable at any parametric
// location, with first and second derivatives and the basis weights phi_j of the control
// vertices (thesis §2.3–2.4, (2.24)–(2.26)). Chapters 7 (fitting) and 8 (multiresolution)
// stand on this.
//
// Parameterisation: OpenSubdiv's "ptex" faces. A quad of the cage is one parametric face with
// (u, v) in [0,1]^2; an n-gon (n != 4) is split into n parametric quads, one per corner.
// ptex_face(base_face, corner) maps between the two.
//
// Machinery (see README.md): OpenSubdiv Far feature-adaptive refinement to `isolation_level`
// and a double-precision PatchTable with infinitely sharp patches (crease curves are exact cubic
// B-splines); every regular patch is the exact bicubic B-spline. The irregular patches at the
// isolation level, the parameter square [0, 2^-L]^2 at an extraordinary corner (L = isolation
// level counted from the base face; n-gon sub-faces start at level 1), are evaluated exactly
// (Stam's method, by repeated local subdivision) when their extraordinary vertex is interior
// and smooth; around boundary, crease, corner and dart vertices they are OpenSubdiv's Gregory
// end caps (an approximation, exact at the vertex itself). All patch points are folded back
// onto the cage's control vertices by stencils. Derivatives are the exact derivatives of what
// is evaluated.
//
// Thread-safety: everything is precomputed at construction; afterwards every const member may
// be called concurrently from any number of threads (no caches, no mutable state). Construction
// and assignment need exclusive access. OpenSubdiv's error callback is process-global: CageKit
// installs a silent one on first use (see opensubdiv_error_handler.h).
//
// Errors: the constructor throws Error(invalid_mesh) for a cage that cannot be subdivided,
// invalid_argument for options out of range; queries throw invalid_argument for an unknown ptex
// face, (u, v) outside [0,1]^2 or NaN, a ptex face of a hole face, a control array of the wrong
// size.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/cage.h"

CAGEKIT_NAMESPACE_BEGIN

constexpr int kMaxIsolationLevel = 10;

struct SurfaceOptions {
  // Adaptive isolation level of features (extraordinary vertices, creases) in OpenSubdiv.
  // Smooth interior extraordinary vertices are exact at any level >= 2 (>= 1 for all-quad
  // cages); the level only moves the boundary between B-spline and Stam patches, and costs
  // time and memory. Around boundary/crease/corner/dart extraordinary vertices the Gregory end
  // caps get closer to the limit surface with a higher level. Range [1, kMaxIsolationLevel].
  // Semi-sharp creases are isolated to at least ceil(sharpness) levels so that they are exact.
  int isolation_level = 2;
  // Isolation level of the region around boundary/crease/corner/dart extraordinary vertices,
  // which have no exact evaluation here and use Gregory end caps instead: every parametric
  // location farther than 2^-level (in ptex units) from such a vertex is on an exact B-spline
  // patch. Feature-adaptive refinement makes the cost grow linearly with the level and only
  // around those vertices. Range [isolation_level, kMaxIsolationLevel].
  int sharp_extraordinary_isolation_level = kMaxIsolationLevel;
  // Threads for building (not for evaluating): with many end-cap faces the region around
  // sharp extraordinary vertices is built as two sub-cages, at once when threads >= 2. The
  // results do not depend on it.
  int threads = 1;
};

struct SurfacePoint {
  Vec3 position, du, dv, duu, duv, dvv;
};

// The patch that holds one parametric location: its square [u0, u0 + size] x [v0, v0 + size]
// of the ptex face (a dyadic square of the ptex quadtree) and whether the limit surface is one
// bicubic polynomial on it (the regular B-spline patches, also those with infinitely sharp
// boundary or crease edges) or not (Stam patches at smooth extraordinary vertices, Gregory end
// caps at the others).
struct PatchDomain {
  double u0 = 0, v0 = 0, size = 1;
  bool polynomial = true;
};

// A stencil: the limit quantity at one location = sum_k weights[k] * control[indices[k]].
struct BasisWeights {
  std::vector<uint32_t> indices;  // control vertices of the cage
  std::vector<double> w, wu, wv, wuu, wuv, wvv;
};

class SubdivisionSurface {
 public:
  explicit SubdivisionSurface(const Cage& cage, const SurfaceOptions& options = {});
  ~SubdivisionSurface();
  SubdivisionSurface(SubdivisionSurface&&) noexcept;
  SubdivisionSurface& operator=(SubdivisionSurface&&) noexcept;

  uint32_t num_control_vertices() const;
  uint32_t num_ptex_faces() const;
  uint32_t ptex_face(uint32_t base_face, uint32_t corner = 0) const;
  uint32_t base_face_of_ptex(uint32_t ptex_face) const;
  // False for the ptex faces of hole faces (no limit surface there); throws for an unknown face.
  bool has_limit_surface(uint32_t ptex_face) const;

  // Evaluates with the cage's own control positions or with `control` (one per control vertex,
  // e.g. moved cage vertices). u, v in [0,1]; out-of-range faces/params throw invalid_argument.
  SurfacePoint evaluate(uint32_t ptex_face, double u, double v) const;
  SurfacePoint evaluate(uint32_t ptex_face, double u, double v, const std::vector<Vec3>& control) const;
  // Fast repeated evaluation with one set of control positions: patch_points(control) applies
  // the stencils of every patch point once (control vertices first, then the refined and
  // end-cap points the patches use); evaluate_patch_points then only weighs the 16-20 points of
  // one patch (no stencils), several times faster than evaluate(..., control). Same results as
  // evaluate(..., control) up to rounding. Throws invalid_argument for arrays of the wrong size.
  std::vector<Vec3> patch_points(const std::vector<Vec3>& control) const;
  SurfacePoint evaluate_patch_points(uint32_t ptex_face, double u, double v,
                                     const std::vector<Vec3>& patch_points) const;
  // Position only (no derivatives), with patch points.
  Vec3 evaluate_position(uint32_t ptex_face, double u, double v, const std::vector<Vec3>& patch_points) const;
  // The position weights of evaluate_position at (ptex_face, u, v) over the patch points
  // (indices into the patch_points() array), into caller arrays (cleared first): a stencil that
  // stays valid for every set of control positions, so a fixed (u, v) is evaluated for new
  // control points by one weighted sum.
  void patch_point_weights(uint32_t ptex_face, double u, double v, std::vector<uint32_t>& points,
                           std::vector<double>& weights) const;

  // The patch at (ptex_face, u, v); same errors as evaluate(). On a patch border the patch the
  // evaluation uses (OpenSubdiv's PatchMap lookup).
  PatchDomain patch_domain(uint32_t ptex_face, double u, double v) const;

  // The basis functions phi_j that are non-zero at (ptex_face, u, v) and their derivatives.
  // They sum to 1 (partition of unity) and their derivatives sum to 0.
  BasisWeights basis(uint32_t ptex_face, double u, double v) const;
  // The values phi_j only (no derivatives), in no particular order, into caller arrays
  // (cleared first; no allocation once they have grown): the fast path of least squares.
  void basis_values(uint32_t ptex_face, double u, double v, std::vector<uint32_t>& indices,
                    std::vector<double>& weights) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

CAGEKIT_NAMESPACE_END
