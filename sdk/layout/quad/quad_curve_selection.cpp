// SPDX-License-Identifier: GPL-3.0-or-later
// Curve selection (thesis §6.7): the optimiser over the arrangement of quad_curve_arrangement.h;
// see quad_curve_selection.h.
#include "layout/quad/quad_curve_selection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include "core/angles.h"
#include "core/edge_key.h"
#include "core/status.h"
#include "layout/quad/quad_curve_arrangement.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

using quad_detail::Arrangement;

double unsigned_angle(const Vec2& a, const Vec2& b) {
  return std::acos(std::clamp(dot(hypot_normalized(a), hypot_normalized(b)), -1.0, 1.0));
}

// Phase I score of a curve end at port `port` with chord direction `chord` (pointing away).
double end_score(const CurveNetwork& net, uint32_t port, const Vec2& chord) {
  const NetworkPort& q = net.ports[port];
  const NetworkPoint& p = net.points[q.point];
  if (p.port_count == 2) return 2.0 * unsigned_angle(chord, q.tangent);
  return std::fabs(unsigned_angle(chord, net.points[p.next].uv - p.uv) - kPi / 2) +
         std::fabs(unsigned_angle(chord, net.points[p.prev].uv - p.uv) - kPi / 2);
}

std::vector<uint32_t> phase1_greedy(const CurveNetwork& net) {
  std::vector<std::pair<double, uint32_t>> order;
  for (uint32_t c = 0; c < net.curves.size(); ++c) {
    const NetworkCurve& curve = net.curves[c];
    const Vec2 a = net.points[net.ports[curve.ports[0]].point].uv, b = net.points[net.ports[curve.ports[1]].point].uv;
    order.push_back({end_score(net, curve.ports[0], b - a) + end_score(net, curve.ports[1], a - b), c});
  }
  std::sort(order.begin(), order.end());
  std::vector<char> used(net.ports.size(), 0);
  std::vector<uint32_t> selected;
  for (const auto& [score, c] : order) {
    const auto& ports = net.curves[c].ports;
    if (used[ports[0]] || used[ports[1]]) continue;
    used[ports[0]] = used[ports[1]] = 1;
    selected.push_back(c);
  }
  return selected;
}

struct Move {
  std::vector<uint32_t> removed, added;
};

class Optimizer {
 public:
  Optimizer(const CurveNetwork& net, const SelectionOptions& options, const TaskMonitor& monitor, QuadSelection& stats)
      : net_(net), options_(options), monitor_(monitor), stats_(stats), arrangement_(net, options.weights) {
    for (uint32_t c = 0; c < net.curves.size(); ++c) curve_of_[edge_key(net.curves[c].ports[0], net.curves[c].ports[1])] = c;
    const ElementWeights& w = options.weights;
    bounded_ = w.triangle >= 0 && w.pentagon >= 0 && w.t_joint >= 0 && w.polygon_offset >= 0 && w.high_valence >= 0 &&
               w.invalid >= 0;
  }
  Arrangement& arrangement() { return arrangement_; }

