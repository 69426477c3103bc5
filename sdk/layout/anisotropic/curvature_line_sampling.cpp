// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/anisotropic/curvature_line_sampling.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <random>
#include <string>

#include "core/angles.h"
#include "core/status.h"
#include "layout/anisotropic/local_unfolding.h"

CAGEKIT_NAMESPACE_BEGIN

double line_spacing(double kappa, double epsilon, double min_spacing, double max_spacing) {
  const double k = std::fabs(kappa);
  if (!(k > 0.0) || !std::isfinite(k)) return max_spacing;
  const double under = epsilon * (2.0 / k - epsilon);  // (5.10)
  if (!(under > 0.0)) return min_spacing;
  return std::clamp(2.0 * std::sqrt(under), min_spacing, max_spacing);
}

namespace {

const double kCos45 = std::cos(kPi / 4.0);

struct Seed {
  uint32_t face;
  Vec3 point;
  LineType type;
  Vec3 hint;           // initial direction where the field is not trusted (3D, tangent)
  bool forced = false;  // start along the field even in an unreliable face (fallback seeds)
};

class Sampler {
 public:
  Sampler(const PolygonMesh& mesh, const CurvatureField& field, const LineSamplingOptions& o, LineSampling& out,
          const TaskMonitor& monitor)
      : mesh_(mesh), field_(field), o_(o), out_(out), db_(*out.database), adj_(*out.adjacency),
        unf_(mesh, *out.adjacency), monitor_(monitor), rng_(o.random_seed) {
    eps_ = out.epsilon;
    dmin_ = out.min_spacing;
    dmax_ = out.max_spacing;
    min_feature_length_ = o.min_feature_length * dmin_;
    corner_angle_.resize(mesh.num_face_vertices());
    for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
      const FlattenedFace ff = flatten_face(mesh, field, f);
      for (int k = 0; k < 3; ++k) {
        const auto& d = ff.t_min[k];
        corner_angle_[3 * f + k] = (d[0] == 0.0 && d[1] == 0.0) ? NAN : float(std::atan2(d[1], d[0]));
      }
    }
  }

  void run();

 private:
  bool confident(uint32_t f) const { return field_.face_confidence[f] >= o_.confidence_threshold; }
  std::array<double, 3> weights(uint32_t f, const Placement& pl, Vec2 p) const;
  // Spacing of lines of type t at a point: D of (5.10) with κ of the other type.
  double spacing(LineType t, uint32_t f, const std::array<double, 3>& w) const;
  Vec2 field_direction(uint32_t f, const Placement& pl, Vec2 p, LineType t, Vec2 ref) const;
  Vec2 direction_at(uint32_t f, Vec2 from, Vec2 to, LineType t, Vec2 ref);
  bool collides(uint32_t f, const Vec3& p, const Vec3& dir, LineType t, bool trusted, double r, uint32_t line,
                double arc, bool& near_start);
  void add_seed(uint32_t f, const Vec3& p, LineType t, const Vec3& hint) {
    seeds_.push_back({f, p, t, hint, false});
  }
  bool crosses_transversal(uint32_t f, const Vec3& a, const Vec3& b, uint32_t line, LineType t) const;
  bool trace(const Seed& s);
  struct Pass {
    Pass(uint32_t f, Vec2 p, Vec2 d, LineType t, double s) : face(f), point(p), dir(d), type(t), sign(s) {}
    uint32_t face;
    Vec2 point, dir;
    LineType type;
    double sign;
    std::vector<uint32_t> segments;
    bool closed = false;
    bool open_end = false;  // stopped by a collision with no transversal line within reach
    uint32_t end_face = 0;
    Vec3 end_point, end_dir;
  };
  struct OpenEnd {
    uint32_t line;
    bool at_front;
    uint32_t face;
    Vec3 point, dir;
    LineType type;
  };
  void run_pass(Pass& pass, uint32_t line, bool trusted_start, const Vec3& start_point, bool extend_only = false);
  void extend_open_ends();
  std::vector<OpenEnd> open_ends_;
  void feature_and_boundary_lines();
  void initial_seeds();
  void sweep();
  void drain();
  bool full() {
    if (out_.lines.size() >= o_.max_lines || db_.num_segments() >= o_.max_segments) out_.truncated = true;
    return out_.truncated;
  }

