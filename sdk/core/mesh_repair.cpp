// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh repair, in the order of mesh_repair.h. Every step is O(n log n); welding with a
// tolerance sorts the points into grid cells and compares points of neighbouring cells only
// (quadratic only for pathological inputs: dense clumps of points just out of reach).
//
// Splitting non-manifold configurations works on corners (face-vertex slots): corners at a
// vertex that are joined across shared ("glued") edges form a fan, and every fan but the first
// gets its own copy of the vertex. Manifold edges are glued; on an edge with more than two
// faces the half-edges are paired (opposite directions first) only where the pair stays a
// two-face edge, so that e.g. two cubes touching along an edge come apart into two cubes and
// the third page of a "book" is detached from the first two. Whatever is still non-manifold
// after that (rare, tangled inputs) is resolved by detaching the faces beyond a consistent
// pair completely, and the fans are split once more.
#include "core/mesh_repair.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/edge_map.h"
#include "core/status.h"
#include "core/vertex_renumbering.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

using detail::kNone;

// Keeps the faces with keep[f] != 0, in order.
void filter_faces(PolygonMesh& m, const std::vector<uint8_t>& keep) {
  const size_t nf = m.num_faces();
  size_t w = 0, wf = 0;
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t b = m.face_offsets[f], e = m.face_offsets[f + 1];
    if (!keep[f]) continue;
    for (uint32_t c = b; c < e; ++c) m.face_vertices[w++] = m.face_vertices[c];
    m.face_offsets[++wf] = static_cast<uint32_t>(w);
  }
  m.face_vertices.resize(w);
  m.face_offsets.resize(wf + 1);
}

bool face_in_range(const PolygonMesh& m, size_t f) {
  const uint32_t* v = m.face_begin(f);
  for (uint32_t i = 0, n = m.face_size(f); i < n; ++i)
    if (v[i] >= m.num_vertices()) return false;
  return true;
}

// Faces that take part in the topology: valid indices, >= 3 vertices, none repeated.
std::vector<uint8_t> topological_faces(const PolygonMesh& m) {
  std::vector<uint8_t> topo(m.num_faces());
  for (size_t f = 0; f < m.num_faces(); ++f)
    topo[f] = m.face_size(f) >= 3 && face_in_range(m, f) &&
              detail::find_repeated_vertex(m.face_begin(f), m.face_size(f)) == kNone;
  return topo;
}

// ---- weld ----------------------------------------------------------------------------------

struct Cell {
  int64_t x, y, z;
  bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
  bool operator<(const Cell& o) const { return x != o.x ? x < o.x : (y != o.y ? y < o.y : z < o.z); }
};

// Cell coordinate floor(x / size). Where that does not fit (|x| / size >= 2^61), points within
// the tolerance of x must have exactly the coordinate x (the spacing of doubles there exceeds
// the tolerance): such coordinates get keys of their own beyond +-2^62 built from their bits.
int64_t cell_coord(double x, double size) {
  const double c = std::floor(x / size);
  if (std::fabs(c) < 2305843009213693952.0) return static_cast<int64_t>(c);  // 2^61
  uint64_t bits = 0;
  std::memcpy(&bits, &x, sizeof bits);
  const int64_t key = (int64_t(1) << 62) + static_cast<int64_t>((bits & ~(uint64_t(1) << 63)) >> 1);
  return x < 0 ? -key : key;
}

// Up to 2^31 cells from the origin, rounding in x / size cannot widen a cell past tol/sqrt(3)
// (size has a 2^-20 margin): all points of such a cell are within the tolerance.
bool cell_is_tight(const Cell& c) {
  const int64_t limit = int64_t(1) << 31;
  return c.x > -limit && c.x < limit && c.y > -limit && c.y < limit && c.z > -limit && c.z < limit;
}

