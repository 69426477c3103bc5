// SPDX-License-Identifier: GPL-3.0-or-later
#include "layout/remesh_constraints.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

double spacing_from_bbox_fraction(const PolygonMesh& mesh, double fraction) {
  if (!(fraction > 0.0) || !std::isfinite(fraction))
    fail(Status::invalid_argument, "remesh constraints: the spacing fraction must be positive and finite");
  return fraction * mesh.bounding_box().diagonal();
}

RemeshConstraints compute_remesh_constraints(const PolygonMesh& triangles, const std::vector<uint32_t>& face_region,
                                             size_t num_regions, const ConstraintOptions& options,
                                             const TaskMonitor& monitor) {
  if (!(options.spacing > 0.0) || !std::isfinite(options.spacing))
    fail(Status::invalid_argument, "remesh constraints: the sample spacing must be positive and finite");
  RemeshConstraints out;
  out.boundaries = compute_region_boundaries(triangles, face_region, num_regions);
  // Arcs are fitted in id order; a split appends its second half, which is fitted in turn.
  for (uint32_t a = 0; a < out.boundaries.arcs.size(); ++a) {
    for (;;) {
      const std::vector<uint32_t>& vertices = out.boundaries.arcs[a].vertices;
      std::vector<Vec3> points;
      for (uint32_t v : vertices) points.push_back(triangles.positions[v]);
      ArcConstraint c;
      c.s = arc_length_parameters(points);
      c.cubic = fit_arc_cubic(points, c.s);
      for (size_t i = 0; i < points.size(); ++i)
        c.fit_max_deviation = std::max(c.fit_max_deviation, distance(points[i], c.cubic.evaluate(c.s[i])));
      c.fit_rms = arc_fit_rms(c.cubic, points, c.s);
      if (options.max_fit_rms > 0.0 && points.size() >= 3 && c.fit_rms > options.max_fit_rms * options.spacing) {
        size_t middle = 1;
        for (size_t i = 1; i + 1 < points.size(); ++i)
          if (std::abs(c.s[i] - 0.5 * c.s.back()) < std::abs(c.s[middle] - 0.5 * c.s.back())) middle = i;
        split_arc(out.boundaries, a, middle);
        continue;
      }
      c.samples = sample_arc_cubic(c.cubic, options.spacing);
      out.arcs.push_back(std::move(c));
      break;
    }
  }
  monitor.report("remesh constraints", 0.1);
  std::vector<std::vector<uint32_t>> faces(num_regions);
  for (uint32_t f = 0; f < face_region.size(); ++f) faces[face_region[f]].push_back(f);
  out.domains.reserve(num_regions);
  out.region_arcs.resize(num_regions);
  for (uint32_t r = 0; r < num_regions; ++r) {
    if (faces[r].empty()) fail(Status::invalid_argument, "remesh constraints: region " + std::to_string(r) + " is empty");
    out.domains.push_back(parameterize_region_lscm(triangles, faces[r]));
    const RegionParameterization& domain = out.domains.back();
    // The outer loop is the one with the largest signed area in Ω_i (the longest in 3D need
    // not be, e.g. on an annulus around a torus' tube); it goes first.
    std::vector<RegionLoop>& loops = out.boundaries.region_loops[r];
    size_t outer = 0;
    double outer_area = -HUGE_VAL;
    for (size_t l = 0; l < loops.size(); ++l) {
      const double area = signed_domain_area(domain, out.boundaries.loop_vertices(loops[l]));
      if (area > outer_area) outer_area = area, outer = l;
    }
    std::rotate(loops.begin(), loops.begin() + long(outer), loops.begin() + long(outer) + 1);
    for (const RegionLoop& loop : out.boundaries.region_loops[r])
      for (uint32_t arc : loop.arcs) {
        const ArcConstraint& constraint = out.arcs[arc];
        std::vector<Vec3> uv;
        for (uint32_t v : out.boundaries.arcs[arc].vertices) {
          const auto& p = domain.uv_of(v);
          uv.push_back(Vec3{p[0], p[1], 0.0});
        }
        RegionArcDomain entry;
        entry.arc = arc;
        entry.planar = fit_arc_cubic(uv, constraint.s);
        for (const Vec3& p : evaluate_at(entry.planar, constraint.samples.t)) entry.samples_uv.push_back({p.x, p.y});
        entry.samples_uv.front() = {uv.front().x, uv.front().y};
        entry.samples_uv.back() = {uv.back().x, uv.back().y};
        out.region_arcs[r].push_back(std::move(entry));
      }
    monitor.report("remesh constraints", 0.1 + 0.9 * double(r + 1) / double(num_regions));
  }
  return out;
}

namespace {

// Appends an arc's entries (first to last, or reversed), leaving out its last point (the next
// arc's first) so that each anchor appears once in a closed loop.
template <class T>
void append_arc(std::vector<T>& out, const std::vector<T>& arc, bool reversed) {
  if (reversed)
    out.insert(out.end(), arc.rbegin(), arc.rend() - 1);
  else
    out.insert(out.end(), arc.begin(), arc.end() - 1);
}

}  // namespace

std::vector<Vec3> RemeshConstraints::loop_samples(uint32_t region, size_t loop) const {
  const RegionLoop& l = boundaries.region_loops.at(region).at(loop);
  std::vector<Vec3> out;
  for (size_t k = 0; k < l.arcs.size(); ++k) append_arc(out, arcs[l.arcs[k]].samples.position, l.reversed[k] != 0);
  return out;
}

std::vector<std::array<double, 2>> RemeshConstraints::loop_samples_uv(uint32_t region, size_t loop) const {
  const std::vector<RegionLoop>& loops = boundaries.region_loops.at(region);
  size_t first = 0;
  for (size_t i = 0; i < loop; ++i) first += loops[i].arcs.size();
  const RegionLoop& l = loops.at(loop);
  std::vector<std::array<double, 2>> out;
  for (size_t k = 0; k < l.arcs.size(); ++k) append_arc(out, region_arcs[region][first + k].samples_uv, l.reversed[k] != 0);
  return out;
}

CAGEKIT_NAMESPACE_END