  const PolygonMesh& mesh_;
  const CurvatureField& field_;
  const LineSamplingOptions& o_;
  LineSampling& out_;
  LineSampleDatabase& db_;
  const TriangleAdjacency& adj_;
  LocalUnfolding unf_;
  const TaskMonitor& monitor_;
  std::mt19937 rng_;
  std::vector<float> corner_angle_;
  std::deque<Seed> seeds_;
  double eps_ = 0, dmin_ = 0, dmax_ = 0, min_feature_length_ = 0;
};

std::array<double, 3> Sampler::weights(uint32_t f, const Placement& pl, Vec2 p) const {
  std::array<double, 3> w = unf_.barycentric(f, pl, p);
  double sum = 0.0;
  for (double& x : w) {
    x = std::isfinite(x) ? std::clamp(x, 0.0, 1.0) : 1.0;
    sum += x;
  }
  for (double& x : w) x /= sum;
  return w;
}

double Sampler::spacing(LineType t, uint32_t f, const std::array<double, 3>& w) const {
  double k = 0.0;
  for (int i = 0; i < 3; ++i) {
    const uint32_t v = mesh_.face_vertices[3 * f + i];
    k += w[i] * std::fabs(t == LineType::min_curvature ? field_.vertex_k_max[v] : field_.vertex_k_min[v]);
  }
  return line_spacing(k, eps_, dmin_, dmax_);
}

// q of (5.11): the flattened t_min (or t_max) of the corners, each signed to agree with `ref`
// (direction fields are line fields), blended barycentrically.
Vec2 Sampler::field_direction(uint32_t f, const Placement& pl, Vec2 p, LineType t, Vec2 ref) const {
  const std::array<double, 3> w = weights(f, pl, p);
  Vec2 q;
  for (int k = 0; k < 3; ++k) {
    const float a = corner_angle_[3 * f + k];
    if (std::isnan(a)) continue;
    const double ang = double(a) + (t == LineType::max_curvature ? 0.5 * kPi : 0.0);
    const Vec2 d = pl.rotate({std::cos(ang), std::sin(ang)});
    q = q + (dot(d, ref) < 0.0 ? -w[k] : w[k]) * d;
  }
  const double len = norm(q);
  return len > 1e-9 ? (1.0 / len) * q : ref;
}

// The field direction at an RK4 evaluation point: walk there from the current point (growing Ω,
// case a) and sample the face reached; points beyond a boundary or crease use the last face.
Vec2 Sampler::direction_at(uint32_t f, Vec2 from, Vec2 to, LineType t, Vec2 ref) {
  const WalkEnd e = unf_.walk(f, from, to, true);
  return field_direction(e.face, e.placement, e.point, t, ref);
}

bool Sampler::collides(uint32_t f, const Vec3& p, const Vec3& dir, LineType t, bool trusted, double r,
                       uint32_t line, double arc, bool& near_start) {
  bool hit = false;
  Vec3 mean{};
  db_.query(f, p, r, [&](uint32_t id, double) {
    const LineSegment& s = db_.segment(id);
    if (s.line == detail::kNone) return true;  // withdrawn stub
    const Vec3 d = s.b - s.a;
    const double len = norm(d);
    if (s.line == line) {
      // The line's own recent samples are always near; older ones mean it came back.
      if (std::fabs(s.arc - arc) < 3.0 * r) return true;
      if (std::fabs(s.arc) < r) near_start = true;
      hit = true;
      return false;
    }
    if (!(len > 0.0)) return true;
    if (!is_curvature_line(s.type)) {  // feature/boundary lines block lines running along them [J]
      if (std::fabs(dot(d, dir)) > kCos45 * len * norm(dir)) {
        hit = true;
        return false;
      }
      return true;
    }
    if (trusted && s.trusted) {
      if (s.type == t) {
        hit = true;
        return false;
      }
      return true;
    }
    mean = mean + (dot(d, dir) < 0.0 ? -1.0 : 1.0) * d;  // type-less test of §5.5.5
    return true;
  });
  if (!hit && norm(mean) > 0.0 && std::fabs(dot(mean, dir)) > kCos45 * norm(mean) * norm(dir)) hit = true;
  return hit;
}

