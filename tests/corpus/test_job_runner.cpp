// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the child-process runner (samples/cli/job_runner.h): exit codes, signals, the wall-time
// limit, the memory limit, captured output, resource figures, and that no zombie or orphan is
// left behind. The test program is also its own helper child (--allocate, --touch, --spin).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <string>
#include <thread>
#include <vector>

#include "job_runner.h"

namespace {

using cagekit_jobs::JobResult;
using cagekit_jobs::JobSpec;
using cagekit_jobs::run_job;

std::string g_self;  // this program, for the helper-child modes

std::string scratch(const std::string& name) {
  const char* tmp = std::getenv("TMPDIR");
  return std::string(tmp && *tmp ? tmp : "/tmp") + "/cagekit_job_runner_" + std::to_string(getpid()) + "_" + name;
}

std::string slurp(const std::string& path) { return cagekit_jobs::read_file_head(path, 1 << 20); }

// True when the process is gone or a zombie (dead, waiting for its parent, here init, to reap it).
bool process_dead(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  if (!stat) return true;
  std::string line;
  std::getline(stat, line);
  const size_t close = line.rfind(')');
  return close == std::string::npos || close + 2 >= line.size() || line[close + 2] == 'Z' || line[close + 2] == 'X';
}

bool dead_within(pid_t pid, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (process_dead(pid)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return process_dead(pid);
}

// Every test ends with every child reaped: no zombie of ours is left.
class JobRunner : public ::testing::Test {
 protected:
  void TearDown() override {
    errno = 0;
    EXPECT_EQ(waitpid(-1, nullptr, WNOHANG), -1) << "a child of the test process was not reaped";
    EXPECT_EQ(errno, ECHILD);
  }
};

JobSpec shell(const std::string& script, const std::string& name) {
  JobSpec spec;
  spec.argv = {"sh", "-c", script};
  spec.stdout_path = scratch(name + ".out");
  spec.stderr_path = scratch(name + ".err");
  return spec;
}

TEST_F(JobRunner, ExitCodeAndCapturedOutput) {
  JobSpec spec = shell("echo to-stdout; echo to-stderr >&2; exit 3", "exit3");
  const JobResult r = run_job(spec);
  ASSERT_TRUE(r.started) << r.error;
  EXPECT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_FALSE(r.signaled);
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(slurp(spec.stdout_path), "to-stdout\n");
  EXPECT_EQ(slurp(spec.stderr_path), "to-stderr\n");
  EXPECT_EQ(cagekit_jobs::describe(r), "exit 3");
  EXPECT_FALSE(cagekit_jobs::likely_out_of_memory(r, slurp(spec.stderr_path)));
  std::remove(spec.stdout_path.c_str());
  std::remove(spec.stderr_path.c_str());
}

TEST_F(JobRunner, ExitZeroWithoutOutputFiles) {
  JobSpec spec;
  spec.argv = {"true"};  // looked up in PATH
  const JobResult r = run_job(spec);
  ASSERT_TRUE(r.started) << r.error;
  EXPECT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_GE(r.wall_seconds, 0.0);
}

TEST_F(JobRunner, Segfault) {
  JobSpec spec = shell("kill -SEGV $$", "segv");
  const JobResult r = run_job(spec);
  ASSERT_TRUE(r.started) << r.error;
  EXPECT_FALSE(r.exited);
  EXPECT_TRUE(r.signaled);
  EXPECT_EQ(r.signal, SIGSEGV);
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(cagekit_jobs::describe(r), "signal 11 (SIGSEGV)");
  EXPECT_FALSE(cagekit_jobs::likely_out_of_memory(r, slurp(spec.stderr_path)));
  std::remove(spec.stdout_path.c_str());
  std::remove(spec.stderr_path.c_str());
}

TEST_F(JobRunner, TimeoutKillsTheWholeGroup) {
  // The shell starts a grandchild and waits: both must be gone after the limit.
  JobSpec spec = shell("sleep 30 & echo $!; wait", "timeout");
  spec.timeout_seconds = 0.5;
  const auto t0 = std::chrono::steady_clock::now();
  const JobResult r = run_job(spec);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r.started) << r.error;
  EXPECT_TRUE(r.timed_out);
  EXPECT_TRUE(r.signaled);
  EXPECT_EQ(r.signal, SIGKILL);
  EXPECT_GE(r.wall_seconds, 0.5);
  EXPECT_LT(took, 10.0);
  EXPECT_FALSE(cagekit_jobs::likely_out_of_memory(r, ""));  // our own SIGKILL is not an OOM kill
  const pid_t grandchild = pid_t(std::atol(slurp(spec.stdout_path).c_str()));
  ASSERT_GT(grandchild, 0);
  EXPECT_TRUE(dead_within(grandchild, 5.0)) << "grandchild " << grandchild << " survived the timeout";
  std::remove(spec.stdout_path.c_str());
  std::remove(spec.stderr_path.c_str());
}

TEST_F(JobRunner, CancelKillsTheWholeGroup) {
  // `cagekit batch` interrupted: another thread sets the flag; the child and its grandchild go.
  JobSpec spec = shell("sleep 30 & echo $!; wait", "cancel");
  std::atomic<bool> cancel{false};
  spec.cancel = &cancel;
  std::thread canceller([&cancel] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    cancel = true;
  });
  const JobResult r = run_job(spec);
  canceller.join();
  ASSERT_TRUE(r.started) << r.error;
  EXPECT_TRUE(r.cancelled);
  EXPECT_FALSE(r.timed_out);
  EXPECT_TRUE(r.signaled);
  EXPECT_EQ(r.signal, SIGKILL);
  EXPECT_LT(r.wall_seconds, 10.0);
  EXPECT_EQ(cagekit_jobs::describe(r).rfind("cancelled after ", 0), 0u) << cagekit_jobs::describe(r);
  EXPECT_FALSE(cagekit_jobs::likely_out_of_memory(r, ""));  // our own SIGKILL is not an OOM kill
  const pid_t grandchild = pid_t(std::atol(slurp(spec.stdout_path).c_str()));
  ASSERT_GT(grandchild, 0);
  EXPECT_TRUE(dead_within(grandchild, 5.0)) << "grandchild " << grandchild << " survived the cancel";
  std::remove(spec.stdout_path.c_str());
  std::remove(spec.stderr_path.c_str());
}