// Unites the finite vertices within `tol` of each other (tol == 0: identical positions).
void weld_clusters(const PolygonMesh& m, double tol, detail::UnionFind& uf) {
  const size_t nv = m.num_vertices();
  std::vector<uint32_t> order;
  order.reserve(nv);
  for (size_t v = 0; v < nv; ++v)
    if (is_finite(m.positions[v])) order.push_back(static_cast<uint32_t>(v));
  const auto& p = m.positions;
  if (tol == 0) {
    auto less = [&](uint32_t a, uint32_t b) {
      if (p[a].x != p[b].x) return p[a].x < p[b].x;
      if (p[a].y != p[b].y) return p[a].y < p[b].y;
      if (p[a].z != p[b].z) return p[a].z < p[b].z;
      return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    for (size_t i = 1; i < order.size(); ++i)
      if (p[order[i]] == p[order[i - 1]]) uf.unite(order[i - 1], order[i]);
    return;
  }
  // Cells of side tol/sqrt(3): two points of one (tight) cell are within tol, so such a cell
  // is united at once (a huge tolerance costs nothing); points within tol lie at most 2 cells
  // apart per axis.
  double size = tol / 1.7320508075688774 * (1.0 - 1.0 / 1048576.0);
  if (!(size > 0)) size = std::numeric_limits<double>::denorm_min();
  std::vector<Cell> cell_of(nv);
  for (uint32_t v : order) cell_of[v] = {cell_coord(p[v].x, size), cell_coord(p[v].y, size), cell_coord(p[v].z, size)};
  auto position_less = [&](uint32_t a, uint32_t b) {
    if (p[a].x != p[b].x) return p[a].x < p[b].x;
    if (p[a].y != p[b].y) return p[a].y < p[b].y;
    return p[a].z < p[b].z;
  };
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    if (!(cell_of[a] == cell_of[b])) return cell_of[a] < cell_of[b];
    if (position_less(a, b)) return true;
    if (position_less(b, a)) return false;
    return a < b;
  });
  std::vector<uint32_t> cell_start;  // cell k holds order[cell_start[k] .. cell_start[k+1])
  std::vector<Cell> cells;           // sorted, unique
  for (size_t i = 0; i < order.size(); ++i) {
    if (i == 0 || !(cell_of[order[i]] == cell_of[order[i - 1]])) {
      cells.push_back(cell_of[order[i]]);
      cell_start.push_back(static_cast<uint32_t>(i));
    } else if (cell_is_tight(cell_of[order[i]]) || p[order[i]] == p[order[i - 1]]) {
      uf.unite(order[i - 1], order[i]);
    }
  }
  cell_start.push_back(static_cast<uint32_t>(order.size()));
  std::vector<uint8_t> tight(cells.size());
  for (size_t k = 0; k < cells.size(); ++k) tight[k] = cell_is_tight(cells[k]);
  const double tol2 = tol * tol;
  auto close = [&](uint32_t a, uint32_t b) {
    const Vec3 d = p[a] - p[b];
    return dot(d, d) <= tol2;
  };
  // Loose cells (far out, |x| > 2^31 tol): compare their distinct positions pairwise.
  std::vector<uint32_t> distinct;
  for (size_t k = 0; k < cells.size(); ++k) {
    if (tight[k]) continue;
    distinct.clear();
    for (uint32_t i = cell_start[k]; i < cell_start[k + 1]; ++i)
      if (i == cell_start[k] || p[order[i]] != p[order[i - 1]]) distinct.push_back(order[i]);
    for (size_t i = 1; i < distinct.size(); ++i)
      for (size_t j = 0; j < i; ++j)
        if (uf.find(distinct[i]) != uf.find(distinct[j]) && close(distinct[i], distinct[j]))
          uf.unite(distinct[i], distinct[j]);
  }
  auto join_cells = [&](size_t a, size_t b) {
    if (tight[a] && tight[b]) {  // both are one set already: one close pair joins them
      if (uf.find(order[cell_start[a]]) == uf.find(order[cell_start[b]])) return;
      for (uint32_t i = cell_start[a]; i < cell_start[a + 1]; ++i)
        for (uint32_t j = cell_start[b]; j < cell_start[b + 1]; ++j)
          if (close(order[i], order[j])) {
            uf.unite(order[i], order[j]);
            return;
          }
      return;
    }
    for (uint32_t i = cell_start[a]; i < cell_start[a + 1]; ++i)
      for (uint32_t j = cell_start[b]; j < cell_start[b + 1]; ++j)
        if (uf.find(order[i]) != uf.find(order[j]) && close(order[i], order[j])) uf.unite(order[i], order[j]);
  };
  // Neighbour rows (dx, dy) "after" the cell's own row, plus the own row for dz = 1, 2. Cells
  // are sorted, so for each row the first candidate (x+dx, y+dy, z-2) only moves forward: one
  // monotone cursor per row finds all neighbours in O(cells) overall.
  struct Row {
    int dx, dy, dz_min;
    size_t cursor;
  };
  std::vector<Row> rows;
  for (int dx = 0; dx <= 2; ++dx)
    for (int dy = -2; dy <= 2; ++dy)
      if (dx > 0 || dy >= 0) rows.push_back({dx, dy, dx == 0 && dy == 0 ? 1 : -2, 0});
  for (size_t a = 0; a < cells.size(); ++a) {
    const Cell ca = cells[a];
    for (Row& row : rows) {
      const Cell first{ca.x + row.dx, ca.y + row.dy, ca.z + row.dz_min};
      while (row.cursor < cells.size() && cells[row.cursor] < first) ++row.cursor;
      for (size_t b = row.cursor; b < cells.size(); ++b) {
        const Cell& cb = cells[b];
        if (cb.x != first.x || cb.y != first.y || cb.z > ca.z + 2) break;
        join_cells(a, b);
      }
    }
  }
}

