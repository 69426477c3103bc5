// SPDX-License-Identifier: GPL-3.0-or-later
#include "multires/patch_deformer_table.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/parallel_for.h"
#include "core/status.h"
#include "multires/scan_binding.h"
#include "subdiv/subdivision_surface.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

// Interpolation nodes of the cubic fit in each direction: interior and not dyadic, so that no
// node lies on a break between the pieces of a piecewise polynomial.
constexpr double kNodes[4] = {0.06, 0.36, 0.64, 0.94};

// The inverse of the Vandermonde matrix V[i][a] = kNodes[i]^a: power coefficients = Vinv * values.
std::array<std::array<double, 4>, 4> inverse_vandermonde() {
  double m[4][8] = {};
  for (int i = 0; i < 4; ++i) {
    for (int a = 0; a < 4; ++a) m[i][a] = std::pow(kNodes[i], a);
    m[i][4 + i] = 1;
  }
  for (int col = 0; col < 4; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 4; ++r)
      if (std::abs(m[r][col]) > std::abs(m[pivot][col])) pivot = r;
    for (int c = 0; c < 8; ++c) std::swap(m[col][c], m[pivot][c]);
    const double d = m[col][col];
    for (int c = 0; c < 8; ++c) m[col][c] /= d;
    for (int r = 0; r < 4; ++r) {
      if (r == col) continue;
      const double f = m[r][col];
      for (int c = 0; c < 8; ++c) m[r][c] -= f * m[col][c];
    }
  }
  // m = [I | V^-1]; V^-1[a][i] maps node values f(x_i) to the coefficient of x^a.
  std::array<std::array<double, 4>, 4> inv{};
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 4; ++i) inv[a][i] = m[a][4 + i];
  return inv;
}

struct CellOut {
  uint8_t depth = 0;
  std::vector<uint32_t> vertices;  // scan vertex indices, ascending
  std::vector<float> s, t;
  std::vector<uint32_t> controls;
  std::vector<double> coefficients;  // 16 per control
};

struct FaceOut {
  std::vector<CellOut> cells;
  std::vector<uint32_t> irregular;
};

// Builds the cells of one ptex face by recursive subdivision of its parameter square.
class FaceBuilder {
 public:
  FaceBuilder(const ScanBinding& b, const SubdivisionSurface& surface, const PatchTableOptions& o,
              const std::array<std::array<double, 4>, 4>& vinv)
      : b_(b), surface_(surface), o_(o), vinv_(vinv), slot_(b.num_control_vertices, -1) {}

  void run(uint32_t ptex, std::vector<uint32_t> vertices, FaceOut* out) {
    ptex_ = ptex;
    out_ = out;
    visit(0, 0, 0, std::move(vertices));
  }

 private:
  // Local parameters of vertex i in the square (depth, ix, iy).
  void local(uint32_t i, int depth, uint32_t ix, uint32_t iy, double* s, double* t) const {
    const double scale = std::ldexp(1.0, depth);
    *s = std::clamp(b_.foot_points[i].u * scale - ix, 0.0, 1.0);
    *t = std::clamp(b_.foot_points[i].v * scale - iy, 0.0, 1.0);
  }

  void visit(int depth, uint32_t ix, uint32_t iy, std::vector<uint32_t> vertices) {
    if (vertices.empty()) return;
    CellOut cell;
    if (fit(depth, ix, iy, vertices, &cell)) {
      well_conditioned(depth, ix, iy, &vertices);
      if (vertices.empty()) return;
      std::sort(vertices.begin(), vertices.end());
      cell.depth = uint8_t(depth);
      for (uint32_t i : vertices) {
        double s, t;
        local(i, depth, ix, iy, &s, &t);
        cell.s.push_back(float(s)), cell.t.push_back(float(t));
      }
      cell.vertices = std::move(vertices);
      out_->cells.push_back(std::move(cell));
      return;
    }
    if (depth >= o_.max_depth || vertices.size() < o_.min_split_vertices) {
      out_->irregular.insert(out_->irregular.end(), vertices.begin(), vertices.end());
      return;
    }
    std::vector<uint32_t> children[4];
    for (uint32_t i : vertices) {
      double s, t;
      local(i, depth, ix, iy, &s, &t);
      children[(s >= 0.5 ? 1 : 0) + (t >= 0.5 ? 2 : 0)].push_back(i);
    }
    vertices.clear();
    vertices.shrink_to_fit();
    for (int c = 0; c < 4; ++c) visit(depth + 1, 2 * ix + (c & 1), 2 * iy + (c >> 1), std::move(children[c]));
  }

