// SPDX-License-Identifier: GPL-3.0-or-later
#include "subdiv/patch_basis.h"

#include <string>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {
namespace {

namespace Far = OpenSubdiv::Far;

// Cubic Bernstein polynomials and their first two derivatives.
void bernstein(double x, double b[4], double db[4], double ddb[4]) {
  const double y = 1.0 - x;
  b[0] = y * y * y;
  b[1] = 3 * x * y * y;
  b[2] = 3 * x * x * y;
  b[3] = x * x * x;
  db[0] = -3 * y * y;
  db[1] = 3 * y * y - 6 * x * y;
  db[2] = 6 * x * y - 3 * x * x;
  db[3] = 3 * x * x;
  ddb[0] = 6 * y;
  ddb[1] = 18 * x - 12;
  ddb[2] = 6 - 18 * x;
  ddb[3] = 6 * x;
}

// Uniform cubic B-spline basis functions and their first two derivatives.
void bspline_curve(double x, double b[4], double db[4], double ddb[4]) {
  const double y = 1.0 - x;
  b[0] = y * y * y / 6;
  b[1] = (3 * x * x * x - 6 * x * x + 4) / 6;
  b[2] = (-3 * x * x * x + 3 * x * x + 3 * x + 1) / 6;
  b[3] = x * x * x / 6;
  db[0] = -y * y / 2;
  db[1] = (3 * x * x - 4 * x) / 2;
  db[2] = (-3 * x * x + 2 * x + 1) / 2;
  db[3] = x * x / 2;
  ddb[0] = y;
  ddb[1] = 3 * x - 2;
  ddb[2] = 1 - 3 * x;
  ddb[3] = x;
}

// Fold the weight of a phantom point P0 = 2 P1 - P2 onto P1 and P2 (index steps of `stride`).
void fold_phantom(PatchBasis w, int phantom, int stride, int count_stride) {
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 4; ++j) {
      const int p0 = phantom + j * count_stride;
      const double x = w[k][p0];
      w[k][p0 + stride] += 2.0 * x;
      w[k][p0 + 2 * stride] -= x;
      w[k][p0] = 0.0;
    }
}

// The Gregory patch is the bicubic Bezier patch whose four interior control points blend two
// face points each, F = g F+ + (1 - g) F-, with g = n / d rational, n and d linear in (s, t).
struct BezierSlot {
  int point, column, row;
};
constexpr BezierSlot kBoundarySlots[12] = {{0, 0, 0},  {1, 1, 0},  {7, 2, 0},  {5, 3, 0},
                                           {2, 0, 1},  {6, 3, 1},  {16, 0, 2}, {12, 3, 2},
                                           {15, 0, 3}, {17, 1, 3}, {11, 2, 3}, {10, 3, 3}};

// Corner i's face points F+ = 5i+3 and F- = 5i+4 sit at Bezier slot (column, row); F+ has
// weight g = (n0 + ns s + nt t) / (d0 + ds s + dt t).
struct FacePair {
  int plus, column, row;
  double n0, ns, nt, d0, ds, dt;
};
constexpr FacePair kFacePairs[4] = {
    {3, 1, 1, 0, 1, 0, 0, 1, 1},      // s / (s + t)
    {8, 2, 1, 0, 0, 1, 1, -1, 1},     // t / ((1 - s) + t)
    {13, 2, 2, 1, -1, 0, 2, -1, -1},  // (1 - s) / ((1 - s) + (1 - t))
    {18, 1, 2, 1, 0, -1, 1, 1, -1},   // (1 - t) / (s + (1 - t))
};

}  // namespace

void bspline_patch_basis(double s, double t, int boundary_mask, PatchBasis w) {
  double bs[4], dbs[4], ddbs[4], bt[4], dbt[4], ddbt[4];
  bspline_curve(s, bs, dbs, ddbs);
  bspline_curve(t, bt, dbt, ddbt);
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) {
      const int i = 4 * row + col;
      w[0][i] = bs[col] * bt[row];
      w[1][i] = dbs[col] * bt[row];
      w[2][i] = bs[col] * dbt[row];
      w[3][i] = ddbs[col] * bt[row];
      w[4][i] = dbs[col] * dbt[row];
      w[5][i] = bs[col] * ddbt[row];
    }
  if (boundary_mask & 1) fold_phantom(w, 0, 4, 1);    // v = 0: row 0 from rows 1, 2
  if (boundary_mask & 2) fold_phantom(w, 3, -1, 4);   // u = 1: column 3 from columns 2, 1
  if (boundary_mask & 4) fold_phantom(w, 12, -4, 1);  // v = 1: row 3 from rows 2, 1
  if (boundary_mask & 8) fold_phantom(w, 0, 1, 4);    // u = 0: column 0 from columns 1, 2
  for (int k = 0; k < 6; ++k)
    for (int i = 16; i < kMaxPatchPoints; ++i) w[k][i] = 0.0;
}