TEST_F(JobRunner, NoOrphanAfterNormalExit) {
  JobSpec spec = shell("sleep 30 & echo $!; exit 0", "orphan");
  spec.timeout_seconds = 20.0;
  const JobResult r = run_job(spec);
  ASSERT_TRUE(r.started) << r.error;
  EXPECT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_LT(r.wall_seconds, 10.0);  // it did not wait for the sleep
  const pid_t grandchild = pid_t(std::atol(slurp(spec.stdout_path).c_str()));
  ASSERT_GT(grandchild, 0);
  EXPECT_TRUE(dead_within(grandchild, 5.0)) << "grandchild " << grandchild << " left running";
  std::remove(spec.stdout_path.c_str());
  std::remove(spec.stderr_path.c_str());
}

#if !defined(CAGEKIT_TEST_SANITIZED)
// (Sanitizer runtimes reserve terabytes of address space: an RLIMIT_AS would stop them first.)
TEST_F(JobRunner, MemoryLimitCaughtBadAlloc) {
  JobSpec spec;
  spec.argv = {g_self, "--allocate", "4096", "--catch"};
  spec.stdout_path = scratch("oom1.out");
  spec.stderr_path = scratch("oom1.err");
  spec.memory_limit_bytes = 256ull << 20;
  spec.timeout_seconds = 60.0;
  const JobResult r = run_job(spec);
  ASSERT_TRUE(r.started) << r.error;
  const std::string err = slurp(spec.stderr_path);
  EXPECT_TRUE(r.exited) << cagekit_jobs::describe(r);
  EXPECT_EQ(r.exit_code, 2) << err;
  EXPECT_NE(err.find("out of memory"), std::string::npos) << err;
  EXPECT_TRUE(cagekit_jobs::likely_out_of_memory(r, err));
  EXPECT_LT(r.peak_rss_mb, 300.0);
  std::remove(spec.stdout_path.c_str());
  std::remove(spec.stderr_path.c_str());
}

TEST_F(JobRunner, MemoryLimitUncaughtBadAlloc) {
  JobSpec spec;
  spec.argv = {g_self, "--allocate", "4096"};
  spec.stdout_path = scratch("oom2.out");
  spec.stderr_path = scratch("oom2.err");
  spec.memory_limit_bytes = 256ull << 20;
  spec.timeout_seconds = 60.0;
  const JobResult r = run_job(spec);
  ASSERT_TRUE(r.started) << r.error;
  const std::string err = slurp(spec.stderr_path);
  EXPECT_TRUE(r.signaled) << cagekit_jobs::describe(r) << " " << err;
  EXPECT_EQ(r.signal, SIGABRT);
  EXPECT_TRUE(cagekit_jobs::likely_out_of_memory(r, err)) << err;
  std::remove(spec.stdout_path.c_str());
  std::remove(spec.stderr_path.c_str());
}