  // Moves the vertices where float32 would lose the surface frame to the irregular list: where
  // S_s or S_t is below 1% of the cell's extent (boundary corners of the limit surface, where
  // the derivatives nearly vanish) or nearly parallel to the other, float rounding relative to
  // the cell's size would turn N_S and T1 noticeably; the double rows keep them exact.
  void well_conditioned(int depth, uint32_t ix, uint32_t iy, std::vector<uint32_t>* vertices) {
    const double scale = std::ldexp(1.0, -depth);
    Vec3 corner[4];
    for (int c = 0; c < 4; ++c)
      corner[c] = surface_.evaluate(ptex_, std::min(1.0, (ix + (c & 1)) * scale), std::min(1.0, (iy + (c >> 1)) * scale))
                      .position;
    double extent = 0;
    for (int a = 0; a < 4; ++a)
      for (int c = a + 1; c < 4; ++c) extent = std::max(extent, distance(corner[a], corner[c]));
    size_t kept = 0;
    for (uint32_t i : *vertices) {
      const FootPoint& f = b_.foot_points[i];
      const SurfacePoint p = surface_.evaluate(ptex_, f.u, f.v);
      const double su = norm(p.du) * scale, sv = norm(p.dv) * scale, cr = norm(cross(p.du, p.dv)) * scale * scale;
      if (su < 1e-2 * extent || sv < 1e-2 * extent || cr < 1e-2 * su * sv)
        out_->irregular.push_back(i);
      else
        (*vertices)[kept++] = i;
    }
    vertices->resize(kept);
  }

  // The power-basis coefficients of the square's polynomial (if the surface is one there, as
  // verified at every vertex of the square against the binding's rows).
  bool fit(int depth, uint32_t ix, uint32_t iy, const std::vector<uint32_t>& vertices, CellOut* cell) {
    const double scale = std::ldexp(1.0, -depth);
    std::vector<uint32_t>& controls = cell->controls;
    controls.clear();
    values_.clear();  // values_[16 * slot + node]
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const double u = (ix + kNodes[i]) * scale, v = (iy + kNodes[j]) * scale;
        surface_.basis_values(ptex_, u, v, indices_, weights_);
        for (size_t e = 0; e < indices_.size(); ++e) {
          int32_t& slot = slot_[indices_[e]];
          if (slot < 0) {
            slot = int32_t(controls.size());
            controls.push_back(indices_[e]);
            values_.resize(values_.size() + 16, 0.0);
          }
          values_[16 * size_t(slot) + size_t(i + 4 * j)] += weights_[e];
        }
      }
    const size_t k = controls.size();
    std::vector<double>& coefficients = cell->coefficients;
    coefficients.assign(16 * k, 0.0);
    for (size_t c = 0; c < k; ++c) {
      const double* f = &values_[16 * c];
      double* out = &coefficients[16 * c];
      for (int a = 0; a < 4; ++a)
        for (int bb = 0; bb < 4; ++bb) {
          double sum = 0;
          for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) sum += vinv_[a][i] * vinv_[bb][j] * f[i + 4 * j];
          out[a + 4 * bb] = sum;
        }
    }
    // Verify at every vertex: value, d/ds and d/dt of every control's weight against the row.
    bool ok = true;
    std::vector<double> expect(3 * k);
    for (size_t vi = 0; vi < vertices.size() && ok; ++vi) {
      const uint32_t i = vertices[vi];
      if (b_.foot_points[i].ptex_face != ptex_) ok = false;
      double s, t;
      local(i, depth, ix, iy, &s, &t);
      std::fill(expect.begin(), expect.end(), 0.0);
      for (uint32_t e = b_.row_offsets[i]; e < b_.row_offsets[i + 1] && ok; ++e) {
        const int32_t slot = slot_[b_.control_index[e]];
        if (slot < 0) {
          ok = std::abs(b_.phi[e]) <= o_.tolerance && std::abs(b_.phi_u[e]) * scale <= o_.tolerance &&
               std::abs(b_.phi_v[e]) * scale <= o_.tolerance;
          continue;
        }
        expect[3 * size_t(slot)] += b_.phi[e];
        expect[3 * size_t(slot) + 1] += b_.phi_u[e] * scale;  // d/ds = 2^-depth d/du
        expect[3 * size_t(slot) + 2] += b_.phi_v[e] * scale;
      }
      const double sp[4] = {1, s, s * s, s * s * s}, tp[4] = {1, t, t * t, t * t * t};
      const double sd[4] = {0, 1, 2 * s, 3 * s * s}, td[4] = {0, 1, 2 * t, 3 * t * t};
      for (size_t c = 0; c < k && ok; ++c) {
        const double* m = &coefficients[16 * c];
        double p = 0, ps = 0, pt = 0;
        for (int bb = 0; bb < 4; ++bb)
          for (int a = 0; a < 4; ++a) {
            p += m[a + 4 * bb] * sp[a] * tp[bb];
            ps += m[a + 4 * bb] * sd[a] * tp[bb];
            pt += m[a + 4 * bb] * sp[a] * td[bb];
          }
        ok = std::abs(p - expect[3 * c]) <= o_.tolerance && std::abs(ps - expect[3 * c + 1]) <= o_.tolerance &&
             std::abs(pt - expect[3 * c + 2]) <= o_.tolerance;
      }
    }
    for (uint32_t c : controls) slot_[c] = -1;
    return ok;
  }

  const ScanBinding& b_;
  const SubdivisionSurface& surface_;
  const PatchTableOptions& o_;
  const std::array<std::array<double, 4>, 4>& vinv_;
  std::vector<int32_t> slot_;  // per control vertex: its slot in the current square, or -1
  std::vector<double> values_, weights_;
  std::vector<uint32_t> indices_;
  uint32_t ptex_ = 0;
  FaceOut* out_ = nullptr;
};

