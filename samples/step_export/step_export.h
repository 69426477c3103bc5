// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// cagekit_step_export: B-spline surfaces -> sewn shell / solid -> STEP file, and a STEP file ->
// face count, validity and distances, through OpenCASCADE (OCCT 7.6). A companion of the SDK, not
// part of it: libcagekit never links OCCT. The interface takes plain data only (no SDK types, no
// OCCT types), so the CLI (through the C API) and the C++ tests (through the SDK's internal
// build_limit_bspline_surfaces) both feed it. See README.md.
//
// Errors: the functions do not throw. Bad input (inconsistent knot vectors, too few points) and
// OCCT failures (Standard_Failure) come back as ok = false with a one-line message.
// Output: OCCT's messages on stdout are switched off for the whole process (the stream printers
// of Message::DefaultMessenger() are removed on the first call).
// Thread-safety: not reentrant. STEP writing goes through OCCT's process-wide Interface_Static
// parameters (the schema); call these functions from one thread at a time.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace cagekit_step {

// One non-rational B-spline surface. Full (clamped or not) knot vectors with repeated knots:
// knots_u.size() == num_u + degree_u + 1, non-decreasing (likewise v). Control points row-major
// with u inner: point (i, j) (i along u) is points[3 * (j * num_u + i) + 0..2].
struct BSplineSurface {
  int degree_u = 3, degree_v = 3;
  std::vector<double> knots_u, knots_v;
  uint32_t num_u = 0, num_v = 0;
  std::vector<double> points;
  // This surface's share of knot removal (model units): it moves by at most
  // min(WriteOptions::knot_removal_tolerance, this). Negative: no limit of its own. A caller that
  // knows the surface's distance e to what it approximates passes tolerance - e (>= 0), so the
  // surface stays within the tolerance after removal.
  double knot_removal_budget = -1.0;
};

struct WriteOptions {
  // BRepBuilderAPI_Sewing tolerance, model units (> 0): borders closer than this are sewn. Shared
  // borders of surfaces built to match exactly need little (e.g. 1e-7 of the bounding-box diagonal).
  double sewing_tolerance = 1e-6;
  // "AP214" (AP214 CD, OCCT's default) or "AP203".
  std::string schema = "AP214";
  // Knot removal (model units, 0: off): each surface's interior knots are removed where the
  // surface moves by at most this much (OCCT's Geom_BSplineSurface::RemoveUKnot / RemoveVKnot,
  // repeated until none goes). The limit surface is bicubic on all but the cells next to an
  // extraordinary vertex, so most of a uniform knot grid's knots go, and with them most control
  // points (STEP size). Each surface's final deviation from its input is measured (33 x 33
  // parameter grid), kept within this value (the removal is redone with smaller steps, or not
  // done) and reported; shared borders then differ by up to twice that, so the sewing tolerance is
  // raised to at least 2.5 times this value.
  double knot_removal_tolerance = 0.0;
};

struct WriteReport {
  bool ok = false;
  std::string error;          // when !ok
  uint32_t faces = 0;         // faces in the written shape
  uint32_t free_edges = 0;    // edges of one face only after sewing (0 for a closed shell)
  uint32_t multiple_edges = 0;  // edges shared by more than two faces after sewing
  uint32_t shells = 0;        // shells after sewing
  bool closed = false;        // every shell closed (no free edges)
  bool solid = false;         // a solid (one per shell, outward-oriented) was made and written
  bool valid = false;         // BRepCheck_Analyzer on the written shape
  uint64_t bytes = 0;         // size of the STEP file
  uint64_t control_points = 0;          // in the written surfaces
  uint64_t control_points_before = 0;   // in the input surfaces
  double max_knot_removal_deviation = 0;  // largest measured move of a surface by knot removal
  double build_seconds = 0, sewing_seconds = 0, solid_seconds = 0, check_seconds = 0, write_seconds = 0;
};

// Builds one Geom_BSplineSurface and face per surface, sews them, makes a solid per closed shell
// (oriented outward), checks the result and writes it to `path` as STEP.
WriteReport write_step(const std::vector<BSplineSurface>& surfaces, const std::string& path,
                       const WriteOptions& options);

struct ReadReport {
  bool ok = false;
  std::string error;      // when !ok
  uint32_t faces = 0, shells = 0, solids = 0;
  bool valid = false;     // BRepCheck_Analyzer on the read shape
  // Largest over `points` of the distance from the point to the nearest face of the read shape
  // (ShapeAnalysis_Surface projection onto each candidate face's surface); 0 without points.
  double max_distance = 0;
  uint32_t points_checked = 0;
  double read_seconds = 0, distance_seconds = 0;
};

// Reads `path` (STEPControl_Reader, all roots as one shape) and measures it against `points`.
ReadReport read_step(const std::string& path, const std::vector<std::array<double, 3>>& points);

// The surface's point at (u, v) (de Boor), for sampling the data passed to write_step. u, v are
// clamped to the knot range. Returns false (p untouched) for an inconsistent surface.
bool evaluate(const BSplineSurface& surface, double u, double v, std::array<double, 3>& p);

}  // namespace cagekit_step