  // Phase II: steepest descent over swaps and reconnects. With a focus (focus_ not empty), only
  // moves that involve a focus port are tried, and the ports of every applied move join the focus.
  void descend() {
    const bool focused = !focus_.empty();
    auto in_focus = [&](uint32_t c) {
      const auto& ports = net_.curves[c].ports;
      return focus_[ports[0]] || focus_[ports[1]];
    };
    for (size_t step = 0; step < options_.max_descent_steps; ++step) {
      monitor_.report("quad curve selection", 0.5);
      const std::vector<uint32_t> selected = arrangement_.selected();
      std::vector<uint32_t> free_ports;
      for (uint32_t p = 0; p < net_.ports.size(); ++p)
        if (arrangement_.port_curve(p) < 0) free_ports.push_back(p);
      double best = -1e-9 * (1.0 + std::fabs(arrangement_.energy()));
      Move best_move;
      auto consider = [&](std::vector<uint32_t> removed, std::vector<uint32_t> added) {
        ++stats_.moves_evaluated;
        const double delta = arrangement_.evaluate(removed, added, false, bounded_ ? best : kInfinity);
        if (delta < best) best = delta, best_move = {std::move(removed), std::move(added)};
      };
      for (size_t i = 0; i < selected.size(); ++i) {
        const auto& pi = net_.curves[selected[i]].ports;
        const bool focus_i = !focused || in_focus(selected[i]);
        for (size_t j = i + 1; j < selected.size(); ++j) {  // swaps (Fig. 6.6)
          if (!focus_i && !in_focus(selected[j])) continue;
          const auto& pj = net_.curves[selected[j]].ports;
          for (int variant = 0; variant < 2; ++variant) {
            const int64_t c1 = curve(pi[0], pj[variant]), c2 = curve(pi[1], pj[1 - variant]);
            if (c1 >= 0 && c2 >= 0) consider({selected[i], selected[j]}, {uint32_t(c1), uint32_t(c2)});
          }
        }
        for (uint32_t k : free_ports) {  // reconnects (Fig. 6.7)
          if (!focus_i && !focus_[k]) continue;
          for (int end = 0; end < 2; ++end) {
            const int64_t c = curve(pi[end], k);
            if (c >= 0) consider({selected[i]}, {uint32_t(c)});
          }
        }
      }
      // Add / remove moves only where no swap or reconnect decreases E (they scan every curve).
      if (polish_ && best_move.removed.empty()) {
        for (uint32_t c : selected)
          if (!focused || in_focus(c)) consider({c}, {});
        for (uint32_t c = 0; c < net_.curves.size(); ++c) {
          const auto& ports = net_.curves[c].ports;
          if (arrangement_.port_curve(ports[0]) < 0 && arrangement_.port_curve(ports[1]) < 0 &&
              (!focused || in_focus(c)))
            consider({}, {c});
        }
      }
      if (best_move.removed.empty() && best_move.added.empty()) return;
      apply(best_move.removed, best_move.added);
      if (focused)
        for (const std::vector<uint32_t>* list : {&best_move.removed, &best_move.added})
          for (uint32_t c : *list) focus_[net_.curves[c].ports[0]] = focus_[net_.curves[c].ports[1]] = 1;
    }
  }

  // Phase III (thesis §6.7.4) from the current configuration; keeps the best in `best`.
  void escape(std::vector<uint32_t>& best, double& best_energy) {
    std::vector<uint32_t> bad;
    for (uint32_t c : arrangement_.selected())
      if (arrangement_.smallest_crossing_angle(c) < options_.bad_crossing_angle) bad.push_back(c);
    if (!bad.empty()) apply(bad, {});
    remember(best, best_energy);
    for (size_t round = 0; round <= net_.ports.size(); ++round) {
      monitor_.report("quad curve selection", 0.75);
      double lowest = std::numeric_limits<double>::infinity();
      int64_t chosen = -1;
      for (uint32_t c = 0; c < net_.curves.size(); ++c) {
        const auto& ports = net_.curves[c].ports;
        if (arrangement_.port_curve(ports[0]) >= 0 || arrangement_.port_curve(ports[1]) >= 0) continue;
        ++stats_.moves_evaluated;
        const double delta = arrangement_.evaluate({}, {c}, false, bounded_ ? lowest : kInfinity);
        if (delta < lowest) lowest = delta, chosen = c;
      }
      if (chosen < 0) return;  // saturated, or no curve left
      apply({}, {uint32_t(chosen)});
      if (options_.run_phase2) descend();
      remember(best, best_energy);
    }
  }

  // Commits a move; with verify_incremental, checks it against a rebuild from scratch.
  void apply(const std::vector<uint32_t>& removed, const std::vector<uint32_t>& added) {
    const double before = arrangement_.energy();
    const double predicted = options_.verify_incremental ? arrangement_.evaluate(removed, added, false) : 0.0;
    arrangement_.evaluate(removed, added, true);
    ++stats_.moves_applied;
    if (!options_.verify_incremental) return;
    Arrangement fresh(net_, options_.weights);
    fresh.reset(arrangement_.selected());
    const double tolerance = 1e-9 * (1.0 + std::fabs(fresh.energy()));
    if (std::fabs(fresh.energy() - arrangement_.energy()) > tolerance ||
        std::fabs(before + predicted - arrangement_.energy()) > tolerance)
      fail(Status::internal_error, "quad selection: incremental E(L) " + std::to_string(arrangement_.energy()) +
                                       " (predicted " + std::to_string(before + predicted) + ") but rebuilt " +
                                       std::to_string(fresh.energy()));
  }

