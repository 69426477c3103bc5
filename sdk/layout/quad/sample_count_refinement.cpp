// SPDX-License-Identifier: GPL-3.0-or-later
// Sample-count refinement of the quad-dominant remesher; see sample_count_refinement.h.
#include "layout/quad/sample_count_refinement.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <thread>
#include <unordered_map>
#include <utility>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

namespace {

// Region r's candidate curves for the current samples (steps 3 of one region), with the bending
// fits of unchanged port pairs taken from `cache`.
CurveNetwork region_network(const RemeshConstraints& constraints, uint32_t r, BendingFitCache& cache) {
  std::vector<std::vector<Vec2>> loops;
  for (size_t l = 0; l < constraints.boundaries.region_loops[r].size(); ++l)
    loops.push_back(constraints.loop_samples_uv(r, l));
  CurveNetworkOptions network_options;
  network_options.threads = 1;
  return build_curve_network(loops, network_options, {}, &cache);
}

BendingFitCache::Key curve_key(const CurveNetwork& network, const NetworkCurve& curve) {
  const NetworkPort &a = network.ports[curve.ports[0]], &b = network.ports[curve.ports[1]];
  return BendingFitCache::key(network.points[a.point].uv, a.tangent, network.points[b.point].uv, b.tangent);
}

// A port's identity across network rebuilds: its point and tangent.
BendingFitCache::Key port_key(const CurveNetwork& network, uint32_t port) {
  const NetworkPort& p = network.ports[port];
  const Vec2 none{0.0, 0.0};
  return BendingFitCache::key(network.points[p.point].uv, p.tangent, none, none);
}

// A region's previous configuration carried over to its rebuilt network: the curves of
// `selected` (in `from`) that `to` has too (same end points and tangents), and the ports to
// repair from (`focus`): those that are new (moved points, changed tangents) and those whose
// curve was not carried over.
// Regions with more candidate curves than this are repaired locally in the screen (moves at the
// focus ports only); smaller ones by the full polish descent, which is cheap there.
constexpr size_t kLocalRepairCurves = 60;

struct CarriedSelection {
  std::vector<uint32_t> curves;
  std::vector<char> focus;
};

CarriedSelection carry_selection(const CurveNetwork& from, const std::vector<uint32_t>& selected, const CurveNetwork& to) {
  CarriedSelection out;
  std::unordered_map<BendingFitCache::Key, uint32_t, BendingFitCache::KeyHash> curve_index;
  for (uint32_t c = 0; c < to.curves.size(); ++c) curve_index.emplace(curve_key(to, to.curves[c]), c);
  std::unordered_map<BendingFitCache::Key, bool, BendingFitCache::KeyHash> old_ports;  // port -> had a curve
  for (uint32_t p = 0; p < from.ports.size(); ++p) old_ports.emplace(port_key(from, p), false);
  for (uint32_t c : selected) {
    for (uint32_t p : from.curves[c].ports) old_ports[port_key(from, p)] = true;
    const auto it = curve_index.find(curve_key(from, from.curves[c]));
    if (it != curve_index.end()) out.curves.push_back(it->second);
  }
  std::sort(out.curves.begin(), out.curves.end());
  std::vector<char> carried(to.ports.size(), 0);
  for (uint32_t c : out.curves) carried[to.curves[c].ports[0]] = carried[to.curves[c].ports[1]] = 1;
  out.focus.assign(to.ports.size(), 0);
  for (uint32_t p = 0; p < to.ports.size(); ++p) {
    const auto it = old_ports.find(port_key(to, p));
    out.focus[p] = it == old_ports.end() || (it->second && !carried[p]);
  }
  return out;
}

// A region's share of the glued mesh's irregularity: its non-quad faces, over its arc-interior
// samples how far the number of selected curves ending there is from one (valence 4 needs one on
// each side), and per anchor the number of selected curves ending there (`anchor_curves`).
double region_irregularity(const RemeshConstraints& constraints, uint32_t r, const CurveNetwork& network,
                           const QuadSelection& selection, std::vector<std::pair<uint32_t, int>>& anchor_curves) {
  std::vector<int> used(network.points.size(), 0);
  for (uint32_t c : selection.curves)
    for (uint32_t p : network.curves[c].ports) ++used[network.ports[p].point];
  std::vector<uint8_t> anchor(network.points.size(), 0);
  anchor_curves.clear();
  size_t point = 0;
  for (const RegionLoop& loop : constraints.boundaries.region_loops[r])
    for (size_t k = 0; k < loop.arcs.size(); ++k) {
      const std::vector<uint32_t>& vertices = constraints.boundaries.arcs[loop.arcs[k]].vertices;
      anchor[point] = 1;
      anchor_curves.emplace_back(loop.reversed[k] ? vertices.back() : vertices.front(), used[point]);
      point += constraints.arcs[loop.arcs[k]].samples.t.size() - 1;
    }
  double irregular = double(selection.faces.size() - selection.quads);
  for (size_t i = 0; i < used.size(); ++i)
    if (!anchor[i]) irregular += std::abs(used[i] - 1);
  return irregular;
}


// Runs work(0) .. work(n - 1), n <= 2, the second on its own thread when allowed; rethrows the
// first failure after both finished.
template <typename Work>
void run_one_or_two(size_t n, int threads, Work&& work) {
  if (n == 2 && threads != 1) {
    std::exception_ptr failure;
    std::thread second([&] {
      try {
        work(1);
      } catch (...) {
        failure = std::current_exception();
      }
    });
    try {
      work(0);
    } catch (...) {
      second.join();
      throw;
    }
    second.join();
    if (failure) std::rethrow_exception(failure);
  } else {
    for (size_t i = 0; i < n; ++i) work(i);
  }
}

}  // namespace