uint64_t weld(PolygonMesh& m, double tol) {
  const size_t nv = m.num_vertices();
  detail::UnionFind uf(nv);
  weld_clusters(m, tol, uf);
  // Each cluster becomes its smallest vertex, numbered in the original order.
  std::vector<uint32_t> new_index(nv, kNone), root_index(nv, kNone);
  size_t count = 0;
  for (size_t v = 0; v < nv; ++v) {
    const uint32_t r = uf.find(static_cast<uint32_t>(v));
    if (root_index[r] == kNone) root_index[r] = static_cast<uint32_t>(count++);
    new_index[v] = root_index[r];
  }
  if (count == nv) return 0;
  remap_vertices(m, new_index, count);  // keeps the position of each cluster's first vertex
  return nv - count;
}

// ---- splitting ------------------------------------------------------------------------------

// Gives every class of corners (a fan) at a vertex its own vertex: the first class met in
// corner order keeps the vertex, the others get copies appended. Returns the copies made.
uint64_t split_fans(PolygonMesh& m, const std::vector<uint8_t>& topo, const detail::EdgeMap& map,
                    detail::UnionFind& corners) {
  const size_t nc = m.face_vertices.size();
  std::vector<uint32_t> class_vertex(nc, kNone);
  std::vector<uint8_t> taken(m.num_vertices(), 0);
  uint64_t added = 0;
  for (size_t c = 0; c < nc; ++c) {
    if (!topo[map.corner_face[c]]) continue;
    const uint32_t r = corners.find(static_cast<uint32_t>(c));
    if (class_vertex[r] == kNone) {
      const uint32_t v = m.face_vertices[r];  // the class root is a corner at the same vertex
      if (!taken[v]) {
        taken[v] = 1;
        class_vertex[r] = v;
      } else {
        const Vec3 copy = m.positions[v];
        class_vertex[r] = static_cast<uint32_t>(m.positions.size());
        m.positions.push_back(copy);
        ++added;
      }
    }
  }
  // Rewrite after the pass so that reading a root's vertex above never sees a rewritten slot.
  for (size_t c = 0; c < nc; ++c)
    if (topo[map.corner_face[c]]) m.face_vertices[c] = class_vertex[corners.find(static_cast<uint32_t>(c))];
  return added;
}

// Gives each corner of the faces with detach[f] its own new vertex. Returns the copies made.
uint64_t detach_faces(PolygonMesh& m, const std::vector<uint8_t>& detach) {
  uint64_t added = 0;
  for (size_t f = 0; f < m.num_faces(); ++f) {
    if (!detach[f]) continue;
    for (uint32_t c = m.face_offsets[f]; c < m.face_offsets[f + 1]; ++c) {
      const Vec3 copy = m.positions[m.face_vertices[c]];
      m.face_vertices[c] = static_cast<uint32_t>(m.positions.size());
      m.positions.push_back(copy);
      ++added;
    }
  }
  return added;
}