void Sampler::run_pass(Pass& ps, uint32_t line, bool trusted_start, const Vec3& start_point, bool extend_only) {
  std::vector<Vec3> history;
  {
    const Placement* pl = unf_.placement(ps.face);
    history.push_back(unf_.to_space(ps.face, *pl, ps.dir));
  }
  bool trusted_mode = trusted_start;
  double arc = 0.0, since_seed = 0.0, step_arc = 0.0, seed_spacing = 0.0;
  uint32_t at_vertex = detail::kNone, start_vertex = detail::kNone;
  // After a collision the line is extended until it crosses a transversal line (or gives up
  // after max_spacing), so that it ends in a T-joint instead of leaving a gap that no line
  // crosses [J] (the thesis stops at the collision point; its limitation 1).
  bool extending = extend_only, crossed = false;
  int stalled = 0;
  double extension = 0.0;
  size_t extension_start = 0;
  const double scale_eps = 1e-12 * out_.bbox_diagonal;
  auto on_piece = [&](uint32_t g, const Placement& pl, Vec2 a, Vec2 b, uint32_t va, uint32_t vb) {
    LineSegment s;
    s.a = unf_.position(g, pl, a);
    s.b = unf_.position(g, pl, b);
    const double len = distance(s.a, s.b);
    if (len <= scale_eps) {  // nothing to store; the end vertex (if any) starts the next piece
      if (vb != detail::kNone) start_vertex = vb;
      return;
    }
    s.face = g;
    s.line = line;
    s.vertex_a = va != detail::kNone ? va : start_vertex;
    s.vertex_b = vb;
    start_vertex = detail::kNone;
    s.arc = ps.sign * (arc + step_arc);
    s.type = ps.type;
    s.trusted = trusted_mode;
    ps.segments.push_back(db_.insert(s));
    step_arc += len;
    if (extending) {
      extension += len;
      crossed |= crosses_transversal(g, s.a, s.b, line, ps.type);
      return;
    }
    // Seeds of the opposite type every D(p) of arc (κ of this line's type), placed exactly [R].
    if (!trusted_mode || !(seed_spacing > 0.0) || !(len > 0.0)) return;
    double used = 0.0;
    while (since_seed + (len - used) >= seed_spacing) {
      used += seed_spacing - since_seed;
      since_seed = 0.0;
      const Vec3 d = s.b - s.a;
      add_seed(g, s.a + (used / len) * d, opposite_type(ps.type), cross(unf_.frame(g).n, d));
    }
    since_seed += len - used;
  };
  for (int step = 0; step < o_.max_steps_per_pass; ++step) {
    if (db_.num_segments() >= o_.max_segments) {
      out_.truncated = true;
      return;
    }
    ++out_.steps;
    if (at_vertex != detail::kNone) {  // case b of Fig. 5.7
      start_vertex = mesh_.face_vertices[at_vertex];
      if (!unf_.leave_vertex(ps.face, at_vertex, ps.dir, ps.face, ps.point, ps.dir)) return;
      at_vertex = detail::kNone;
    }
    const Placement pl = *unf_.placement(ps.face);
    const std::array<double, 3> w = weights(ps.face, pl, ps.point);
    const bool conf = confident(ps.face);
    if (conf && !trusted_mode) {  // leaving an unreliable region: the type may switch
      const Vec2 tmin = field_direction(ps.face, pl, ps.point, LineType::min_curvature, ps.dir);
      const Vec2 tmax = field_direction(ps.face, pl, ps.point, LineType::max_curvature, ps.dir);
      ps.type = std::fabs(dot(ps.dir, tmin)) >= std::fabs(dot(ps.dir, tmax)) ? LineType::min_curvature
                                                                              : LineType::max_curvature;
      trusted_mode = true;
    } else if (!conf && trusted_mode) {  // entering one: follow t_tr, a geodesic in Ω
      Vec3 mean{};
      for (const Vec3& d : history) mean = mean + (dot(d, history.back()) < 0.0 ? -1.0 : 1.0) * d;
      const Vec2 d = unf_.to_omega(ps.face, pl, mean);
      if (norm(d) > 0.0) ps.dir = (1.0 / norm(d)) * d;
      trusted_mode = false;
    }
    const double S = spacing(ps.type, ps.face, w);
    const double h = o_.step_fraction * S;
    Vec2 q = ps.dir;
    if (trusted_mode) {  // RK4 (5.11)
      const Vec2 k1 = field_direction(ps.face, pl, ps.point, ps.type, ps.dir);
      const Vec2 k2 = direction_at(ps.face, ps.point, ps.point + 0.5 * h * k1, ps.type, k1);
      const Vec2 k3 = direction_at(ps.face, ps.point, ps.point + 0.5 * h * k2, ps.type, k1);
      const Vec2 k4 = direction_at(ps.face, ps.point, ps.point + h * k3, ps.type, k1);
      const Vec2 sum = k1 + 2.0 * k2 + 2.0 * k3 + k4;
      if (norm(sum) > 0.0) q = (1.0 / norm(sum)) * sum;
    }
    step_arc = 0.0;
    seed_spacing = trusted_mode ? spacing(opposite_type(ps.type), ps.face, w) : 0.0;
    WalkEnd e = unf_.walk(ps.face, ps.point, ps.point + h * q, true, on_piece);
    arc += step_arc;
    // No progress (e.g. bouncing on an input vertex) or an absurd length: end the pass.
    stalled = step_arc < 1e-6 * h ? stalled + 1 : 0;
    if (stalled >= 3 || arc > 100.0 * out_.bbox_diagonal) return;
    ps.face = e.face;
    ps.point = e.point;
    ps.dir = q;
    if (unf_.needs_reset() || !unf_.placement(e.face)) unf_.reroot(e, ps.point, {&ps.dir});
    if (e.kind == WalkEnd::boundary || e.kind == WalkEnd::feature || e.kind == WalkEnd::stuck) return;
    if (e.kind == WalkEnd::vertex) {
      // A vertex on a crease or the boundary ends a curvature line like the edge would.
      const uint32_t v = mesh_.face_vertices[e.corner];
      bool barrier = false;
      db_.for_each_at_vertex(v, [&](uint32_t id) { barrier |= !is_curvature_line(db_.segment(id).type); });
      if (barrier) return;
      at_vertex = 3 * ps.face + (e.corner % 3);
    }
    const Placement pl2 = *unf_.placement(ps.face);
    const Vec3 p3 = unf_.position(ps.face, pl2, ps.point);
    const Vec3 d3 = unf_.to_space(ps.face, pl2, ps.dir);
    const std::array<double, 3> w2 = weights(ps.face, pl2, ps.point);
    if (trusted_mode) {
      history.push_back(d3);
      if (int(history.size()) > std::max(1, o_.trusted_history)) history.erase(history.begin());
    }
    if (extending) {
      if (crossed) return;
      if (extension > dmax_) {  // no transversal line ahead: withdraw the extension
        for (size_t k = extension_start; k < ps.segments.size(); ++k) db_.segment_for_update(ps.segments[k]).line = detail::kNone;
        ps.segments.resize(extension_start);
        ps.open_end = !extend_only;
        return;
      }
      continue;
    }
    bool near_start = false;
    const double r = o_.collision_factor * spacing(ps.type, ps.face, w2);
    if (collides(ps.face, p3, d3, ps.type, trusted_mode, r, line, ps.sign * arc, near_start)) {
      if (near_start && ps.sign > 0.0 && arc > 4.0 * r && !ps.segments.empty()) {
        // Back at the seed: close the loop with a last straight piece onto the seed point.
        const Vec2 to = ps.point + unf_.to_omega(ps.face, pl2, start_point - p3);
        step_arc = 0.0;
        const size_t before = ps.segments.size();
        const WalkEnd c = unf_.walk(ps.face, ps.point, to, true, on_piece);
        if (c.kind == WalkEnd::reached && distance(unf_.position(c.face, c.placement, c.point), start_point) < 0.25 * r &&
            ps.segments.size() > before) {
          db_.segment_for_update(ps.segments.back()).b = start_point;
          ps.closed = true;
          return;
        }
      }
      extending = true;
      extension = 0.0;
      extension_start = ps.segments.size();
      ps.end_face = ps.face;
      ps.end_point = p3;
      ps.end_dir = d3;
    }
  }
}

