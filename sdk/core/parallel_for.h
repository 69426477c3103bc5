// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// parallel_for: body(i) for i in [0, n) on `threads` worker threads (the calling thread is one of
// them), in chunks; progress and cancellation between chunks on the calling thread (stage
// `stage`, fractions from fraction_begin to fraction_end). An exception thrown by a body is
// rethrown on the calling thread after the chunk's workers joined. Each chunk is split into
// contiguous ranges, so results written per index do not depend on the thread count.
#include <algorithm>
#include <exception>
#include <thread>
#include <vector>

#include "core/task_monitor.h"

CAGEKIT_NAMESPACE_BEGIN

// body(begin, end, worker) over `workers` contiguous ranges of [0, n) at once, one thread per
// range (the calling thread takes range 0); an exception thrown by a body is rethrown on the
// calling thread after all joined.
template <typename Body>
void run_ranges(size_t n, size_t workers, Body&& body) {
  workers = std::max<size_t>(1, workers);
  std::vector<std::exception_ptr> errors(workers);
  auto work = [&](size_t w) {
    try {
      body(n * w / workers, n * (w + 1) / workers, w);
    } catch (...) {
      errors[w] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (size_t w = 1; w < workers; ++w) pool.emplace_back(work, w);
  work(0);
  for (auto& t : pool) t.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

// body(begin, end) over up to `threads` contiguous ranges of [0, n) at once (one thread start per
// call, no progress; at least 1024 items per thread): for short per-frame loops.
template <typename Body>
void parallel_ranges(size_t n, int threads, Body&& body) {
  run_ranges(n, std::min<size_t>(size_t(std::max(threads, 1)), n / 1024),
             [&](size_t begin, size_t end, size_t) { body(begin, end); });
}

template <typename Body>
void parallel_for(size_t n, int threads, const TaskMonitor& monitor, const char* stage, double fraction_begin,
                  double fraction_end, Body&& body) {
  const size_t chunk = 8192;
  for (size_t begin = 0; begin < n; begin += chunk) {
    monitor.report(stage, fraction_begin + (fraction_end - fraction_begin) * double(begin) / double(n));
    const size_t end = std::min(n, begin + chunk);
    const size_t workers = std::min<size_t>(size_t(std::max(threads, 1)), (end - begin + 255) / 256);
    run_ranges(end - begin, workers, [&](size_t b, size_t e, size_t) {
      for (size_t i = begin + b; i < begin + e; ++i) body(i);
    });
  }
}

// Worker count for a `threads` option: 0 = std::thread::hardware_concurrency().
inline int resolve_threads(int threads) {
  return threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
}

CAGEKIT_NAMESPACE_END