template <typename T>
void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

// Inverse lists: for each control vertex, the items (cells or irregular vertices) using it.
void invert(size_t num_control, const std::vector<uint32_t>& item_offsets, const std::vector<uint32_t>& item_control,
            std::vector<uint32_t>* offsets, std::vector<uint32_t>* items) {
  offsets->assign(num_control + 1, 0);
  for (uint32_t j : item_control) ++(*offsets)[j + 1];
  for (size_t j = 0; j < num_control; ++j) (*offsets)[j + 1] += (*offsets)[j];
  items->resize(item_control.size());
  std::vector<uint32_t> fill(offsets->begin(), offsets->end() - 1);
  for (size_t item = 0; item + 1 < item_offsets.size(); ++item)
    for (uint32_t e = item_offsets[item]; e < item_offsets[item + 1]; ++e) (*items)[fill[item_control[e]]++] = uint32_t(item);
}

}  // namespace

double PatchDeformerTable::bytes_per_vertex(size_t num_control_vertices) const {
  const size_t n = num_cell_vertices() + num_irregular_vertices();
  if (n == 0) return 0;
  const double out = 2 * 3 * sizeof(double);  // position + normal written
  // Cell vertices: index, s, t, D, 6 coefficients (+ a, b).
  const double cell_vertex = sizeof(uint32_t) + (9 + (local_frame ? 2 : 0)) * sizeof(float);
  // Irregular vertices: index, row offsets, per entry index + 3 doubles; D, 6 coefficients
  // (+ a, b) read from the binding as doubles.
  const double irregular_entries = double(irregular_control.size()) * (sizeof(uint32_t) + 3 * sizeof(double));
  const double irregular_vertex = 2 * sizeof(uint32_t) + (7 + (local_frame ? 2 : 0)) * sizeof(double);
  // Per cell: offsets, depth, per term an index, 16 floats and the control point it reads.
  const double cells = double(num_cells()) * (2 * 2 * sizeof(uint32_t) + 1) +
                       double(term_control.size()) * (sizeof(uint32_t) + 16 * sizeof(float) + 3 * sizeof(double));
  const double total = double(n) * out + double(num_cell_vertices()) * cell_vertex +
                       double(num_irregular_vertices()) * irregular_vertex + irregular_entries + cells +
                       double(num_control_vertices) * 3 * sizeof(double);
  return total / double(n);
}

