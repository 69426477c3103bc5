// SPDX-License-Identifier: GPL-3.0-or-later
// Steps 3-4 over all regions; see quad_region_selection.h.
#include "layout/quad/quad_region_selection.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <numeric>
#include <string>
#include <thread>

#include "core/parallel_for.h"
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

RegionQuadMeshes select_region_quads(const RemeshConstraints& constraints, const CurveNetworkOptions& network_options,
                                     const SelectionOptions& selection_options, int threads,
                                     const TaskMonitor& monitor, std::vector<BendingFitCache>* fit_caches,
                                     std::vector<RegionFailure>* failures, SelectionMemo* memo) {
  if (threads < 0) fail(Status::invalid_argument, "select_region_quads: threads must be >= 0");
  const size_t regions = constraints.boundaries.region_loops.size();
  RegionQuadMeshes out;
  out.networks.resize(regions);
  out.selections.resize(regions);
  if (fit_caches) fit_caches->assign(regions, BendingFitCache());
  // Largest regions (by constrained points) first, for the load balance.
  std::vector<size_t> samples(regions, 0), order(regions);
  for (uint32_t r = 0; r < regions; ++r)
    for (size_t l = 0; l < constraints.boundaries.region_loops[r].size(); ++l)
      samples[r] += constraints.loop_samples_uv(r, l).size();
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return samples[a] > samples[b]; });
  CurveNetworkOptions per_region = network_options;
  per_region.threads = 1;  // the parallelism is over regions
  std::atomic<size_t> next{0}, done{0};
  std::mutex failure_mutex;
  if (failures) failures->clear();
  const size_t workers = std::max<size_t>(
      1, std::min<size_t>(threads > 0 ? size_t(threads) : std::thread::hardware_concurrency(), regions));
  run_ranges(workers, workers, [&](size_t, size_t, size_t worker) {
    for (size_t k = next++; k < regions; k = next++) {
      if (worker == 0) monitor.report("quad region selection", double(done) / std::max<size_t>(1, regions));
      const uint32_t r = static_cast<uint32_t>(order[k]);
      std::vector<std::vector<Vec2>> loops;
      for (size_t l = 0; l < constraints.boundaries.region_loops[r].size(); ++l)
        loops.push_back(constraints.loop_samples_uv(r, l));
      if (failures && !(plane2::signed_area(loops[0]) > 0.0)) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        failures->push_back({r, "region " + std::to_string(r) + ": its outer loop of " +
                                    std::to_string(loops[0].size()) + " samples has no area in its domain",
                             true});
        ++done;
        continue;
      }
      std::string key;
      if (memo) {
        for (const std::vector<Vec2>& loop : loops) {
          const uint64_t n = loop.size();
          key.append(reinterpret_cast<const char*>(&n), sizeof(n));
          key.append(reinterpret_cast<const char*>(loop.data()), loop.size() * sizeof(Vec2));
        }
        const std::lock_guard<std::mutex> lock(memo->mutex);
        const auto it = memo->entries.find(key);
        if (it != memo->entries.end()) {
          out.networks[r] = it->second.network;
          out.selections[r] = it->second.selection;
          if (fit_caches) (*fit_caches)[r] = it->second.fit_cache;
          ++memo->hits;
          ++done;
          continue;
        }
      }
      try {
        out.networks[r] = build_curve_network(loops, per_region, {}, fit_caches ? &(*fit_caches)[r] : nullptr);
        out.selections[r] = select_quad_curves(out.networks[r], selection_options);
        if (memo) {
          SelectionMemo::Entry entry{out.networks[r], out.selections[r],
                                     fit_caches ? (*fit_caches)[r] : BendingFitCache()};
          const std::lock_guard<std::mutex> lock(memo->mutex);
          memo->entries.emplace(std::move(key), std::move(entry));
        }
      } catch (const Error& e) {
        if (!failures || e.status() == Status::cancelled || e.status() == Status::out_of_memory)
          fail(e.status(), "region " + std::to_string(r) + ": " + e.what());
        const std::lock_guard<std::mutex> lock(failure_mutex);
        failures->push_back({r, "region " + std::to_string(r) + ": " + e.what()});
        out.networks[r] = {};
        out.selections[r] = {};
      }
      ++done;
    }
  });
  for (const QuadSelection& s : out.selections) {
    out.energy += s.energy;
    out.faces += s.faces.size();
    out.quads += s.quads;
  }
  if (failures)
    std::sort(failures->begin(), failures->end(),
              [](const RegionFailure& a, const RegionFailure& b) { return a.region < b.region; });
  monitor.report("quad region selection", 1.0);
  return out;
}

CAGEKIT_NAMESPACE_END