bool Sampler::crosses_transversal(uint32_t f, const Vec3& a, const Vec3& b, uint32_t line, LineType t) const {
  const FaceFrame fr = face_frame(mesh_, f);
  auto flat = [&](const Vec3& p) { return Vec2{dot(p - fr.origin, fr.u), dot(p - fr.origin, fr.v)}; };
  const Vec2 a2 = flat(a), b2 = flat(b), d = b2 - a2;
  bool hit = false;
  db_.for_each_in_face(f, [&](uint32_t id) {
    const LineSegment& s = db_.segment(id);
    if (hit || s.line == detail::kNone || s.line == line) return;
    if (is_curvature_line(s.type) && s.type == t && s.trusted) return;
    const Vec2 c2 = flat(s.a), e = flat(s.b) - c2;
    const double den = cross(d, e);
    if (!(std::fabs(den) > 1e-12 * norm(d) * norm(e))) return;
    const double u = cross(c2 - a2, e) / den, v = cross(c2 - a2, d) / den;
    hit = u >= -1e-9 && u <= 1 + 1e-9 && v >= -1e-9 && v <= 1 + 1e-9;
  });
  return hit;
}

bool Sampler::trace(const Seed& seed) {
  ++out_.seeds_tried;
  const uint32_t line = uint32_t(out_.lines.size());
  unf_.reset(seed.face);
  const FaceFrame fr = unf_.frame(seed.face);
  const Vec2 p{dot(seed.point - fr.origin, fr.u), dot(seed.point - fr.origin, fr.v)};
  const Placement frame0;
  const bool conf = confident(seed.face);
  Vec2 hint = unf_.to_omega(seed.face, frame0, seed.hint);
  if (norm(hint) > 0.0) hint = (1.0 / norm(hint)) * hint;
  else hint = {1.0, 0.0};
  Vec2 dir = (conf || seed.forced) ? field_direction(seed.face, frame0, p, seed.type, hint) : hint;
  const std::array<double, 3> w = weights(seed.face, frame0, p);
  bool near_start = false;
  const double r = o_.collision_factor * spacing(seed.type, seed.face, w);
  if (!std::isfinite(p.x) || !std::isfinite(p.y) ||
      collides(seed.face, seed.point, unf_.to_space(seed.face, frame0, dir), seed.type, conf || seed.forced, r, line,
               0.0, near_start)) {
    ++out_.seeds_rejected;
    return false;
  }
  out_.lines.push_back({seed.type, false, {}});
  const size_t seeds_before = seeds_.size();
  if (conf || seed.forced) add_seed(seed.face, seed.point, opposite_type(seed.type), cross(fr.n, unf_.to_space(seed.face, frame0, dir)));
  Pass fwd(seed.face, p, dir, seed.type, 1.0);
  run_pass(fwd, line, conf || seed.forced, seed.point);
  Pass bwd(seed.face, p, -1.0 * dir, seed.type, -1.0);
  if (!fwd.closed) {
    unf_.reset(seed.face);
    run_pass(bwd, line, conf || seed.forced, seed.point);
  }
  SampledLine& l = out_.lines[line];
  l.closed = fwd.closed;
  double length = 0.0;
  for (const Pass* ps : {&fwd, &bwd})
    for (uint32_t id : ps->segments) length += distance(db_.segment(id).a, db_.segment(id).b);
  if (length < 0.5 * r) {  // a stub (typically a seed in a field artefact): withdrawn [J]
    for (const Pass* ps : {&fwd, &bwd})
      for (uint32_t id : ps->segments) db_.segment_for_update(id).line = detail::kNone;
    out_.lines.pop_back();
    seeds_.resize(seeds_before);
    ++out_.seeds_rejected;
    return false;
  }
  for (auto it = bwd.segments.rbegin(); it != bwd.segments.rend(); ++it) {
    LineSegment& s = db_.segment_for_update(*it);
    std::swap(s.a, s.b);
    std::swap(s.vertex_a, s.vertex_b);
    l.segments.push_back(*it);
  }
  l.segments.insert(l.segments.end(), fwd.segments.begin(), fwd.segments.end());
  if (fwd.open_end) open_ends_.push_back({line, false, fwd.end_face, fwd.end_point, fwd.end_dir, fwd.type});
  if (bwd.open_end) open_ends_.push_back({line, true, bwd.end_face, bwd.end_point, bwd.end_dir, bwd.type});
  ++out_.lines_by_type[size_t(seed.type)];
  return true;
}