  // Number of matchings of the candidate curves (the empty one included), or limit + 1 when
  // there are more.
  size_t count_matchings(size_t limit) {
    build_adjacency();
    std::vector<char> used(net_.ports.size(), 0);
    size_t count = 0;
    count_from(0, used, count, limit);
    return count;
  }

  // Every matching, by depth-first search with incremental add/remove moves; the least E(L)
  // goes to `best` (a global minimum of the selection problem).
  void enumerate(std::vector<uint32_t>& best, double& best_energy) {
    build_adjacency();
    arrangement_.reset({});
    std::vector<char> used(net_.ports.size(), 0);
    enumerate_from(0, used, best, best_energy);
  }

  void remember(std::vector<uint32_t>& best, double& best_energy) {
    if (arrangement_.energy() < best_energy) best = arrangement_.selected(), best_energy = arrangement_.energy();
  }

 private:
  void build_adjacency() {
    if (!forward_.empty() || net_.ports.empty()) return;
    forward_.resize(net_.ports.size());
    for (uint32_t c = 0; c < net_.curves.size(); ++c) forward_[net_.curves[c].ports[0]].push_back(c);
  }
  void count_from(uint32_t p, std::vector<char>& used, size_t& count, size_t limit) {
    while (p < used.size() && used[p]) ++p;
    if (count > limit) return;
    if (p >= used.size()) {
      ++count;
      return;
    }
    count_from(p + 1, used, count, limit);  // p stays unmatched
    for (uint32_t c : forward_[p]) {
      const uint32_t q = net_.curves[c].ports[1];
      if (used[q]) continue;
      used[p] = used[q] = 1;
      count_from(p + 1, used, count, limit);
      used[p] = used[q] = 0;
    }
  }
  void enumerate_from(uint32_t p, std::vector<char>& used, std::vector<uint32_t>& best, double& best_energy) {
    while (p < used.size() && used[p]) ++p;
    if (p >= used.size()) {
      ++stats_.matchings_enumerated;
      if ((stats_.matchings_enumerated & 255) == 0) monitor_.report("quad curve selection", 0.5);
      remember(best, best_energy);
      return;
    }
    enumerate_from(p + 1, used, best, best_energy);
    for (uint32_t c : forward_[p]) {
      const uint32_t q = net_.curves[c].ports[1];
      if (used[q]) continue;
      used[p] = used[q] = 1;
      arrangement_.evaluate({}, {c}, true);
      enumerate_from(p + 1, used, best, best_energy);
      arrangement_.evaluate({c}, {}, true);
      used[p] = used[q] = 0;
    }
  }

  int64_t curve(uint32_t a, uint32_t b) const {
    auto it = curve_of_.find(edge_key(a, b));
    return it == curve_of_.end() ? -1 : int64_t(it->second);
  }

  const CurveNetwork& net_;
  const SelectionOptions& options_;
  const TaskMonitor& monitor_;
  QuadSelection& stats_;
  Arrangement arrangement_;
  std::unordered_map<uint64_t, uint32_t> curve_of_;
  std::vector<std::vector<uint32_t>> forward_;  // per port: the curves whose first port it is
  // Every face energy is >= 0 (non-negative weights), so a descent's trials can stop at the best
  // change found so far (Arrangement::evaluate's bound).
  bool bounded_ = false;
  static constexpr double kInfinity = std::numeric_limits<double>::infinity();
 public:
  bool polish_ = false;  // descend() also tries add and remove moves
  std::vector<char> focus_;  // per port; empty: every move (see descend())
};

