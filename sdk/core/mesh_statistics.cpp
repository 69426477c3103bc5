// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh statistics. The topology (edges, boundary, components, Euler characteristic, genus) is
// computed over the faces with valid indices, at least 3 vertices and no repeated vertex; any
// other face makes the mesh non-manifold. Boundary loops are the independent cycles of the
// boundary-edge graph (E_b - V_b + C_b): for a manifold mesh every boundary vertex has two
// boundary edges and this is exactly the number of loops, whatever the faces' orientation; for
// a non-manifold mesh (a bow-tie) it still counts each closed boundary walk once.
#include "core/mesh_statistics.h"

#include "core/edge_map.h"

CAGEKIT_NAMESPACE_BEGIN

MeshStatistics compute_mesh_statistics(const Cage& cage) {
  MeshStatistics s = compute_mesh_statistics(cage.mesh);
  s.creases = cage.creases.size();
  s.corners = cage.corners.size();
  s.holes = cage.holes.size();
  return s;
}

MeshStatistics compute_mesh_statistics(const PolygonMesh& mesh, const TaskMonitor& monitor) {
  using detail::kNone;
  detail::check_mesh_arrays(mesh);
  MeshStatistics s;
  const size_t nv = mesh.num_vertices(), nf = mesh.num_faces(), nc = mesh.face_vertices.size();
  s.vertices = nv;
  s.faces = nf;
  for (const Vec3& p : mesh.positions)
    if (is_finite(p)) s.bbox.extend(p);
  s.bbox_diagonal = s.bbox.diagonal();

  bool manifold = true;
  std::vector<uint8_t> topo(nf, 0);
  std::vector<uint8_t> referenced(nv, 0);
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t n = mesh.face_size(f);
    if (n == 3) ++s.triangles;
    else if (n == 4) ++s.quads;
    else ++s.other_polygons;
    const uint32_t* fv = mesh.face_begin(f);
    bool in_range = true;
    for (uint32_t i = 0; i < n; ++i) {
      if (fv[i] < nv) referenced[fv[i]] = 1;
      else in_range = false;
    }
    topo[f] = in_range && n >= 3 && detail::find_repeated_vertex(fv, n) == kNone;
    if (!topo[f]) {
      manifold = false;
      ++s.invalid_faces;
    }
  }
  for (size_t v = 0; v < nv; ++v) s.unreferenced_vertices += !referenced[v];
  monitor.report("statistics", 0.1);

  detail::EdgeMap map;
  detail::build_edge_map(map, mesh, topo);
  const size_t ne = map.num_edges();
  s.edges = ne;
  monitor.report("statistics", 0.4);

  // Vertex components (faces joined through shared vertices), fans, orientability.
  detail::UnionFind comp(nv);
  std::vector<uint8_t> used(nv, 0);
  uint64_t topo_faces = 0;
  for (size_t f = 0; f < nf; ++f) {
    if (!topo[f]) continue;
    ++topo_faces;
    const uint32_t* fv = mesh.face_begin(f);
    const uint32_t n = mesh.face_size(f);
    for (uint32_t i = 0; i < n; ++i) {
      used[fv[i]] = 1;
      comp.unite(fv[0], fv[i]);
    }
  }
  detail::UnionFind corners(nc);
  detail::glue_fans(map, corners, [](size_t) { return true; });
  monitor.report("statistics", 0.6);
  {
    std::vector<uint8_t> has_fan(nv, 0);
    for (size_t c = 0; c < nc && manifold; ++c) {
      if (!topo[map.corner_face[c]] || corners.find(static_cast<uint32_t>(c)) != c) continue;
      const uint32_t v = mesh.face_vertices[c];
      if (has_fan[v]) manifold = false;
      has_fan[v] = 1;
    }
  }

  // Orientability: a union-find over faces with the parity "flipped relative to the root";
  // two faces sharing a manifold edge the same way must have opposite parity.
  bool orientable = true;
  {
    std::vector<uint32_t> parent(nf);
    std::vector<uint8_t> parity(nf, 0);
    for (size_t f = 0; f < nf; ++f) parent[f] = static_cast<uint32_t>(f);
    auto find = [&](uint32_t x, uint8_t& p) {
      p = 0;
      uint32_t r = x;
      while (parent[r] != r) {
        p ^= parity[r];
        r = parent[r];
      }
      // Path compression with parity bookkeeping.
      uint8_t acc = p;
      while (parent[x] != x) {
        const uint32_t next = parent[x];
        const uint8_t px = parity[x];
        parent[x] = r;
        parity[x] = acc;
        acc ^= px;
        x = next;
      }
      return r;
    };
    for (size_t e = 0; e < ne && orientable; ++e) {
      if (map.valence(e) != 2) continue;
      const uint32_t* h = map.corners_begin(e);
      const uint8_t want = map.forward(h[0]) == map.forward(h[1]);  // 1: must differ in flip
      uint8_t pa = 0, pb = 0;
      const uint32_t ra = find(map.corner_face[h[0]], pa), rb = find(map.corner_face[h[1]], pb);
      if (ra == rb) {
        if ((pa ^ pb) != want) orientable = false;
      } else {
        parent[rb] = ra;
        parity[rb] = pa ^ pb ^ want;
      }
    }
  }

  monitor.report("statistics", 0.8);
  // Per component: V, E, F, boundary edges, boundary vertices, boundary graph components.
  std::vector<int64_t> chi(nv, 0), loops(nv, 0);
  detail::UnionFind boundary(nv);
  std::vector<uint8_t> on_boundary(nv, 0);
  int64_t used_vertices = 0;
  for (size_t v = 0; v < nv; ++v)
    if (used[v]) {
      ++used_vertices;
      ++chi[comp.find(static_cast<uint32_t>(v))];
    }
  for (size_t f = 0; f < nf; ++f)
    if (topo[f]) ++chi[comp.find(mesh.face_vertices[mesh.face_offsets[f]])];
  for (size_t e = 0; e < ne; ++e) {
    const uint32_t a = map.edge_lo[e], b = map.edge_hi[e];
    const uint32_t r = comp.find(a);
    --chi[r];
    const uint32_t k = map.valence(e);
    if (k > 2) manifold = false;
    if (k != 1) continue;
    ++s.boundary_edges;
    ++loops[r];  // + E_b
    on_boundary[a] = on_boundary[b] = 1;
    boundary.unite(a, b);
  }
  for (size_t v = 0; v < nv; ++v) {
    if (!on_boundary[v]) continue;
    const uint32_t r = comp.find(static_cast<uint32_t>(v));
    --loops[r];                                               // - V_b
    if (boundary.find(static_cast<uint32_t>(v)) == v) ++loops[r];  // + C_b
  }
  int64_t genus2 = 0;
  bool genus_ok = manifold && orientable;
  for (size_t v = 0; v < nv; ++v) {
    if (!used[v] || comp.find(static_cast<uint32_t>(v)) != v) continue;
    ++s.components;
    s.boundary_loops += static_cast<uint64_t>(loops[v] > 0 ? loops[v] : 0);
    const int64_t g2 = 2 - loops[v] - chi[v];
    if (g2 < 0 || g2 % 2 != 0) genus_ok = false;
    genus2 += g2;
  }
  s.euler_characteristic = used_vertices - static_cast<int64_t>(ne) + static_cast<int64_t>(topo_faces);
  s.manifold = manifold;
  s.genus = genus_ok ? genus2 / 2 : -1;
  return s;
}

CAGEKIT_NAMESPACE_END