// Glues as many half-edges of a non-manifold edge in pairs as possible such that no group of
// half-edges that will share both endpoints after splitting has more than two members.
void pair_non_manifold_edge(const detail::EdgeMap& map, detail::UnionFind& uf, size_t e) {
  const uint32_t k = map.valence(e);
  const uint32_t* h = map.corners_begin(e);
  std::vector<uint32_t> lo(k), hi(k);
  auto refresh = [&] {
    for (uint32_t i = 0; i < k; ++i) {
      lo[i] = uf.find(map.corner_at_lo(h[i]));
      hi[i] = uf.find(map.corner_at_hi(h[i]));
    }
  };
  refresh();
  // Half-edges already sharing both fans with another are settled (pairs) or beyond help here.
  std::vector<uint32_t> idx(k);
  for (uint32_t i = 0; i < k; ++i) idx[i] = i;
  std::sort(idx.begin(), idx.end(), [&](uint32_t a, uint32_t b) {
    return lo[a] != lo[b] ? lo[a] < lo[b] : (hi[a] != hi[b] ? hi[a] < hi[b] : a < b);
  });
  std::vector<uint8_t> used(k, 0);
  for (uint32_t i = 0; i < k;) {
    uint32_t j = i + 1;
    while (j < k && lo[idx[j]] == lo[idx[i]] && hi[idx[j]] == hi[idx[i]]) ++j;
    if (j - i > 1)
      for (uint32_t t = i; t < j; ++t) used[idx[t]] = 1;
    i = j;
  }
  if (k > 64) return;  // pathological fan of pages: leave the singles as separate sheets
  for (int pass = 0; pass < 2; ++pass) {
    for (uint32_t i = 0; i < k; ++i) {
      if (used[i]) continue;
      for (uint32_t j = i + 1; j < k; ++j) {
        if (used[j]) continue;
        if (pass == 0 && map.forward(h[i]) == map.forward(h[j])) continue;
        refresh();
        uint32_t group = 0;
        for (uint32_t t = 0; t < k; ++t)
          group += (lo[t] == lo[i] || lo[t] == lo[j]) && (hi[t] == hi[i] || hi[t] == hi[j]);
        if (group > 2) continue;
        uf.unite(map.corner_at_lo(h[i]), map.corner_at_lo(h[j]));
        uf.unite(map.corner_at_hi(h[i]), map.corner_at_hi(h[j]));
        used[i] = used[j] = 1;
        break;
      }
    }
  }
}

// Splits fans with every edge of exactly two faces glued (unless cut[e]). Returns copies made.
uint64_t split_manifold_fans(PolygonMesh& m, const std::vector<uint8_t>& topo, const std::vector<uint8_t>* cut) {
  detail::EdgeMap map;
  detail::build_edge_map(map, m, topo);
  detail::UnionFind uf(m.face_vertices.size());
  detail::glue_fans(map, uf, [&](size_t e) { return map.valence(e) == 2 && !(cut && (*cut)[e]); });
  return split_fans(m, topo, map, uf);
}

uint64_t split_non_manifold(PolygonMesh& m, const std::vector<uint8_t>& topo) {
  uint64_t added = 0;
  bool any_non_manifold_edge = false;
  {
    detail::EdgeMap map;
    detail::build_edge_map(map, m, topo);
    detail::UnionFind uf(m.face_vertices.size());
    detail::glue_fans(map, uf, [&](size_t e) { return map.valence(e) == 2; });
    for (size_t e = 0; e < map.num_edges(); ++e)
      if (map.valence(e) > 2) {
        any_non_manifold_edge = true;
        pair_non_manifold_edge(map, uf, e);
      }
    added += split_fans(m, topo, map, uf);
  }
  if (!any_non_manifold_edge) return added;
  // Whatever edge still has more than two faces keeps a consistent pair; the rest is detached.
  detail::EdgeMap map;
  detail::build_edge_map(map, m, topo);
  std::vector<uint8_t> detach(m.num_faces(), 0);
  bool any = false;
  for (size_t e = 0; e < map.num_edges(); ++e) {
    const uint32_t k = map.valence(e);
    if (k <= 2) continue;
    const uint32_t* h = map.corners_begin(e);
    uint32_t second = 1;
    for (uint32_t j = 1; j < k; ++j)
      if (map.forward(h[j]) != map.forward(h[0])) {
        second = j;
        break;
      }
    for (uint32_t j = 1; j < k; ++j)
      if (j != second) detach[map.corner_face[h[j]]] = 1;
    any = true;
  }
  if (!any) return added;
  // A face kept by one edge may be detached by another: then both lose it, never gain one.
  added += detach_faces(m, detach);
  added += split_manifold_fans(m, topo, nullptr);
  return added;
}

