// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The local parameterization domain Ω of thesis §5.5.3 / Fig. 5.7 (spec thesis-ch4-6.md §1.3):
// a set R of input triangles unfolded isometrically into the plane around the front of the line
// being integrated. Ω starts with one face (its canonical frame: corner 0 at the origin, corner 1
// on +u, corner 2 at v > 0), grows by rotating the one unassigned vertex of a neighbour across
// each crossed edge (case a) and is reset at a vertex through the polar map of the vertex's
// 1-ring [WW94] (case b).
//
// Decisions [J]: a neighbour reached along a path whose unfolding disagrees with the placement
// it already has in Ω (the path went around a vertex with angle defect) is used with the path's
// placement and Ω is then reset at the face the walk ended in; Ω is also reset when it holds
// more than `max_faces` faces, so it stays local and small.
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/polygon_mesh.h"
#include "core/vec2.h"
#include "layout/anisotropic/line_sample_database.h"

CAGEKIT_NAMESPACE_BEGIN

// Rigid map from a face's canonical frame into Ω: p -> R(angle) p + t.
struct Placement {
  double c = 1.0, s = 0.0;
  Vec2 t;
  Vec2 apply(Vec2 p) const { return {c * p.x - s * p.y + t.x, s * p.x + c * p.y + t.y}; }
  Vec2 rotate(Vec2 d) const { return {c * d.x - s * d.y, s * d.x + c * d.y}; }
  Vec2 unrotate(Vec2 d) const { return {c * d.x + s * d.y, -s * d.x + c * d.y}; }
  Vec2 invert(Vec2 p) const { return unrotate(p - t); }
};

// Canonical frame of a triangle: corner positions and the 3D axes (u, v, n).
struct FaceFrame {
  std::array<Vec2, 3> corner;
  Vec3 origin, u, v, n;
};
FaceFrame face_frame(const PolygonMesh& triangles, uint32_t face);

// Where a walk in Ω ended.
struct WalkEnd {
  enum Kind { reached, boundary, feature, vertex, stuck } kind = reached;
  uint32_t face = 0;
  Placement placement;       // of `face` as the walk used it
  Vec2 point;                // in Ω
  uint32_t corner = detail::kNone;  // boundary/feature: the corner whose edge was hit; vertex: corner at the vertex
};

class LocalUnfolding {
 public:
  LocalUnfolding(const PolygonMesh& triangles, const TriangleAdjacency& adjacency, size_t max_faces = 128);

  // R = {face}, Ω = the face's canonical frame.
  void reset(uint32_t face);
  // Re-roots Ω at end.face (whose placement may be a transient one) and maps `point` and the
  // directions in `dirs` into the new frame.
  void reroot(const WalkEnd& end, Vec2& point, std::vector<Vec2*> dirs);
  bool needs_reset() const { return needs_reset_; }
  const Placement* placement(uint32_t face) const;

  // Walks the straight segment from `from` (in Ω, inside `face`) to `to`, unfolding the faces it
  // crosses (case a). on_piece(face, placement, a, b, vertex_a, vertex_b) is called for each part inside one
  // face (not called when `record` is false). Stops at boundary edges, at feature edges when
  // stop_at_features, and at input vertices (the point is snapped onto them).
  template <class OnPiece>
  WalkEnd walk(uint32_t face, Vec2 from, Vec2 to, bool stop_at_features, OnPiece&& on_piece);
  WalkEnd walk(uint32_t face, Vec2 from, Vec2 to, bool stop_at_features) {
    return walk(face, from, to, stop_at_features, [](uint32_t, const Placement&, Vec2, Vec2, uint32_t, uint32_t) {});
  }

  // Case b: the point sits on the vertex of `corner` (a corner of `face`, which is in Ω) and the
  // line leaves in direction `dir` (Ω). Picks, through the polar map of the 1-ring, the face of the
  // fan that direction enters, resets Ω there and returns the face, the vertex position and the
  // direction in the new Ω. False when the direction leaves the surface (boundary vertex) or
  // the fan cannot be walked.
  bool leave_vertex(uint32_t face, uint32_t corner, Vec2 dir, uint32_t& out_face, Vec2& out_point, Vec2& out_dir);

