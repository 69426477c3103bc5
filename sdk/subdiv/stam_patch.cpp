// SPDX-License-Identifier: GPL-3.0-or-later
#include "subdiv/stam_patch.h"

#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>

#include "core/angles.h"
#include "core/status.h"
#include "subdiv/patch_basis.h"
#include "subdiv/topology_refiner_factory.h"

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {
namespace {

namespace Far = OpenSubdiv::Far;

// The points beyond the 1-ring, in F0's frame: the first 7 complete the 2N+8 layout, all 16
// the 2N+17 extended layout.
constexpr int kExtra[16][2] = {{2, -1}, {2, 0}, {2, 1}, {2, 2}, {1, 2}, {0, 2}, {-1, 2}, {3, -1},
                               {3, 0},  {3, 1}, {3, 2}, {3, 3}, {2, 3}, {1, 3}, {0, 3}, {-1, 3}};

// Index of grid point (i, j) of F0's frame in the (extended) layout; -1 if it has none.
int layout_index(int n, int i, int j) {
  if (i == 0 && j == 0) return 0;
  if (i == 1 && j == 0) return 1;
  if (i == 0 && j == 1) return 1 + 1 % n;
  if (i == -1 && j == 0) return 1 + 2 % n;
  if (i == 0 && j == -1) return n;
  if (i == 1 && j == 1) return n + 1;
  if (i == -1 && j == 1) return n + 2;
  if (i == 1 && j == -1) return 2 * n;
  for (int k = 0; k < 16; ++k)
    if (kExtra[k][0] == i && kExtra[k][1] == j) return 2 * n + 1 + k;
  return -1;
}

// A cell of the quad grid of one sector: face and the corner at the cell's (0,0), the face's
// vertices counter-clockwise from there being (0,0), (1,0), (1,1), (0,1).
struct Cell {
  int face, corner;
};

class Walker {
 public:
  explicit Walker(const Far::TopologyLevel& level) : level_(level) {}

  bool usable_face(int f) const { return level_.GetFaceVertices(f).size() == 4 && !level_.IsFaceHole(f); }

  // The face across local edge `edge` of f and the corner of vertex `pivot` in it.
  bool cross(const Cell& c, int edge, int pivot, Cell* out) const {
    const auto fe = level_.GetFaceEdges(c.face);
    const int e = fe[(c.corner + edge) % 4];
    const auto ef = level_.GetEdgeFaces(e);
    if (ef.size() != 2 || ef[0] == ef[1]) return false;
    const int g = ef[0] == c.face ? ef[1] : ef[0];
    if (!usable_face(g)) return false;
    const int v = level_.GetFaceVertices(c.face)[(c.corner + pivot) % 4];
    const auto gv = level_.GetFaceVertices(g);
    int corner = -1;
    for (int k = 0; k < 4; ++k)
      if (gv[k] == v) corner = corner < 0 ? k : 4;  // a repeated vertex is not a grid
    if (corner < 0 || corner > 3) return false;
    *out = {g, corner};
    return true;
  }
  bool step_i(Cell* c) const { return cross(*c, 1, 1, c); }
  bool step_j(Cell* c) const { return cross(*c, 2, 3, c); }
  bool next_sector(Cell* c) const { return cross(*c, 3, 0, c); }

  // Point (i, j) >= 0 of the sector whose cell (0,0) is `origin`.
  bool point(Cell origin, int i, int j, int* vertex) const {
    const int ci = std::max(i - 1, 0), cj = std::max(j - 1, 0);
    for (int k = 0; k < ci; ++k)
      if (!step_i(&origin)) return false;
    for (int k = 0; k < cj; ++k)
      if (!step_j(&origin)) return false;
    static constexpr int kCorner[2][2] = {{0, 3}, {1, 2}};  // [di][dj]
    *vertex = level_.GetFaceVertices(origin.face)[(origin.corner + kCorner[i - ci][j - cj]) % 4];
    return true;
  }

  bool smooth_edges(int v) const {
    for (int e : level_.GetVertexEdges(v))
      if (level_.GetEdgeSharpness(e) > 0.0f || level_.IsEdgeInfSharp(e) || level_.IsEdgeNonManifold(e)) return false;
    return true;
  }
  bool smooth_vertex(int v) const {
    return !level_.IsVertexBoundary(v) && !level_.IsVertexNonManifold(v) && level_.GetVertexSharpness(v) <= 0.0f &&
           !level_.IsVertexInfSharp(v) && smooth_edges(v);
  }
  bool regular_vertex(int v) const {
    return smooth_vertex(v) && level_.GetVertexEdges(v).size() == 4 && level_.GetVertexFaces(v).size() == 4;
  }

 private:
  const Far::TopologyLevel& level_;
};

}  // namespace

bool gather_stam_points(const Far::TopologyLevel& level, int face, int corner, bool extended,
                        std::vector<int>* points) {
  const Walker walk(level);
  if (face < 0 || face >= level.GetNumFaces() || !walk.usable_face(face) || corner < 0 || corner > 3) return false;
  const int ev = level.GetFaceVertices(face)[corner];
  if (!walk.smooth_vertex(ev)) return false;
  const int n = level.GetVertexFaces(ev).size();
  if (n < 3 || static_cast<int>(level.GetVertexEdges(ev).size()) != n) return false;
  std::vector<Cell> sectors{{face, corner}};
  for (;;) {
    Cell next = sectors.back();
    if (!walk.next_sector(&next)) return false;
    if (next.face == face) break;
    if (static_cast<int>(sectors.size()) == n) return false;
    sectors.push_back(next);
  }
  if (static_cast<int>(sectors.size()) != n || sectors[0].corner != corner) return false;
  for (const Cell& c : sectors)
    if (level.GetFaceVertices(c.face)[c.corner] != ev) return false;

  // Point (i, j) of F0's frame.
  auto f0_point = [&](int i, int j, int* v) {
    if (j < 0) return walk.point(sectors[n - 1], -j, i, v);
    if (i < 0) return walk.point(sectors[1], j, -i, v);
    return walk.point(sectors[0], i, j, v);
  };
  const int size = 2 * n + (extended ? 17 : 8);
  points->assign(static_cast<size_t>(size), -1);
  int* p = points->data();
  p[0] = ev;
  for (int k = 0; k < n; ++k)
    if (!walk.point(sectors[k], 1, 0, &p[1 + k]) || !walk.point(sectors[k], 1, 1, &p[n + 1 + k])) return false;
  for (int k = 0; 2 * n + 1 + k < size; ++k)
    if (!f0_point(kExtra[k][0], kExtra[k][1], &p[2 * n + 1 + k])) return false;
  // Vertex rules apply only to the EV and to F0's three other corners (every other point enters
  // the matrices as a neighbour of an edge, face or one of these vertices), so only these need
  // to be smooth, and the three regular: another EV may sit at distance 2 (triangles at level 2).
  for (int k : {1, 2, n + 1})
    if (!walk.regular_vertex(p[k])) return false;
  std::vector<int> sorted(*points);
  std::sort(sorted.begin(), sorted.end());
  return std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
}

StamMatrices build_stam_matrices(int valence) {
  const int n = valence, radius = 4;
  // A polar grid: the EV (vertex 0) and N sectors of radius x radius quads.
  auto vertex = [&](int k, int i, int j) {
    k %= n;
    if (i == 0 && j == 0) return 0;
    if (j == 0) return 1 + k * radius + (i - 1);                                 // spoke k
    if (i == 0) return 1 + ((k + 1) % n) * radius + (j - 1);                      // spoke k+1
    return 1 + n * radius + k * radius * radius + (i - 1) * radius + (j - 1);  // interior
  };
  const int num_vertices = 1 + n * radius + n * radius * radius;
  std::vector<int> face_vertices, face_sizes(static_cast<size_t>(n * radius * radius), 4);
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < radius; ++i)
      for (int j = 0; j < radius; ++j) {
        face_vertices.push_back(vertex(k, i, j));
        face_vertices.push_back(vertex(k, i + 1, j));
        face_vertices.push_back(vertex(k, i + 1, j + 1));
        face_vertices.push_back(vertex(k, i, j + 1));
      }
  Far::TopologyDescriptor desc;
  desc.numVertices = num_vertices;
  desc.numFaces = static_cast<int>(face_sizes.size());
  desc.numVertsPerFace = face_sizes.data();
  desc.vertIndicesPerFace = face_vertices.data();
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(
      desc, Factory::Options(OpenSubdiv::Sdc::SCHEME_CATMARK, sdc_options(BoundaryRule::edges_only))));
  if (!refiner) fail(Status::internal_error, "could not build the local mesh of valence " + std::to_string(n));
  Far::TopologyRefiner::UniformOptions uniform(1);
  uniform.fullTopologyInLastLevel = true;
  refiner->RefineUniform(uniform);
  Far::StencilTableFactoryReal<double>::Options options;
  options.generateIntermediateLevels = false;
  options.generateControlVerts = false;
  options.generateOffsets = true;
  options.maxLevel = 1;
  std::unique_ptr<const Far::StencilTableReal<double>> stencils(
      Far::StencilTableFactoryReal<double>::Create(*refiner, options));

  const Far::TopologyLevel& parent = refiner->GetLevel(0);
  const Far::TopologyLevel& child = refiner->GetLevel(1);
  std::vector<int> parent_points, child_points;
  const int f0 = 0;  // sector 0's cell (0,0): corner 0 is the EV
  int child_face = -1, child_corner = -1;
  const int ev_child = parent.GetVertexChildVertex(0);
  for (int c : parent.GetFaceChildFaces(f0)) {
    const auto cv = child.GetFaceVertices(c);
    for (int k = 0; k < 4; ++k)
      if (cv[k] == ev_child) child_face = c, child_corner = k;
  }
  if (!gather_stam_points(parent, f0, 0, false, &parent_points) ||
      !gather_stam_points(child, child_face, child_corner, true, &child_points) || !stencils)
    fail(Status::internal_error, "Stam layout not found in the local mesh of valence " + std::to_string(n));
  // The child face's frame must be F0's frame halved: its (1,0) is the midpoint of the spoke.
  if (child_points[1] != parent.GetEdgeChildVertex(parent.FindEdge(0, parent_points[1])))
    fail(Status::internal_error, "Stam layout orientation mismatch");

  StamMatrices m;
  m.valence = n;
  const int cols = m.size(), rows = cols + 9;
  m.extended.assign(static_cast<size_t>(rows) * cols, 0.0);
  std::vector<int> column(static_cast<size_t>(num_vertices), -1);
  for (int c = 0; c < cols; ++c) column[parent_points[c]] = c;
  const int first_child = 0;  // stencil table rows are the level-1 vertices
  for (int r = 0; r < rows; ++r) {
    const auto s = stencils->GetStencil(child_points[r] - first_child);
    for (int k = 0; k < s.GetSize(); ++k) {
      const int c = column[s.GetVertexIndices()[k]];
      if (c < 0) {
        if (s.GetWeights()[k] != 0.0)
          fail(Status::internal_error, "Stam child point depends on a point outside the layout");
        continue;
      }
      m.extended[static_cast<size_t>(r) * cols + c] += s.GetWeights()[k];
    }
  }
  // Limit position mask (Halstead et al. 1993): the left eigenvector of A for eigenvalue 1.
  m.limit.assign(static_cast<size_t>(2 * n + 1), 0.0);
  m.limit[0] = n / (n + 5.0);
  for (int k = 0; k < n; ++k) {
    m.limit[1 + k] = 4.0 / (n * (n + 5.0));
    m.limit[n + 1 + k] = 1.0 / (n * (n + 5.0));
  }
  static constexpr int kSub[3][2] = {{0, -1}, {0, 0}, {-1, 0}};  // first (i, j) of each 4x4 block
  for (int sub = 0; sub < 3; ++sub)
    for (int row = 0; row < 4; ++row)
      for (int col = 0; col < 4; ++col) {
        const int idx = layout_index(n, kSub[sub][0] + col, kSub[sub][1] + row);
        if (idx < 0) fail(Status::internal_error, "Stam sub-patch point outside the layout");
        m.sub_points[sub][4 * row + col] = idx;
      }
  // E_0 = extended, E_(l+1) = E_l * A (A: the first `cols` rows of extended).
  const size_t block = static_cast<size_t>(rows) * cols;
  m.powers.assign(block * (StamMatrices::kStoredLevels + 1), 0.0);
  std::copy(m.extended.begin(), m.extended.end(), m.powers.begin());
  for (int l = 0; l < StamMatrices::kStoredLevels; ++l) {
    const double* e = &m.powers[block * l];
    double* out = &m.powers[block * (l + 1)];
    for (int r = 0; r < rows; ++r)
      for (int j = 0; j < cols; ++j) {
        const double x = e[static_cast<size_t>(r) * cols + j];
        if (x == 0.0) continue;
        const double* a = &m.extended[static_cast<size_t>(j) * cols];
        for (int c = 0; c < cols; ++c) out[static_cast<size_t>(r) * cols + c] += x * a[c];
      }
  }
  return m;
}