TEST_F(JobRunner, SameAllocationSucceedsWithoutTheLimit) {
  JobSpec spec;
  spec.argv = {g_self, "--allocate", "64", "--catch"};
  const JobResult r = run_job(spec);
  ASSERT_TRUE(r.started) << r.error;
  EXPECT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 0);
}
#endif

TEST_F(JobRunner, PeakMemoryAndCpuTime) {
  JobSpec spec;
  spec.argv = {g_self, "--touch", "96", "--spin", "0.3"};
  const JobResult r = run_job(spec);
  ASSERT_TRUE(r.started) << r.error;
  EXPECT_TRUE(r.exited);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_GE(r.peak_rss_mb, 90.0);
  EXPECT_LT(r.peak_rss_mb, 1024.0);
  EXPECT_GE(r.cpu_seconds, 0.25);
  EXPECT_GE(r.wall_seconds, r.cpu_seconds * 0.5);
}

TEST_F(JobRunner, CommandThatCannotStart) {
  JobSpec spec;
  spec.argv = {"/nonexistent/cagekit-no-such-program"};
  const JobResult r = run_job(spec);
  EXPECT_FALSE(r.started);
  EXPECT_NE(r.error.find("No such file"), std::string::npos) << r.error;
  EXPECT_EQ(cagekit_jobs::describe(r).rfind("not started: ", 0), 0u);
  JobSpec unwritable = shell("exit 0", "x");
  unwritable.stdout_path = "/nonexistent-dir/out.txt";
  const JobResult w = run_job(unwritable);
  EXPECT_FALSE(w.started);
  EXPECT_NE(w.error.find("open stdout"), std::string::npos) << w.error;
}

TEST_F(JobRunner, ConcurrentRunsKeepTheirOwnResults) {
  constexpr int kRuns = 6;
  std::vector<JobResult> results(kRuns);
  std::vector<std::thread> threads;
  for (int i = 0; i < kRuns; ++i)
    threads.emplace_back([i, &results] {
      JobSpec spec;
      spec.argv = {"sh", "-c", "sleep 0.1; exit " + std::to_string(10 + i)};
      spec.timeout_seconds = 30.0;
      results[size_t(i)] = run_job(spec);
    });
  for (std::thread& t : threads) t.join();
  for (int i = 0; i < kRuns; ++i) {
    ASSERT_TRUE(results[size_t(i)].started) << results[size_t(i)].error;
    EXPECT_EQ(results[size_t(i)].exit_code, 10 + i);
  }
}

// Helper-child modes. --allocate MB [--catch]: allocate MB mebibytes in 16 MiB blocks (touched);
// with --catch, std::bad_alloc prints "out of memory" and exits 2 (as the CLI does). --touch MB:
// allocate and touch MB mebibytes, keep them. --spin S: burn S seconds of CPU.
int helper_child(int argc, char** argv) {
  long allocate = 0, touch = 0;
  double spin = 0.0;
  bool catch_it = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--allocate" && i + 1 < argc) allocate = std::atol(argv[++i]);
    else if (a == "--touch" && i + 1 < argc) touch = std::atol(argv[++i]);
    else if (a == "--spin" && i + 1 < argc) spin = std::atof(argv[++i]);
    else if (a == "--catch") catch_it = true;
  }
  std::vector<std::vector<char>> blocks;
  auto grab = [&blocks](long mb) {
    for (long done = 0; done < mb; done += 16) blocks.emplace_back(size_t(16) << 20, char(1));
  };
  if (allocate > 0) {
    if (catch_it) {
      try {
        grab(allocate);
      } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "helper: out of memory\n");
        return 2;
      }
    } else {
      grab(allocate);
    }
  }
  if (touch > 0) grab(touch);
  // Spins until the process has used `spin` seconds of CPU (not of wall time: on a loaded
  // machine a wall-time spin gets less CPU, and the runner's cpu_seconds check failed in CI).
  volatile double sink = 0.0;
  while (double(std::clock()) / CLOCKS_PER_SEC < spin)
    for (int k = 0; k < 10000; ++k) sink = sink + 1e-9 * k;
  return blocks.empty() && allocate + touch > 0 ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  g_self = "/proc/self/exe";
  char path[4096];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof(path) - 1);
  if (n > 0) g_self.assign(path, size_t(n));
  if (argc > 1 && (std::strcmp(argv[1], "--allocate") == 0 || std::strcmp(argv[1], "--touch") == 0))
    return helper_child(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