void gregory_patch_basis(double s, double t, PatchBasis w) {
  double bs[4], dbs[4], ddbs[4], bt[4], dbt[4], ddbt[4];
  bernstein(s, bs, dbs, ddbs);
  bernstein(t, bt, dbt, ddbt);
  for (const BezierSlot& b : kBoundarySlots) {
    w[0][b.point] = bs[b.column] * bt[b.row];
    w[1][b.point] = dbs[b.column] * bt[b.row];
    w[2][b.point] = bs[b.column] * dbt[b.row];
    w[3][b.point] = ddbs[b.column] * bt[b.row];
    w[4][b.point] = dbs[b.column] * dbt[b.row];
    w[5][b.point] = bs[b.column] * ddbt[b.row];
  }
  for (const FacePair& f : kFacePairs) {
    const double d = f.d0 + f.ds * s + f.dt * t;
    // At the patch corner itself d = 0 and g is undefined; its Bezier weight vanishes there
    // (only the twist sees g), and g = 0 is OpenSubdiv's convention.
    double g[6] = {0, 0, 0, 0, 0, 0};  // g, gs, gt, gss, gst, gtt
    if (d > 0) {
      g[0] = (f.n0 + f.ns * s + f.nt * t) / d;
      g[1] = (f.ns - g[0] * f.ds) / d;  // quotient rule with n'' = d'' = 0
      g[2] = (f.nt - g[0] * f.dt) / d;
      g[3] = -2.0 * g[1] * f.ds / d;
      g[4] = -(g[1] * f.dt + g[2] * f.ds) / d;
      g[5] = -2.0 * g[2] * f.dt / d;
    }
    // Derivatives of the Bezier product b(s, t) = B_col(s) B_row(t).
    const double b[6] = {bs[f.column] * bt[f.row],    dbs[f.column] * bt[f.row],   bs[f.column] * dbt[f.row],
                         ddbs[f.column] * bt[f.row],  dbs[f.column] * dbt[f.row],  bs[f.column] * ddbt[f.row]};
    // Leibniz rule for b * g; F- gets b * (1 - g) = b - b * g.
    const double bg[6] = {b[0] * g[0],
                          b[1] * g[0] + b[0] * g[1],
                          b[2] * g[0] + b[0] * g[2],
                          b[3] * g[0] + 2.0 * b[1] * g[1] + b[0] * g[3],
                          b[4] * g[0] + b[1] * g[2] + b[2] * g[1] + b[0] * g[4],
                          b[5] * g[0] + 2.0 * b[2] * g[2] + b[0] * g[5]};
    for (int k = 0; k < 6; ++k) {
      w[k][f.plus] = bg[k];
      w[k][f.plus + 1] = b[k] - bg[k];
    }
  }
}

int patch_basis(Far::PatchDescriptor::Type type, const Far::PatchParam& param, double u, double v, PatchBasis w) {
  double s = u, t = v;
  param.Normalize(s, t);
  int count = 0;
  if (type == Far::PatchDescriptor::REGULAR) {
    bspline_patch_basis(s, t, param.GetBoundary(), w);
    count = 16;
  } else if (type == Far::PatchDescriptor::GREGORY_BASIS) {
    gregory_patch_basis(s, t, w);
    count = 20;
  } else {
    fail(Status::internal_error, "unexpected OpenSubdiv patch type " + std::to_string(static_cast<int>(type)));
  }
  // d(s, t) / d(u, v): the patch covers a square of side GetParamFraction() of its ptex face.
  const double scale = 1.0 / param.GetParamFraction();
  for (int i = 0; i < count; ++i) {
    for (int k = 1; k <= 2; ++k) w[k][i] *= scale;
    for (int k = 3; k <= 5; ++k) w[k][i] *= scale * scale;
  }
  return count;
}

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
