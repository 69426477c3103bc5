// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Curve selection of the two-step quad-dominant remeshing (thesis §6.6-6.7, spec
// thesis-ch4-6.md §2.7-2.9): choose a matching L of candidate curves (at most one curve per
// port) whose arrangement with the boundary loops gives the least element energy E(L) = Σ_f E(f)
// (quad_element_energy.h).
//
// Meshing of a configuration (§6.6.1): vertices are the boundary points and the crossings of the
// selected curves' polylines; edges the boundary edges and the curve pieces between consecutive
// vertices; faces are the cycles of the planar map (next half-edge = first one clockwise from the
// twin, using the polyline's direction at the vertex), rated on their straight polygons.
//
// Optimiser: small regions (at most `exhaustive_limit` matchings) are solved exactly by
// enumeration; otherwise Phase I greedy by the end-point heuristic Σ|ξ_k − π/2| (chord against the two
// boundary edges at each end; at a two-tangent concave port 2·∠(chord, tangent)); Phase II steepest
// descent over all swap (Fig. 6.6) and reconnect (Fig. 6.7) moves; Phase III removes the curves
// with a crossing at an angle below `bad_crossing_angle`, then repeatedly adds the curve with the
// smallest resulting E followed by Phase II, with a backup of the best configuration restored at
// the end (so the result is never worse than Phase I); then the polish (add_remove_moves).
//
// The meshing and the incremental evaluation of moves (the bottleneck the thesis names in
// §6.10) are the arrangement's, quad_curve_arrangement.h; this file's functions are the optimiser.
//
// Thread-safety: pure function (separate regions can run on separate threads). Errors:
// invalid_argument for a network without points or bad options; internal_error if a face cycle
// does not close (an inconsistent planar map); cancelled from the monitor.
#include <cstdint>
#include <vector>

#include "core/task_monitor.h"
#include "layout/quad/quad_curve_network.h"
#include "layout/quad/quad_element_energy.h"

CAGEKIT_NAMESPACE_BEGIN

struct SelectionOptions {
  ElementWeights weights;
  double bad_crossing_angle = 0.7853981633974483;  // π/4 (Phase III)
  bool run_phase2 = true;
  bool run_phase3 = true;
  // Polish (not in the thesis): after Phase III, from the best configuration, a Phase II descent
  // that also tries removing a selected curve and adding a curve between two free ports (these
  // scan every curve, so only when no swap or reconnect decreases E). Inside Phase III the same
  // moves gave the same E but took 5-7x longer.
  bool add_remove_moves = true;
  size_t max_descent_steps = 100000;  // per Phase II run
  // A region whose candidate curves admit at most this many matchings (the empty one included)
  // is solved exactly by enumerating them all (depth-first, incremental add/remove); Phases II
  // and III are then skipped. 0: always the thesis's Phases I-III.
  size_t exhaustive_limit = 2000;
  // Testing aid: after every applied move, rebuild E(L) from scratch and fail with
  // internal_error if it differs from the incrementally updated value or from the move's
  // predicted change (slow: one full rebuild per move).
  bool verify_incremental = false;
};

struct QuadSelection {
  std::vector<uint32_t> curves;  // selected indices into CurveNetwork::curves, increasing
  double energy = 0.0;           // E(L) of `curves`
  double phase1_energy = 0.0, phase2_energy = 0.0;
  double phase3_energy = 0.0;  // the best after Phase III (before the polish)
  // The best E(L) as tracked by the incremental updates (before the final rebuild of `curves`):
  // equal to `energy` up to rounding when the incremental bookkeeping is right.
  double tracked_energy = 0.0;
  // The region mesh in Ω (concave faces split): vertices, and per vertex its boundary point
  // (CurveNetwork::points index) or -1 for a curve crossing.
  std::vector<Vec2> vertices;
  std::vector<int64_t> vertex_point;
  std::vector<std::vector<uint32_t>> faces;  // counter-clockwise
  size_t quads = 0, triangles = 0, pentagons = 0, larger = 0;  // valence counts of `faces`
  size_t invalid_faces = 0;                                    // flipped or hole cycles
  size_t moves_evaluated = 0, moves_applied = 0;
  bool exhaustive = false;           // solved by enumeration (a global minimum of E(L))
  size_t matchings_enumerated = 0;
};

QuadSelection select_quad_curves(const CurveNetwork& network, const SelectionOptions& options = {},
                                 const TaskMonitor& monitor = {});

// Local improvement of a given matching (not in the thesis; the quad remesher's sample-count
// refinement uses it to rate a changed arc cheaply, starting from the region's previous
// configuration carried over to the rebuilt network): the polish descent of select_quad_curves
// (swap, reconnect, add and remove moves, steepest first) from `initial` until no move lowers E.
// The result's E is at most that of `initial` (phase1..3_energy report the initial E).
// `focus_ports` (optional, one flag per port): only moves that involve a flagged port are tried,
// and the ports of every applied move are flagged in turn (a local repair; no flag: no move).
// Errors: invalid_argument if `initial` is not a matching of existing curves, the focus has the
// wrong size or the network has no loop; cancelled from the monitor. Thread-safety: pure function.
QuadSelection improve_quad_selection(const CurveNetwork& network, const std::vector<uint32_t>& initial,
                                     const SelectionOptions& options = {}, const TaskMonitor& monitor = {},
                                     const std::vector<char>* focus_ports = nullptr);

// E(L) of an arbitrary matching, rebuilt from scratch (no caches): the reference for tests.
// Errors: invalid_argument if `curves` is not a matching of existing curves.
double configuration_energy(const CurveNetwork& network, const std::vector<uint32_t>& curves,
                            const ElementWeights& weights);

CAGEKIT_NAMESPACE_END