// ---- orientation ---------------------------------------------------------------------------

void reverse_face(PolygonMesh& m, size_t f) {
  std::reverse(m.face_begin(f) + 1, m.face_vertices.data() + m.face_offsets[f + 1]);
}

struct OrientResult {
  uint64_t flipped = 0, non_orientable = 0, added = 0;
};

OrientResult orient(PolygonMesh& m, const std::vector<uint8_t>& topo, bool allow_cuts, const TaskMonitor& monitor) {
  OrientResult res;
  const size_t nf = m.num_faces();
  detail::EdgeMap map;
  detail::build_edge_map(map, m, topo);
  monitor.report("repair: orientation", 5.25 / 7);
  std::vector<uint8_t> flip(nf, 0), visited(nf, 0), conflict(map.num_edges(), 0);
  std::vector<uint32_t> component;
  bool any_conflict = false;
  for (size_t seed = 0; seed < nf; ++seed) {
    if (!topo[seed] || visited[seed]) continue;
    component.clear();
    component.push_back(static_cast<uint32_t>(seed));
    visited[seed] = 1;
    bool bad = false;
    for (size_t q = 0; q < component.size(); ++q) {
      const uint32_t f = component[q];
      if ((q & 0xFFFF) == 0xFFFF) monitor.report("repair: orientation", 5.5 / 7);
      for (uint32_t c = m.face_offsets[f]; c < m.face_offsets[f + 1]; ++c) {
        const uint32_t e = map.corner_edge[c];
        if (map.valence(e) != 2) continue;
        const uint32_t* h = map.corners_begin(e);
        const uint32_t other = h[0] == c ? h[1] : h[0];
        const uint32_t g = map.corner_face[other];
        const uint8_t want = flip[f] ^ static_cast<uint8_t>(map.forward(c) == map.forward(other));
        if (!visited[g]) {
          visited[g] = 1;
          flip[g] = want;
          component.push_back(g);
        } else if (flip[g] != want) {
          conflict[e] = 1;
          bad = true;
        }
      }
    }
    size_t flips = 0;
    for (uint32_t f : component) flips += flip[f];
    if (2 * flips > component.size())  // keep the majority's orientation
      for (uint32_t f : component) flip[f] ^= 1;
    if (bad) {
      ++res.non_orientable;
      any_conflict = true;
    }
  }
  for (size_t f = 0; f < nf; ++f)
    if (flip[f]) {
      reverse_face(m, f);
      ++res.flipped;
    }
  if (!any_conflict || !allow_cuts) return res;

  // Cut along the conflicting edges (the edge set, hence the edge ids, did not change).
  res.added += split_manifold_fans(m, topo, &conflict);
  // Edges that stay shared (both ends inside closed fans) lose one of their two faces.
  detail::EdgeMap map2;
  detail::build_edge_map(map2, m, topo);
  std::vector<uint8_t> detach(nf, 0);
  bool any = false;
  for (size_t e = 0; e < map2.num_edges(); ++e) {
    if (map2.valence(e) != 2) continue;
    const uint32_t* h = map2.corners_begin(e);
    if (map2.forward(h[0]) != map2.forward(h[1])) continue;
    detach[std::max(map2.corner_face[h[0]], map2.corner_face[h[1]])] = 1;
    any = true;
  }
  if (any) {
    res.added += detach_faces(m, detach);
    res.added += split_manifold_fans(m, topo, nullptr);
  }
  return res;
}

}  // namespace

