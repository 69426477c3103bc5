// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// scan_to_cage: the whole journey from a scan a user brings to a fitted Catmull-Clark cage, as
// one call that either returns a good result or says why not (thesis ch. 3/5/6 for the cage,
// ch. 7 for the fit; the checks around them are CageKit's own). The phases, in order:
//   1. condition_input       repair what hosts' meshes carry (input_conditioning.h)
//   2. initial_cage          the method: simplify (ch. 3) / quad (ch. 6) / anisotropic (ch. 5);
//                            an input that already has fewer faces than the method would make is
//                            its own cage (creases where it is sharp)
//   3. check_cage            a valid manifold cage, no holes the conditioned input did not have
//   4. fit                   the limit surface fitted to the scan, best state by two-sided RMS
//   5. measure_limit         the limit surface (level limit_levels) against the scan both ways;
//                            self-intersections of the level-2 limit mesh
//   6. judge                 good = the checks of 3 and limit -> scan max <= max(max_limit_to_scan,
//                            limit_to_scan_factor x scan -> limit max) (waived under
//                            small_input_faces input faces)
// A simplify result whose limit strays is retried at 2x and 4x the target (finer_simplify_attempts).
// Self-intersections of the limit (phase 5) are not part of the rule, but when the limit has more
// than the scan itself (whose own a faithful surface inherits) they are remedied as far as
// possible, keeping the good result with the fewest: the fit is run again with fairing 0.01,
// then 0.1; a tiny input used as its own cage is creased at 20 degrees, then on every edge (its
// limit then is the input itself); simplify tries the finer targets too.
// Last, a good fitted result is fitted once more by two-sided least squares
// (FitOptions::reverse_sample_factor = two_sided_refit_factor): kept when its limit is closer to
// the scan both ways (the larger of the two maxima drops by at least 5 %) with no more self-intersections, and
// still good. The method, target and remedies above are chosen by the thesis's one-sided fit.
// A quad or anisotropic result that is not good (or a method failure) falls back to simplify when
// fallback_to_simplify is on (reported with the reason); a simplify result that is not good is
// Error(quality) naming the figure. Nothing that is not good comes back.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/cage.h"
#include "core/polygon_mesh.h"
#include "core/task_monitor.h"
#include "fit/surface_fitter.h"
#include "layout/anisotropic/anisotropic_remesher.h"
#include "layout/common/approximation_error.h"
#include "layout/simplify/cage_builder.h"
#include "layout/simplify/face_merge_simplifier.h"
#include "layout/quad/quad_remesher.h"
#include "pipeline/input_conditioning.h"
#include "pipeline/self_intersections.h"

CAGEKIT_NAMESPACE_BEGIN

enum class ScanMethod { simplify, quad, anisotropic };
const char* scan_method_name(ScanMethod method);

struct ScanToCageOptions {
  ScanMethod method = ScanMethod::simplify;
  ConditioningOptions conditioning;
  // simplify: the coarsest level with at most `target` faces (or vertices).
  uint64_t target = 60;
  bool target_is_vertices = false;
  SimplifyOptions simplify;
  CageBuildOptions cage;
  QuadRemeshOptions quad;
  AnisotropicRemeshOptions anisotropic;
  FitOptions fit;
  int limit_levels = 3;            // the limit mesh the errors are measured on (1..kMaxUniformLevels)
  int self_intersection_level = 2; // the limit mesh whose self-intersections are counted (0: not counted)
  // The good-result rule (relative to the conditioned scan's diagonal).
  double max_limit_to_scan = 0.05;
  double limit_to_scan_factor = 3.0;
  uint64_t small_input_faces = 1000;
  bool fallback_to_simplify = true;
  // A simplify result whose limit surface strays from the scan is retried at 2x, 4x, ... the
  // target (this many times at most; 0: never), the first good one returned.
  int finer_simplify_attempts = 2;
  // Crease angle of a tiny input used as its own cage (degrees; < 0: no creases).
  double own_cage_crease_angle_degrees = 40.0;
  // Try the self-intersection remedies above (counting must be on: self_intersection_level > 0).
  bool remedy_self_intersections = true;
  // The two-sided refit of the last phase (FitOptions::reverse_sample_factor; 0: not tried).
  double two_sided_refit_factor = 3.0;
  // The host's sharp edges as vertex pairs of the INPUT scan (edge_key()s): after conditioning
  // they are found again by their end positions and given to every method (simplify's locked
  // edges and cage creases, the remeshers' sharp edges); an edge whose ends were welded away or
  // that is no edge of the conditioned scan is dropped (counted in the result).
  std::vector<uint64_t> sharp_edges;
};