void Sampler::drain() {
  while (!seeds_.empty() && !full()) {
    const Seed s = seeds_.front();
    seeds_.pop_front();
    trace(s);
    if (out_.seeds_tried % 64 == 0)
      monitor_.report("curvature lines", double(out_.seeds_tried) / double(out_.seeds_tried + seeds_.size() + 1));
  }
}


// Feature lines: chains of the feature graph between its nodes (vertices of feature degree != 2)
// or closed loops; boundary lines: one per boundary loop, running with the interior on the left.
// Both are stored edge by edge; they seed curvature lines of both types into their faces at the
// spacing of (5.10) [J].
void Sampler::feature_and_boundary_lines() {
  const uint32_t nc = uint32_t(mesh_.num_face_vertices()), nv = uint32_t(mesh_.num_vertices());
  std::vector<std::vector<uint32_t>> incident(nv);  // feature half-edges (c < twin) per vertex
  for (uint32_t c = 0; c < nc; ++c) {
    const uint32_t t = adj_.twin[c];
    if (t == detail::kNone || !adj_.feature[c] || t < c) continue;
    incident[mesh_.face_vertices[c]].push_back(c);
    incident[mesh_.face_vertices[TriangleAdjacency::next(c)]].push_back(c);
  }
  std::vector<uint8_t> used_edge(nc, 0);
  auto emit = [&](LineType type, const std::vector<std::pair<uint32_t, bool>>& chain, bool closed) {
    if (type == LineType::feature) {
      // Feature chains shorter than min_feature_length are noise (a scan's dihedral spikes): they
      // stay barriers of the tensor estimate but neither become lines nor stop lines [J].
      double length = 0.0;
      for (const auto& ce : chain)
        length += distance(mesh_.positions[mesh_.face_vertices[ce.first]],
                           mesh_.positions[mesh_.face_vertices[TriangleAdjacency::next(ce.first)]]);
      if (length < min_feature_length_) {
        for (const auto& ce : chain) {
          out_.adjacency->feature[ce.first] = 0;
          if (adj_.twin[ce.first] != detail::kNone) out_.adjacency->feature[adj_.twin[ce.first]] = 0;
        }
        ++out_.features_dropped;
        return;
      }
    }
    const uint32_t line = uint32_t(out_.lines.size());
    SampledLine l;
    l.type = type;
    l.closed = closed;
    double arc = 0.0, since[2] = {1e300, 1e300};
    for (const auto& [c, forward] : chain) {
      const uint32_t a = mesh_.face_vertices[c], b = mesh_.face_vertices[TriangleAdjacency::next(c)];
      LineSegment s;
      s.vertex_a = forward ? a : b;
      s.vertex_b = forward ? b : a;
      s.a = mesh_.positions[s.vertex_a];
      s.b = mesh_.positions[s.vertex_b];
      s.face = c / 3;
      s.line = line;
      s.arc = arc;
      s.type = type;
      const uint32_t t = adj_.twin[c];
      l.segments.push_back(db_.insert(s, t == detail::kNone ? detail::kNone : t / 3));
      const double len = distance(s.a, s.b);
      arc += len;
      if (!(len > 0.0)) continue;
      for (int k = 0; k < 2; ++k) {
        const LineType lt = k == 0 ? LineType::min_curvature : LineType::max_curvature;
        const std::array<double, 3> w{1.0 / 3, 1.0 / 3, 1.0 / 3};
        const double d = spacing(lt, c / 3, w);
        double used = 0.0;
        while (since[k] + (len - used) >= d) {  // exactly every D along the line
          used += std::max(0.0, d - since[k]);
          since[k] = 0.0;
          const Vec3 p = s.a + (used / len) * (s.b - s.a);
          for (uint32_t side : {c, t}) {
            if (side == detail::kNone || !confident(side / 3)) continue;
            const Vec3 e = mesh_.positions[mesh_.face_vertices[TriangleAdjacency::next(side)]] -
                           mesh_.positions[mesh_.face_vertices[side]];
            add_seed(side / 3, p, lt, cross(unf_.frame(side / 3).n, e));  // n x e points into the face
          }
        }
        since[k] += len - used;
      }
    }
    out_.lines.push_back(std::move(l));
    ++out_.lines_by_type[size_t(type)];
  };
  // Feature chains from the nodes, then the remaining closed loops.
  auto other_end = [&](uint32_t c, uint32_t v) {
    const uint32_t a = mesh_.face_vertices[c];
    return a == v ? mesh_.face_vertices[TriangleAdjacency::next(c)] : a;
  };
  for (int pass = 0; pass < 2; ++pass)
    for (uint32_t v0 = 0; v0 < nv; ++v0) {
      if ((pass == 0) == (incident[v0].size() == 2)) continue;
      for (uint32_t c0 : incident[v0]) {
        if (used_edge[c0]) continue;
        std::vector<std::pair<uint32_t, bool>> chain;
        uint32_t v = v0, c = c0;
        bool closed = false;
        for (uint32_t guard = 0; guard < nc && !used_edge[c]; ++guard) {
          used_edge[c] = 1;
          chain.push_back({c, mesh_.face_vertices[c] == v});
          v = other_end(c, v);
          if (v == v0 && pass == 1) {
            closed = true;
            break;
          }
          if (incident[v].size() != 2) break;
          c = incident[v][0] == c ? incident[v][1] : incident[v][0];
        }
        emit(LineType::feature, chain, closed);
      }
    }
  // Boundary loops.
  std::vector<uint32_t> boundary_out(nv, detail::kNone);
  for (uint32_t c = 0; c < nc; ++c)
    if (adj_.twin[c] == detail::kNone) boundary_out[mesh_.face_vertices[c]] = c;
  for (uint32_t c0 = 0; c0 < nc; ++c0) {
    if (adj_.twin[c0] != detail::kNone || used_edge[c0]) continue;
    std::vector<std::pair<uint32_t, bool>> chain;
    uint32_t c = c0;
    bool closed = false;
    for (uint32_t guard = 0; guard < nc; ++guard) {
      used_edge[c] = 1;
      chain.push_back({c, true});
      const uint32_t next = boundary_out[mesh_.face_vertices[TriangleAdjacency::next(c)]];
      if (next == c0) {
        closed = true;
        break;
      }
      if (next == detail::kNone || used_edge[next]) break;
      c = next;
    }
    emit(LineType::boundary, chain, closed);
  }
}