PolygonMesh repair_mesh(const PolygonMesh& mesh, const RepairOptions& options, RepairReport* report,
                        const TaskMonitor& monitor) {
  detail::check_mesh_arrays(mesh);
  if (std::isnan(options.weld_tolerance) || std::isinf(options.weld_tolerance))
    fail(Status::invalid_argument, "weld tolerance must be a finite number (negative disables welding)");
  RepairReport rep;
  PolygonMesh m = mesh;

  monitor.report("repair: weld", 0.0);
  if (options.weld_tolerance >= 0) rep.welded_vertices = weld(m, options.weld_tolerance);

  monitor.report("repair: invalid faces", 1.0 / 7);
  if (options.drop_invalid_faces) {
    const size_t nv = m.num_vertices();
    std::vector<uint8_t> finite(nv);
    for (size_t v = 0; v < nv; ++v) finite[v] = is_finite(m.positions[v]);
    std::vector<uint8_t> keep(m.num_faces(), 1);
    for (size_t f = 0; f < m.num_faces(); ++f) {
      const uint32_t* v = m.face_begin(f);
      for (uint32_t i = 0, n = m.face_size(f); i < n && keep[f]; ++i) keep[f] = v[i] < nv && finite[v[i]];
      rep.dropped_invalid_faces += !keep[f];
    }
    if (rep.dropped_invalid_faces) filter_faces(m, keep);
    rep.removed_non_finite_vertices = keep_vertices(m, finite);
  }

  monitor.report("repair: degenerate faces", 2.0 / 7);
  if (options.drop_degenerate_faces) {
    std::vector<uint8_t> keep(m.num_faces(), 1);
    for (size_t f = 0; f < m.num_faces(); ++f) {
      const uint32_t n = m.face_size(f);
      const uint32_t* v = m.face_begin(f);
      bool degenerate = n < 3 || detail::find_repeated_vertex(v, n) != kNone;
      if (!degenerate && face_in_range(m, f)) {
        bool finite = true;
        for (uint32_t i = 0; i < n; ++i) finite = finite && is_finite(m.positions[v[i]]);
        degenerate = finite && detail::face_has_zero_area(m, f);
      }
      keep[f] = !degenerate;
      rep.dropped_degenerate_faces += degenerate;
    }
    if (rep.dropped_degenerate_faces) filter_faces(m, keep);
  }

  monitor.report("repair: duplicate faces", 3.0 / 7);
  if (options.drop_duplicate_faces) {
    std::vector<uint32_t> dup_of;
    std::vector<uint8_t> reversed;
    detail::find_duplicate_faces(m, topological_faces(m), dup_of, reversed);
    std::vector<uint8_t> keep(m.num_faces(), 1);
    for (size_t f = 0; f < m.num_faces(); ++f)
      if (dup_of[f] != kNone) {
        keep[f] = 0;
        ++rep.dropped_duplicate_faces;
      }
    if (rep.dropped_duplicate_faces) filter_faces(m, keep);
  }

  // Faces of the topology no longer change from here on (only their vertex numbers).
  const std::vector<uint8_t> topo = topological_faces(m);
  monitor.report("repair: non-manifold", 4.0 / 7);
  if (options.split_non_manifold) rep.split_vertices += split_non_manifold(m, topo);

  monitor.report("repair: orientation", 5.0 / 7);
  if (options.orient_consistently) {
    const OrientResult o = orient(m, topo, options.split_non_manifold, monitor);
    rep.flipped_faces = o.flipped;
    rep.non_orientable_components = o.non_orientable;
    rep.split_vertices += o.added;
    if (o.non_orientable)
      monitor.log(LogLevel::warning, std::to_string(o.non_orientable) +
                                         " component(s) cannot be oriented consistently (non-orientable); " +
                                         (options.split_non_manifold ? "they were cut open along the conflicting edges"
                                                                     : "the majority orientation was kept"));
  }

  monitor.report("repair: unreferenced vertices", 6.0 / 7);
  if (options.remove_unreferenced_vertices) {
    const size_t nv = m.num_vertices();
    std::vector<uint8_t> used(nv, 0);
    for (uint32_t v : m.face_vertices)
      if (v < nv) used[v] = 1;
    rep.removed_unreferenced_vertices = keep_vertices(m, used);
  }
  monitor.report("repair: done", 1.0);
  if (report) *report = rep;
  return m;
}

CAGEKIT_NAMESPACE_END
