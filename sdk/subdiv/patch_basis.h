// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Basis functions of the patches in a Far::PatchTable of a Catmull-Clark surface, evaluated at a
// ptex (u, v) with first and second derivatives with respect to the ptex (u, v).
//
// CageKit evaluates the bases itself instead of calling Far::PatchTable::EvaluateBasis because
// OpenSubdiv 3.5 as packaged gets two derivative cases wrong:
//  - Gregory end caps: only the polynomial part of the rational interior weights is
//    differentiated (OPENSUBDIV_GREGORY_EVAL_TRUE_DERIVATIVES is off), so derivatives disagree
//    with the positions by up to a few percent inside end caps;
//  - patches of the sub-faces of non-quad faces: derivatives are scaled by 2^depth instead of
//    2^(depth-1), i.e. twice too large for the ptex sub-face parameterisation.
// Fitting (Newton steps, least squares on derivatives) needs derivatives that are exactly those
// of the evaluated surface, so both are done here. Positions agree with OpenSubdiv's.
#include <opensubdiv/far/patchDescriptor.h>
#include <opensubdiv/far/patchParam.h>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {

constexpr int kMaxPatchPoints = 20;

// Weights w[k][i] of the patch points i for k = value, d/du, d/dv, d2/du2, d2/dudv, d2/dv2.
using PatchBasis = double[6][kMaxPatchPoints];

// Uniform bicubic B-spline patch, 16 points row by row (v outer, u inner), at patch-local
// (s, t); boundary_mask (PatchParam::GetBoundary: bit 0 v=0, 1 u=1, 2 v=1, 3 u=0) replaces the
// missing outer row/column by the linear extrapolation 2 P1 - P2 (boundaries, infinitely sharp
// creases).
void bspline_patch_basis(double s, double t, int boundary_mask, PatchBasis w);

// OpenSubdiv's 20-point Gregory patch (GREGORY_BASIS): five points per corner i (P, E+, E-, F+,
// F-) at 5i .. 5i+4, corners counter-clockwise from (0,0); exact rational derivatives.
void gregory_patch_basis(double s, double t, PatchBasis w);

// The basis of a patch at ptex (u, v): normalises (u, v) into the patch and scales the
// derivatives to the ptex face. Returns the number of patch points (16 or 20); throws
// Error(internal_error) for patch types a Catmull-Clark PatchTable with Gregory end caps does
// not produce.
int patch_basis(OpenSubdiv::Far::PatchDescriptor::Type type, const OpenSubdiv::Far::PatchParam& param, double u,
                double v, PatchBasis w);

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
