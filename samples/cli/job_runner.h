// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Runs one command in a child process with a wall-time and an address-space limit and reports
// how it ended (exit code or signal, timed out, likely out of memory), its wall and CPU seconds
// and its peak resident memory. Written once for the corpus harness (tests/corpus) and
// `cagekit batch` (command_batch.cpp); it does not depend on the SDK.
//
// The child runs in its own process group: on a timeout the whole group is killed with SIGKILL,
// and after the child ends whatever it left running in its group is killed too, so a run never
// leaves orphans behind. The child is always reaped (no zombies). run_job is safe to call from
// several threads at once: between fork and exec the child only makes async-signal-safe calls.
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace cagekit_jobs {

struct JobSpec {
  std::vector<std::string> argv;   // argv[0] is looked up in PATH when it has no '/'
  std::string stdout_path;         // file that receives the child's stdout ("" = /dev/null)
  std::string stderr_path;         // file that receives the child's stderr ("" = /dev/null)
  double timeout_seconds = 0.0;    // wall-time limit; <= 0: none
  uint64_t memory_limit_bytes = 0; // RLIMIT_AS of the child; 0: none
  // When set, the runner polls it while the child runs and kills the child's group with SIGKILL
  // once it reads true (an interrupted `cagekit batch`); the result then says cancelled.
  const std::atomic<bool>* cancel = nullptr;
};

struct JobResult {
  bool started = false;       // false: the command could not be started (see error)
  std::string error;          // why it could not start (exec failure, fork failure, ...)
  bool exited = false;        // ended by exit(): exit_code is valid
  int exit_code = -1;
  bool signaled = false;      // ended by a signal: signal is valid
  int signal = 0;
  bool timed_out = false;     // killed by the runner after timeout_seconds (signaled, SIGKILL)
  bool cancelled = false;     // killed by the runner because spec.cancel became true (signaled, SIGKILL)
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;   // user + system time of the child and the children it waited for
  double peak_rss_mb = 0.0;   // largest resident set of the child (or a waited-for descendant)
};

// Runs spec.argv to its end (or its time limit) and returns how it ended. Never throws for
// failures of the child; throws std::invalid_argument for an empty argv.
JobResult run_job(const JobSpec& spec);

// Whether a run most likely ended because it ran out of memory: a message on its stderr that
// says so (the CLI's "out of memory", std::bad_alloc from an uncaught exception, "Cannot
// allocate memory", the dynamic loader's "failed to map segment" under a small address-space
// limit), or a SIGKILL the runner did not send (the kernel's OOM killer).
// `stderr_text` is the captured stderr (or its beginning).
bool likely_out_of_memory(const JobResult& result, const std::string& stderr_text);

// The first `max_bytes` bytes of a file ("" when it cannot be read).
std::string read_file_head(const std::string& path, size_t max_bytes);

// "exit 3", "signal 11 (SIGSEGV)", "timed out after 2.0 s", "cancelled", "not started: ..."
std::string describe(const JobResult& result);

}  // namespace cagekit_jobs
