// SPDX-License-Identifier: GPL-3.0-or-later
#include "render/scan_distance.h"

#include <algorithm>

#include "core/parallel_for.h"
#include "core/status.h"
#include "layout/common/approximation_error.h"

CAGEKIT_NAMESPACE_BEGIN

std::vector<double> two_sided_distance_to_scan(const PolygonMesh& surface, const PolygonMesh& scan,
                                               const TaskMonitor& monitor) {
  const SurfaceDistance to_scan(scan);
  if (to_scan.empty()) fail(Status::invalid_mesh, "the scan has no non-degenerate triangle to measure a distance to");
  const SurfaceDistance to_surface(surface);
  if (to_surface.empty()) fail(Status::invalid_mesh, "the drawn surface has no non-degenerate triangle");
  const int threads = resolve_threads(0);
  std::vector<double> d(surface.num_vertices(), 0.0);
  parallel_for(d.size(), threads, monitor, "distance to scan", 0.0, 0.5,
               [&](size_t v) { d[v] = to_scan.distance(surface.positions[v]); });
  // Scan -> surface, splatted onto the corners of the nearest triangle.
  const std::vector<uint32_t> nearest = nearest_faces(surface, scan.positions);
  std::vector<double> back(scan.num_vertices(), 0.0);
  parallel_for(back.size(), threads, monitor, "distance to scan", 0.5, 1.0,
               [&](size_t s) { back[s] = to_surface.distance(scan.positions[s]); });
  for (size_t s = 0; s < back.size(); ++s) {
    const uint32_t f = nearest[s];
    if (f == UINT32_MAX) continue;
    const uint32_t* corner = surface.face_begin(f);
    for (uint32_t k = 0; k < surface.face_size(f); ++k) d[corner[k]] = std::max(d[corner[k]], back[s]);
  }
  return d;
}

CAGEKIT_NAMESPACE_END
