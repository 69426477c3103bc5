// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Measurement helpers shared by the benchmarks: wall and process-CPU clocks, load average,
// /proc/self/status fields (VmHWM, VmRSS).
#include <time.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>

namespace bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Process CPU time: robust to other processes competing for the cores (everything timed here is
// single-threaded, so on an idle machine it equals the wall time).
inline double cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

inline std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one + " " + five + " " + fifteen;
}

// A "Field:   1234 kB" line of /proc/self/status, in KiB; -1 if absent.
inline long status_kib(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(in, line))
    if (line.compare(0, key.size(), key) == 0) return std::atol(line.c_str() + key.size());
  return -1;
}

}  // namespace bench