PatchDeformerTable build_patch_deformer_table(const ScanBinding& b, const SubdivisionSurface& surface,
                                              const PatchTableOptions& options, int threads,
                                              const TaskMonitor& monitor) {
  if (options.max_depth < 0 || options.max_depth > 20 || !(options.tolerance > 0))
    fail(Status::invalid_argument, "patch table: max_depth must be in [0, 20] and tolerance > 0");
  if (surface.num_control_vertices() != b.num_control_vertices)
    fail(Status::invalid_argument, "patch table: the binding was made on another limit surface");
  const size_t n = b.num_vertices();
  const uint32_t num_ptex = surface.num_ptex_faces();
  std::vector<std::vector<uint32_t>> by_ptex(num_ptex);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t f = b.foot_points[i].ptex_face;
    if (f >= num_ptex) fail(Status::invalid_argument, "patch table: a foot point is on an unknown ptex face");
    by_ptex[f].push_back(uint32_t(i));
  }
  const auto vinv = inverse_vandermonde();
  std::vector<FaceOut> faces(num_ptex);
  // One builder per worker range (its per-control slot array is reused across faces).
  const size_t workers = std::min<size_t>(size_t(resolve_threads(threads)), std::max<size_t>(1, num_ptex / 8));
  run_ranges(num_ptex, workers, [&](size_t begin, size_t end, size_t worker) {
    FaceBuilder builder(b, surface, options, vinv);
    for (size_t f = begin; f < end; ++f) {
      if (worker == 0 && (f - begin) % 16 == 0) monitor.report("bind", 0.95 + 0.05 * double(f - begin) / double(end - begin));
      if (!by_ptex[f].empty()) builder.run(uint32_t(f), std::move(by_ptex[f]), &faces[f]);
    }
  });

  PatchDeformerTable table;
  table.local_frame = b.mode == DisplacementMode::local_frame;
  const bool local = table.local_frame;
  for (FaceOut& face : faces) {
    for (CellOut& cell : face.cells) {
      const float scale = float(std::ldexp(1.0, cell.depth));  // d/ds = 2^-depth d/du
      append(table.vertex, cell.vertices);
      append(table.s, cell.s);
      append(table.t, cell.t);
      for (uint32_t i : cell.vertices) {
        table.displacement.push_back(float(b.displacement[i]));
        const double* k = &b.normal_coefficients[6 * size_t(i)];
        for (int c = 0; c < 6; ++c) table.k[c].push_back(float(c % 3 == 2 ? k[c] : k[c] * scale));
        if (local) {
          table.tangent_a.push_back(float(b.tangent_offset[2 * size_t(i)]));
          table.tangent_b.push_back(float(b.tangent_offset[2 * size_t(i) + 1]));
        }
      }
      append(table.term_control, cell.controls);
      for (double m : cell.coefficients) table.term_coefficients.push_back(float(m));
      table.cell_depth.push_back(cell.depth);
      table.cell_vertex_offsets.push_back(uint32_t(table.vertex.size()));
      table.cell_term_offsets.push_back(uint32_t(table.term_control.size()));
    }
    for (uint32_t i : face.irregular) {
      table.irregular_vertex.push_back(i);
      for (uint32_t e = b.row_offsets[i]; e < b.row_offsets[i + 1]; ++e) {
        table.irregular_control.push_back(b.control_index[e]);
        table.irregular_w.push_back(b.phi[e]);
        table.irregular_wu.push_back(b.phi_u[e]);
        table.irregular_wv.push_back(b.phi_v[e]);
      }
      table.irregular_offsets.push_back(uint32_t(table.irregular_control.size()));
    }
    face = FaceOut();
  }
  // 7 lanes of padding: the deformer evaluates whole groups of 8 vertices.
  for (std::vector<float>* a : {&table.s, &table.t, &table.displacement, &table.k[0], &table.k[1], &table.k[2],
                                &table.k[3], &table.k[4], &table.k[5]})
    a->insert(a->end(), 7, 0.0f);
  if (local) table.tangent_a.insert(table.tangent_a.end(), 7, 0.0f), table.tangent_b.insert(table.tangent_b.end(), 7, 0.0f);
  invert(b.num_control_vertices, table.cell_term_offsets, table.term_control, &table.control_cell_offsets,
         &table.control_cells);
  invert(b.num_control_vertices, table.irregular_offsets, table.irregular_control, &table.control_irregular_offsets,
         &table.control_irregular);
  // A control vertex may appear twice in one irregular row (never in a cell): keep each item once.
  for (size_t j = 0; j < b.num_control_vertices; ++j) {
    auto first = table.control_irregular.begin() + table.control_irregular_offsets[j];
    auto last = table.control_irregular.begin() + table.control_irregular_offsets[j + 1];
    if (std::adjacent_find(first, last) != last) fail(Status::internal_error, "patch table: repeated control in a row");
  }
  return table;
}

CAGEKIT_NAMESPACE_END