// A few sparse random seeds among the most confident anisotropic faces (§5.5.1); fallbacks
// [J]: confident faces of any anisotropy, then the most confident faces at all (a sphere).
void Sampler::initial_seeds() {
  const uint32_t nf = uint32_t(mesh_.num_faces());
  std::vector<std::pair<double, uint32_t>> pool;
  bool forced = false;
  for (int attempt = 0; attempt < 3 && pool.empty(); ++attempt)
    for (uint32_t f = 0; f < nf; ++f) {
      const double kmin = std::fabs(field_.face_k_min[f]), kmax = std::fabs(field_.face_k_max[f]);
      const double aniso = kmax > 0.0 ? (kmax - kmin) / kmax : 0.0;
      const double lam = field_.face_confidence[f];
      if (attempt == 0 && (!confident(f) || aniso < 0.5)) continue;
      if (attempt == 1 && !confident(f)) continue;
      if (attempt == 2) forced = true;
      pool.push_back({lam * (attempt == 0 ? aniso : 1.0), f});
    }
  std::sort(pool.begin(), pool.end(), [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
  pool.resize(std::max<size_t>(std::min<size_t>(pool.size(), 64), pool.size() / 50));
  std::shuffle(pool.begin(), pool.end(), rng_);
  std::vector<Vec3> chosen;
  for (const auto& [score, f] : pool) {
    if (int(chosen.size()) >= o_.initial_seeds) break;
    const Vec3 c = (1.0 / 3.0) * (mesh_.positions[mesh_.face_vertices[3 * f]] + mesh_.positions[mesh_.face_vertices[3 * f + 1]] +
                                  mesh_.positions[mesh_.face_vertices[3 * f + 2]]);
    bool far = true;
    for (const Vec3& q : chosen) far &= distance(q, c) >= dmax_;
    if (!far) continue;
    chosen.push_back(c);
    Seed s{f, c, LineType::min_curvature, field_.face_t_min[f], forced};
    seeds_.push_back(s);
  }
}

// "Until no new curvature lines can be generated without violating the density": confident
// faces (a random sample of at most 200K) holding no segment of a type try a seed of that type.
void Sampler::sweep() {
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < mesh_.num_faces(); ++f)
    if (confident(f)) faces.push_back(f);
  std::shuffle(faces.begin(), faces.end(), rng_);
  if (faces.size() > 200000) faces.resize(200000);
  for (size_t i = 0; i < faces.size() && !full(); ++i) {
    const uint32_t f = faces[i];
    if (i % 4096 == 0) monitor_.report("curvature lines: sweep", double(i) / double(faces.size()));
    for (LineType t : {LineType::min_curvature, LineType::max_curvature}) {
      bool has = false;
      db_.for_each_in_face(f, [&](uint32_t id) { has |= db_.segment(id).type == t; });
      if (has) continue;
      const Vec3 c = (1.0 / 3.0) * (mesh_.positions[mesh_.face_vertices[3 * f]] + mesh_.positions[mesh_.face_vertices[3 * f + 1]] +
                                    mesh_.positions[mesh_.face_vertices[3 * f + 2]]);
      seeds_.push_back({f, c, t, t == LineType::min_curvature ? field_.face_t_min[f] : field_.face_t_max[f], false});
      drain();
    }
  }
}

// Lines stopped by a collision before any transversal line existed: once all lines are in,
// extend them (at most max_spacing) until they cross one, so they end in T-joints [J].
void Sampler::extend_open_ends() {
  for (size_t i = 0; i < open_ends_.size(); ++i) {
    if (i % 256 == 0) monitor_.report("curvature lines: open ends", double(i) / double(open_ends_.size()));
    const OpenEnd& oe = open_ends_[i];
    unf_.reset(oe.face);
    const FaceFrame fr = unf_.frame(oe.face);
    const Vec2 p{dot(oe.point - fr.origin, fr.u), dot(oe.point - fr.origin, fr.v)};
    Vec2 d{dot(oe.dir, fr.u), dot(oe.dir, fr.v)};
    if (!(norm(d) > 0.0)) continue;
    d = (1.0 / norm(d)) * d;
    Pass ps(oe.face, p, d, oe.type, 1.0);
    run_pass(ps, oe.line, confident(oe.face), oe.point, true);
    if (ps.segments.empty()) continue;
    std::vector<uint32_t>& segs = out_.lines[oe.line].segments;
    if (!oe.at_front) {
      segs.insert(segs.end(), ps.segments.begin(), ps.segments.end());
      continue;
    }
    std::vector<uint32_t> front;
    for (auto it = ps.segments.rbegin(); it != ps.segments.rend(); ++it) {
      LineSegment& sg = db_.segment_for_update(*it);
      std::swap(sg.a, sg.b);
      std::swap(sg.vertex_a, sg.vertex_b);
      front.push_back(*it);
    }
    segs.insert(segs.begin(), front.begin(), front.end());
  }
}

void Sampler::run() {
  feature_and_boundary_lines();
  initial_seeds();
  drain();
  sweep();
  extend_open_ends();
}

}  // namespace