  // Barycentric coordinates of an Ω point in a placed face.
  std::array<double, 3> barycentric(uint32_t face, const Placement& pl, Vec2 p) const;
  Vec3 position(uint32_t face, const Placement& pl, Vec2 p) const;
  // A tangent direction of the face (3D) in Ω and back.
  Vec2 to_omega(uint32_t face, const Placement& pl, const Vec3& d) const;
  Vec3 to_space(uint32_t face, const Placement& pl, Vec2 d) const;
  FaceFrame frame(uint32_t face) const { return face_frame(mesh_, face); }

 private:
  Placement neighbour_placement(uint32_t face, const Placement& pl, uint32_t corner, uint32_t twin) const;
  Placement place(uint32_t face, const Placement& pl, uint32_t corner, uint32_t twin);

  const PolygonMesh& mesh_;
  const TriangleAdjacency& adj_;
  size_t max_faces_;
  std::unordered_map<uint32_t, Placement> omega_;
  bool needs_reset_ = false;
};

template <class OnPiece>
WalkEnd LocalUnfolding::walk(uint32_t face, Vec2 from, Vec2 to, bool stop_at_features, OnPiece&& on_piece) {
  constexpr double kSnap = 1e-7;
  WalkEnd end;
  const Placement* start = placement(face);
  Placement pl = start ? *start : Placement{};
  Vec2 p = from;
  uint32_t p_vertex = detail::kNone;
  for (int crossing = 0; crossing < 100000; ++crossing) {
    const std::array<double, 3> bq = barycentric(face, pl, to);
    if (bq[0] >= -1e-12 && bq[1] >= -1e-12 && bq[2] >= -1e-12) {
      on_piece(face, pl, p, to, p_vertex, detail::kNone);
      end.kind = WalkEnd::reached;
      end.face = face;
      end.placement = pl;
      end.point = to;
      return end;
    }
    const std::array<double, 3> bp = barycentric(face, pl, p);
    double best = 2.0;
    int edge = -1;
    for (int i = 0; i < 3; ++i) {
      if (bq[i] >= 0.0) continue;
      const double denom = bp[i] - bq[i];
      const double t = denom > 0.0 ? std::max(0.0, bp[i]) / denom : 0.0;
      if (t < best) {
        best = t;
        edge = i;
      }
    }
    if (edge < 0) break;
    Vec2 x = p + best * (to - p);
    const std::array<double, 3> bx = barycentric(face, pl, x);
    for (int j = 0; j < 3; ++j)
      if (bx[j] > 1.0 - kSnap) {  // through an input vertex: snap and stop there
        const FaceFrame fr = frame(face);
        x = pl.apply(fr.corner[j]);
        const uint32_t v = mesh_.face_vertices[3 * face + j];
        on_piece(face, pl, p, x, p_vertex, v);
        end.kind = WalkEnd::vertex;
        end.face = face;
        end.placement = pl;
        end.point = x;
        end.corner = 3 * face + j;
        return end;
      }
    on_piece(face, pl, p, x, p_vertex, detail::kNone);
    p_vertex = detail::kNone;
    const uint32_t c = 3 * face + uint32_t((edge + 1) % 3);  // half-edge opposite corner `edge`
    const uint32_t tw = adj_.twin[c];
    end.face = face;
    end.placement = pl;
    end.point = x;
    end.corner = c;
    if (tw == detail::kNone) {
      end.kind = WalkEnd::boundary;
      return end;
    }
    if (stop_at_features && adj_.feature[c]) {
      end.kind = WalkEnd::feature;
      return end;
    }
    pl = place(face, pl, c, tw);
    face = tw / 3;
    p = x;
  }
  end.kind = WalkEnd::stuck;
  end.face = face;
  end.placement = pl;
  end.point = p;
  return end;
}

CAGEKIT_NAMESPACE_END