void validate_matching(const CurveNetwork& net, const std::vector<uint32_t>& curves) {
  std::vector<char> used(net.ports.size(), 0);
  for (uint32_t c : curves) {
    if (c >= net.curves.size())
      fail(Status::invalid_argument, "quad selection: curve " + std::to_string(c) + " does not exist");
    for (uint32_t p : net.curves[c].ports) {
      if (used[p]) fail(Status::invalid_argument, "quad selection: two curves share port " + std::to_string(p));
      used[p] = 1;
    }
  }
}

}  // namespace

double configuration_energy(const CurveNetwork& network, const std::vector<uint32_t>& curves,
                            const ElementWeights& weights) {
  validate_matching(network, curves);
  Arrangement arrangement(network, weights);
  arrangement.reset(curves);
  return arrangement.energy();
}

QuadSelection select_quad_curves(const CurveNetwork& network, const SelectionOptions& options,
                                 const TaskMonitor& monitor) {
  if (network.points.size() < 3) fail(Status::invalid_argument, "quad selection: the network has no region loop");
  if (!(options.bad_crossing_angle >= 0.0 && options.bad_crossing_angle <= kPi / 2))
    fail(Status::invalid_argument, "quad selection: bad_crossing_angle must lie in [0, π/2]");
  QuadSelection result;
  Optimizer optimizer(network, options, monitor, result);
  Arrangement& arrangement = optimizer.arrangement();
  arrangement.reset(phase1_greedy(network));
  result.phase1_energy = arrangement.energy();
  std::vector<uint32_t> best = arrangement.selected();
  double best_energy = arrangement.energy();
  if (options.exhaustive_limit > 0 && optimizer.count_matchings(options.exhaustive_limit) <= options.exhaustive_limit) {
    result.phase2_energy = result.phase1_energy;
    result.exhaustive = true;
    optimizer.enumerate(best, best_energy);
  } else {
    if (options.run_phase2) optimizer.descend();
    result.phase2_energy = arrangement.energy();
    optimizer.remember(best, best_energy);
    if (options.run_phase3) optimizer.escape(best, best_energy);
  }
  result.phase3_energy = best_energy;
  if (options.add_remove_moves && !result.exhaustive) {
    arrangement.reset(best);
    optimizer.polish_ = true;
    optimizer.descend();
    optimizer.remember(best, best_energy);
  }
  result.tracked_energy = best_energy;
  arrangement.reset(best);  // the backup (§6.7.4)
  result.curves = arrangement.selected();
  result.energy = arrangement.energy();
  arrangement.export_mesh(result);
  monitor.report("quad curve selection", 1.0);
  return result;
}

QuadSelection improve_quad_selection(const CurveNetwork& network, const std::vector<uint32_t>& initial,
                                     const SelectionOptions& options, const TaskMonitor& monitor,
                                     const std::vector<char>* focus_ports) {
  if (network.points.size() < 3) fail(Status::invalid_argument, "quad selection: the network has no region loop");
  validate_matching(network, initial);
  if (focus_ports && focus_ports->size() != network.ports.size())
    fail(Status::invalid_argument, "quad selection: the focus needs one flag per port");
  QuadSelection result;
  Optimizer optimizer(network, options, monitor, result);
  Arrangement& arrangement = optimizer.arrangement();
  arrangement.reset(initial);
  result.phase1_energy = result.phase2_energy = result.phase3_energy = arrangement.energy();
  std::vector<uint32_t> best = arrangement.selected();
  double best_energy = arrangement.energy();
  optimizer.polish_ = true;
  if (focus_ports) {
    optimizer.focus_ = *focus_ports;
    // An empty focus would mean "every move": give it one port that matters to nothing instead.
    if (std::find(optimizer.focus_.begin(), optimizer.focus_.end(), 1) == optimizer.focus_.end())
      optimizer.focus_.clear();
  }
  if (!focus_ports || !optimizer.focus_.empty()) optimizer.descend();
  optimizer.remember(best, best_energy);
  result.tracked_energy = best_energy;
  arrangement.reset(best);
  result.curves = arrangement.selected();
  result.energy = arrangement.energy();
  arrangement.export_mesh(result);
  monitor.report("quad curve selection", 1.0);
  return result;
}

CAGEKIT_NAMESPACE_END