LineSampling sample_curvature_lines(const PolygonMesh& mesh, const CurvatureField& field,
                                    const LineSamplingOptions& o, const std::vector<uint8_t>* feature_corners,
                                    const TaskMonitor& monitor) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance) || !(o.max_spacing > 0.0) || !(o.step_fraction > 0.0) ||
      o.step_fraction > 1.0 || !(o.collision_factor > 0.0) || o.collision_factor > 1.0 ||
      !(o.confidence_threshold >= 0.0 && o.confidence_threshold <= 1.0) || !(o.min_spacing <= o.max_spacing) ||
      o.max_steps_per_pass <= 0 || o.initial_seeds < 0)
    fail(Status::invalid_argument, "curvature-line sampling: invalid options (tolerance, spacing, step or collision factor)");
  LineSampling out;
  out.adjacency = std::make_shared<TriangleAdjacency>();
  out.adjacency->build(mesh, feature_corners);
  if (field.vertex_k_min.size() != mesh.num_vertices() || field.face_confidence.size() != mesh.num_faces() ||
      field.vertex_t_min.size() != mesh.num_vertices())
    fail(Status::invalid_argument, "curvature-line sampling: the curvature field belongs to another mesh");
  out.database = std::make_shared<LineSampleDatabase>(mesh, *out.adjacency);
  out.bbox_diagonal = mesh.bounding_box().diagonal();
  const double mean_edge = mesh.mean_edge_length();
  if (!(out.bbox_diagonal > 0.0) || !(mean_edge > 0.0))
    fail(Status::invalid_mesh, "curvature-line sampling: the mesh has zero extent");
  out.epsilon = o.tolerance * out.bbox_diagonal;
  out.max_spacing = o.max_spacing * out.bbox_diagonal;
  out.min_spacing = std::min(out.max_spacing, o.min_spacing > 0.0 ? o.min_spacing * out.bbox_diagonal : 2.0 * mean_edge);
  Sampler sampler(mesh, field, o, out, monitor);
  sampler.run();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

CAGEKIT_NAMESPACE_END