void stam_basis(const StamMatrices& m, double s, double t, double* w, int kinds) {
  const int n = m.valence, size = m.size(), ext = size + 9;
  kinds = std::clamp(kinds, 1, 6);
  std::fill(w, w + 6 * size, 0.0);
  double largest = std::max(s, t);
  int levels = 0;
  while (largest > 0.0 && largest < 0.5 && levels <= 60) {
    largest *= 2, s *= 2, t *= 2;
    ++levels;
  }
  if (largest == 0.0 || levels > 60) {
    // Limit position and tangent masks of the EV (Halstead et al. 1993), tangents scaled so
    // that valence 4 gives the B-spline derivatives.
    for (int c = 0; c <= 2 * n; ++c) w[c] = m.limit[c];
    const double a = 1.0 + std::cos(2 * kPi / n) + std::cos(kPi / n) * std::sqrt(2.0 * (9.0 + std::cos(2 * kPi / n)));
    for (int k = 0; k < n; ++k) {
      for (int d = 0; d < 2; ++d) {  // d/ds along spoke 0, d/dt along spoke 1
        const double c0 = std::cos(2 * kPi * (k - d) / n), c1 = std::cos(2 * kPi * (k + 1 - d) / n);
        w[(1 + d) * size + 1 + k] = a * c0 / 12.0;
        w[(1 + d) * size + n + 1 + k] = (c0 + c1) / 12.0;
      }
    }
    return;
  }
  int sub;
  double x, y;
  if (t < 0.5) {
    sub = 0, x = 2 * s - 1, y = 2 * t;
  } else if (s >= 0.5) {
    sub = 1, x = 2 * s - 1, y = 2 * t - 1;
  } else {
    sub = 2, x = 2 * s, y = 2 * t - 1;
  }
  PatchBasis b;
  bspline_patch_basis(x, y, 0, b);
  // Row vectors over the child's extended layout (16 non-zero entries), pushed back through
  // A-bar * A^levels: one product with the stored power, then any levels beyond it one by one.
  // Per-thread scratch rows (no allocation per evaluation once grown).
  thread_local std::vector<double> cur, next;
  cur.assign(6 * static_cast<size_t>(size), 0.0);
  next.resize(6 * static_cast<size_t>(size));
  const int stored = std::min(levels, StamMatrices::kStoredLevels);
  const double* e = &m.powers[static_cast<size_t>(stored) * ext * size];
  for (int k = 0; k < kinds; ++k) {
    double* out = &cur[static_cast<size_t>(k) * size];
    for (int p = 0; p < 16; ++p) {
      const double x_r = b[k][p];
      if (x_r == 0.0) continue;
      const double* a = &e[static_cast<size_t>(m.sub_points[sub][p]) * size];
      for (int c = 0; c < size; ++c) out[c] += x_r * a[c];
    }
  }
  for (int l = stored; l < levels; ++l) {
    std::fill(next.begin(), next.end(), 0.0);
    for (int r = 0; r < size; ++r) {
      const double* a = &m.extended[static_cast<size_t>(r) * size];
      for (int k = 0; k < kinds; ++k) {
        const double x_r = cur[k * size + r];
        if (x_r == 0.0) continue;
        double* out = &next[k * size];
        for (int c = 0; c < size; ++c) out[c] += x_r * a[c];
      }
    }
    cur.swap(next);
  }
  // Every row of A sums to 1, so the sums of the rows are invariant (1 for the value, 0 for
  // the derivatives) in exact arithmetic; rounding drifts them along the eigenvalue-1 direction,
  // which the 2^n scaling of derivatives would amplify. The drift is removed exactly along that
  // left eigenvector, the limit mask.
  for (int k = 0; k < kinds; ++k) {
    double total = 0.0;
    for (int c = 0; c < size; ++c) total += cur[k * size + c];
    const double drift = total - (k == 0 ? 1.0 : 0.0);
    for (int c = 0; c <= 2 * n; ++c) cur[k * size + c] -= drift * m.limit[c];
  }
  const double scale = std::ldexp(1.0, levels + 1);
  for (int k = 0; k < kinds; ++k) {
    const double f = k == 0 ? 1.0 : k < 3 ? scale : scale * scale;
    for (int c = 0; c < size; ++c) w[k * size + c] = cur[k * size + c] * f;
  }
}

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