void refine_sample_counts(RemeshConstraints& constraints, RegionQuadMeshes& meshes, const SelectionOptions& options,
                          std::vector<BendingFitCache>& caches, int passes, size_t max_curves, int threads,
                          const TaskMonitor& monitor) {
  const size_t regions = meshes.selections.size();
  std::unordered_map<uint32_t, int> anchor_degree, anchor_total;  // arcs at an anchor; curves ending there
  for (const RegionArc& arc : constraints.boundaries.arcs) ++anchor_degree[arc.vertices.front()], ++anchor_degree[arc.vertices.back()];
  std::vector<double> irregularity(regions);
  std::vector<std::vector<std::pair<uint32_t, int>>> anchors(regions);
  for (uint32_t r = 0; r < regions; ++r) {
    irregularity[r] = region_irregularity(constraints, r, meshes.networks[r], meshes.selections[r], anchors[r]);
    for (const auto& [v, n] : anchors[r]) anchor_total[v] += n;
  }
  // Σ |valence − 4| over the anchors of `touched` regions, with their anchor usages replaced.
  auto anchor_cost = [&](const std::vector<uint32_t>& touched,
                         const std::vector<std::vector<std::pair<uint32_t, int>>>& usage) {
    std::unordered_map<uint32_t, int> total;
    for (uint32_t r : touched)
      for (const auto& [v, n] : anchors[r]) total.emplace(v, anchor_total[v]);
    for (uint32_t r : touched)
      for (const auto& [v, n] : anchors[r]) total[v] -= n;
    for (const auto& u : usage)
      for (const auto& [v, n] : u) total[v] += n;
    double cost = 0.0;
    for (const auto& [v, n] : total) cost += std::abs(anchor_degree[v] + n - 4);
    return cost;
  };
  // A candidate state of the touched regions and its rating.
  struct Candidate {
    std::vector<QuadSelection> selections;
    std::vector<std::vector<std::pair<uint32_t, int>>> usage;
    std::vector<double> region_cost;
    double cost = 0.0, energy = 0.0;
  };
  auto rate = [&](const std::vector<uint32_t>& touched, Candidate& c) {
    c.cost = c.energy = 0.0;
    for (size_t i = 0; i < touched.size(); ++i) c.cost += c.region_cost[i], c.energy += c.selections[i].energy;
    c.cost += anchor_cost(touched, c.usage);
  };
  auto better = [](double cost, double energy, double than_cost, double than_energy) {
    return cost < than_cost || (cost == than_cost && energy < than_energy - 1e-9 * (1.0 + than_energy));
  };
  std::vector<uint64_t> version(regions, 1), tried(constraints.arcs.size(), 0);
  uint64_t clock = 1;
  for (int pass = 0; pass < passes; ++pass) {
    bool changed = false;
    for (uint32_t a = 0; a < constraints.arcs.size(); ++a) {
      monitor.report("quad region selection", 1.0);
      const RegionArc& arc = constraints.boundaries.arcs[a];
      std::vector<uint32_t> touched{arc.left_region};
      if (arc.right_region != kMeshBorder) touched.push_back(arc.right_region);
      uint64_t stamp = 0;
      for (uint32_t r : touched) stamp = std::max(stamp, version[r]);
      if (tried[a] >= stamp) continue;
      tried[a] = clock;
      double before = 0.0, before_energy = 0.0;
      std::vector<std::vector<std::pair<uint32_t, int>>> old_usage;
      for (uint32_t r : touched) {
        before += irregularity[r];
        before_energy += meshes.selections[r].energy;
        old_usage.push_back(anchors[r]);
      }
      if (before == 0.0) continue;  // faces all quads, samples all regular
      bool expensive = false;  // re-selecting a region with many candidates costs the most
      for (uint32_t r : touched) expensive |= meshes.networks[r].curves.size() > max_curves;
      if (expensive) continue;
      before += anchor_cost(touched, old_usage);
      const uint32_t current = uint32_t(constraints.arcs[a].samples.t.size() - 1);
      const uint32_t base = constraints.arcs[a].base_segments;
      for (uint32_t value : {current - 1, current + 1}) {
        if (value < 1 || value + 1 < base || value > base + 1) continue;
        resample_arc(constraints, a, value);
        // Every loop stays a curve-network polygon, and a hole of the input keeps 3 samples.
        bool polygons = border_loop_is_polygon(constraints, a);
        for (uint32_t r : touched) polygons &= loops_are_polygons(constraints, r);
        if (!polygons) {
          resample_arc(constraints, a, current);
          continue;
        }
        const size_t n = touched.size();
        std::vector<CurveNetwork> networks(n);
        Candidate screen, full;
        for (Candidate* c : {&screen, &full}) c->selections.resize(n), c->usage.resize(n), c->region_cost.resize(n);
        // The screen: networks rebuilt, previous configurations carried over and improved. A try
        // whose samples make some region's network impossible (a loop without area) is undone.
        std::vector<uint8_t> impossible(n, 0);
        run_one_or_two(n, threads, [&](size_t i) {
          const uint32_t r = touched[i];
          try {
            networks[i] = region_network(constraints, r, caches[r]);
          } catch (const Error& e) {
            if (e.status() == Status::cancelled || e.status() == Status::out_of_memory) throw;
            impossible[i] = 1;
            return;
          }
          const CarriedSelection carried = carry_selection(meshes.networks[r], meshes.selections[r].curves, networks[i]);
          const bool local = networks[i].curves.size() > kLocalRepairCurves;
          screen.selections[i] =
              improve_quad_selection(networks[i], carried.curves, options, {}, local ? &carried.focus : nullptr);
          screen.region_cost[i] = region_irregularity(constraints, r, networks[i], screen.selections[i], screen.usage[i]);
        });
        if (std::find(impossible.begin(), impossible.end(), 1) != impossible.end()) {
          resample_arc(constraints, a, current);
          continue;
        }
        rate(touched, screen);
        if (!better(screen.cost, screen.energy, before, before_energy)) {
          resample_arc(constraints, a, current);
          continue;
        }
        run_one_or_two(n, threads, [&](size_t i) {
          full.selections[i] = select_quad_curves(networks[i], options);
          full.region_cost[i] = region_irregularity(constraints, touched[i], networks[i], full.selections[i], full.usage[i]);
        });
        rate(touched, full);
        Candidate& kept = better(full.cost, full.energy, screen.cost, screen.energy) ? full : screen;
        if (!better(kept.cost, kept.energy, before, before_energy)) {
          resample_arc(constraints, a, current);
          continue;
        }
        for (size_t i = 0; i < n; ++i) {
          const uint32_t r = touched[i];
          for (const auto& [v, k] : anchors[r]) anchor_total[v] -= k;
          for (const auto& [v, k] : kept.usage[i]) anchor_total[v] += k;
          anchors[r] = std::move(kept.usage[i]);
          irregularity[r] = kept.region_cost[i];
          meshes.networks[r] = std::move(networks[i]);
          meshes.selections[r] = std::move(kept.selections[i]);
          version[r] = ++clock;
        }
        changed = true;
        break;
      }
    }
    if (!changed) break;
  }
  meshes.energy = 0.0, meshes.faces = 0, meshes.quads = 0;
  for (const QuadSelection& s : meshes.selections) {
    meshes.energy += s.energy;
    meshes.faces += s.faces.size();
    meshes.quads += s.quads;
  }
}

CAGEKIT_NAMESPACE_END
