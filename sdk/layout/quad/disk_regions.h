// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Disk regions for the two-step quad remeshing (thesis §6.4 assumes every VSA region is a disk,
// possibly with holes, whose LSCM map Ω_i is injective; on meshes with many components, handles
// or strongly curved parts VSA's regions need not be). make_disk_regions parameterises every
// region with LSCM and splits each region that is closed, has a handle or folds in its map
// (flipped triangles) into two, along the boundary of the geodesic Voronoi cells (face-centroid
// distances through the region) of its two mutually farthest faces — a region with a handle is
// cut across it first (cut_region_handle), one that touches itself at a vertex is split there —
// then checks the parts again, for at most `max_rounds` rounds (`max_topology_rounds` for
// regions that are not disks). Host-pinned regions (ids below `pinned`) are never split.
// Not in the thesis: its regions were all disks. Regions that still fail after the last round
// keep their failure (compute_remesh_constraints reports it).
//
// Thread-safety: pure function. Errors: cancelled from the monitor; parameterize_region_lscm's
// invalid_argument for bad face ids.
#include <cstdint>
#include <vector>

#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "layout/quad/lscm_parameterization.h"

CAGEKIT_NAMESPACE_BEGIN

struct DiskRegionOptions {
  int max_rounds = 8;           // split rounds at most (each splits every failing region once)
  int max_topology_rounds = 24; // rounds in all for regions that are not disks (no map without a cut)
  bool split_folded = true;     // also split regions whose LSCM map has flipped triangles
};

struct DiskRegionReport {
  uint64_t split_regions = 0;   // splits made (each adds one region)
  uint64_t topology_splits = 0; // of those: closed regions, handles, disconnected regions
  uint64_t fold_splits = 0;     // of those: flipped triangles in the LSCM map
  uint64_t handle_cuts = 0;     // of the topology splits: cut across a handle (cut_region_handle)
  uint64_t failing_regions = 0; // regions still not a disk with an injective map after the last round
};

// Updates face_region / num_regions in place (new regions get the next ids) and returns the LSCM
// domain of every final region, in region order, for compute_remesh_constraints; the entry of a
// region that still cannot be parameterised (closed, a handle) is empty (faces empty), a region
// that still folds keeps its map.
std::vector<RegionParameterization> make_disk_regions(const PolygonMesh& triangles, std::vector<uint32_t>& face_region,
                                                      size_t& num_regions, size_t pinned,
                                                      const DiskRegionOptions& options = {},
                                                      DiskRegionReport* report = nullptr,
                                                      const TaskMonitor& monitor = {});

// Splits one region (its faces, edge-connected through the region) into the geodesic Voronoi
// cells of its two mutually farthest faces; returns the faces of the second cell (empty when the
// region has fewer than two faces). Exposed for tests.
std::vector<uint32_t> split_region_in_two(const PolygonMesh& triangles, const std::vector<uint32_t>& faces);

// Splits region `region` of face_region between two points on (or near) it: the geodesic
// Voronoi cells of the region's faces nearest to `p` and to `q`. Used where the layouts of two
// regions glue into faces over the same vertices or an edge of four faces (two regions that
// wrap a tube or a band together, each spanning it from one shared boundary stretch to the
// other): split between the two ends of such an edge, the region no longer spans it. Falls back
// to split_region_in_two when both points are nearest to one face. Returns the faces of the
// second part.
std::vector<uint32_t> split_region_between(const PolygonMesh& triangles, const std::vector<uint32_t>& face_region,
                                           uint32_t region, const Vec3& p, const Vec3& q);

// Splits region `region` at a vertex where its boundary touches itself (the region's faces
// around it form two or more fans: a layout face would repeat that vertex): the faces of one
// fan and of the other fans seed the two geodesic Voronoi cells. Falls back to
// split_region_in_two when the region has no such vertex. Returns the faces of the second part.
std::vector<uint32_t> split_region_at_pinch(const PolygonMesh& triangles, const std::vector<uint32_t>& face_region,
                                            uint32_t region);

// Cuts a handle of a region (its faces, edge-connected, no edge of three faces, no vertex where
// its border touches itself): returns the faces of one non-separating dual cycle of the region's
// surface with its border loops capped (tree-cotree: a breadth-first dual tree, a primal spanning
// tree of the edges it does not cross, the shortest cycle one left-over edge closes), a band
// across the handle or a strip from border to border. Removing them lowers the genus; the band
// itself is an annulus or a strip that halving splits into disks. Empty when the region has genus
// 0, is not such a surface, or the cycle covers every face.
std::vector<uint32_t> cut_region_handle(const PolygonMesh& triangles, const std::vector<uint32_t>& faces);

CAGEKIT_NAMESPACE_END