struct ScanToCageResult {
  PolygonMesh conditioned;
  // The conditioned scan's sharp edges (detect_sharp_features with options.cage.features): the
  // feature lines every fit holds the limit's crease curves on (FitOptions::crease_feature_reach).
  std::shared_ptr<const std::vector<FeatureSegment>> sharp_features;
  ConditioningReport conditioning;
  ScanMethod requested = ScanMethod::simplify, used = ScanMethod::simplify;
  bool input_is_cage = false;      // the conditioned input was its own cage (tiny input)
  bool fallback = false;           // the requested method's result was replaced by simplify
  struct HostSharpEdges {
    uint64_t found = 0, dropped = 0;  // the options' sharp edges found / not found after conditioning
  } host_sharp_edges;
  std::string fallback_reason;     // why ("" when no fallback)
  // simplify
  size_t level = 0, level_count = 0;
  uint64_t target_used = 0;  // the target of the returned simplify result (after finer attempts)
  uint64_t level_faces = 0, level_faces_with_holes = 0;  // (own cage: level_faces = the input's faces)
  CageBuildReport cage_report;
  // quad / anisotropic
  RemeshQuality remesh;
  uint64_t remesh_regions = 0, remesh_lines = 0, remesh_holes = 0;
  uint64_t remesh_reseeded_regions = 0;  // quad: QuadRemeshResult::reseeded_regions
  double mean_alignment_deg = 0;
  // every method
  uint64_t creases = 0;
  ApproximationError method_error;  // scan vs the initial cage's control mesh (the method's output)
  Cage initial_cage, cage, limit;   // before the fit, fitted, fitted refined limit_levels onto the limit
  FitReport fit;
  ApproximationError limit_error;   // scan vs `limit` (hausdorff_rel: scan -> limit; reverse_rel)
  SelfIntersections self_intersections;
  // Counted only when the limit self-intersects (else zero, *_counted false): the conditioned
  // scan's own self-intersections (a faithful surface inherits them; the remedies are only
  // tried while the limit has more) and the initial cage's limit before the fit (says
  // whether the method or the fit made them).
  SelfIntersections scan_self_intersections, unfitted_self_intersections;
  bool scan_self_intersections_counted = false;
  // The own cage's crease angle used (degrees; 0: every edge creased, the limit then is the
  // conditioned input itself). Only for input_is_cage.
  double own_cage_crease_angle_used = 0;
  double fit_fairing_used = 0;  // FitOptions::fairing of the returned fit (raised by a remedy: self-intersections, strays)
  // The returned fit is the two-sided refit (ScanToCageOptions::two_sided_refit_factor); the
  // larger of the limit's two one-sided maxima before it (relative to the diagonal; 0 when not kept).
  bool two_sided_refit = false;
  double one_sided_fit_max_rel = 0;
  uint64_t input_boundary_loops = 0, cage_boundary_loops = 0, holes_added = 0;
  double method_seconds = 0, fit_seconds = 0, seconds = 0;
};

// Throws Error(invalid_mesh) for corrupt input or nothing left after conditioning,
// Error(invalid_argument) for bad options, Error(quality) when no good result could be made
// (naming the figure and the method), Error(cancelled) via the monitor, and whatever a phase
// throws when no fallback applies.
ScanToCageResult scan_to_cage(const PolygonMesh& scan, const ScanToCageOptions& options,
                              const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
