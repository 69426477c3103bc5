// SPDX-License-Identifier: GPL-3.0-or-later
#include "job_runner.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <thread>

namespace cagekit_jobs {

namespace {

// argv[0] as a path to execute: names with a '/' are used as they are, others are looked up in
// PATH here, in the parent (execvp may allocate, which a child of a multithreaded process must
// not do before exec).
std::string resolve_program(const std::string& name) {
  if (name.find('/') != std::string::npos) return name;
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  size_t begin = 0;
  while (begin <= dirs.size()) {
    size_t end = dirs.find(':', begin);
    if (end == std::string::npos) end = dirs.size();
    std::string dir = dirs.substr(begin, end - begin);
    if (dir.empty()) dir = ".";
    const std::string candidate = dir + "/" + name;
    struct stat info {};
    if (stat(candidate.c_str(), &info) == 0 && S_ISREG(info.st_mode) && access(candidate.c_str(), X_OK) == 0)
      return candidate;
    begin = end + 1;
  }
  return name;  // execv fails with ENOENT, reported as "not started"
}

double seconds_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

double timeval_seconds(const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); }

// In the child, after fork: only async-signal-safe calls. Reports a failure through `error_fd`
// (errno, then the step that failed) and exits 127.
[[noreturn]] void child_fail(int error_fd, int step) {
  const int payload[2] = {errno, step};
  ssize_t ignored = write(error_fd, payload, sizeof(payload));
  (void)ignored;
  _exit(127);
}

int open_output(const char* path) {
  return path ? open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644) : open("/dev/null", O_WRONLY);
}

const char* signal_name(int signal) {
  switch (signal) {
    case SIGSEGV: return "SIGSEGV";
    case SIGABRT: return "SIGABRT";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGILL: return "SIGILL";
    case SIGKILL: return "SIGKILL";
    case SIGTERM: return "SIGTERM";
    case SIGPIPE: return "SIGPIPE";
    case SIGTRAP: return "SIGTRAP";
    default: return "other signal";
  }
}

const char* kSteps[] = {"exec", "open stdout", "open stderr", "open /dev/null", "set the memory limit",
                        "redirect output", "create a process group"};

}  // namespace

JobResult run_job(const JobSpec& spec) {
  if (spec.argv.empty()) throw std::invalid_argument("run_job: empty argv");
  JobResult result;

  // Everything the child needs is prepared before fork.
  const std::string program = resolve_program(spec.argv[0]);
  std::vector<char*> argv;
  argv.reserve(spec.argv.size() + 1);
  for (const std::string& a : spec.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const char* out_path = spec.stdout_path.empty() ? nullptr : spec.stdout_path.c_str();
  const char* err_path = spec.stderr_path.empty() ? nullptr : spec.stderr_path.c_str();
  rlimit memory{};
  memory.rlim_cur = memory.rlim_max = spec.memory_limit_bytes ? rlim_t(spec.memory_limit_bytes) : RLIM_INFINITY;

  // Close-on-exec pipe: the child writes errno into it when it cannot exec; a successful exec
  // closes it, so the parent reads 0 bytes.
  int error_pipe[2];
  if (pipe2(error_pipe, O_CLOEXEC) != 0) {
    result.error = std::string("cannot create a pipe: ") + std::strerror(errno);
    return result;
  }

  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid < 0) {
    result.error = std::string("cannot fork: ") + std::strerror(errno);
    close(error_pipe[0]);
    close(error_pipe[1]);
    return result;
  }
  if (pid == 0) {
    // Child.
    close(error_pipe[0]);
    if (setpgid(0, 0) != 0) child_fail(error_pipe[1], 6);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    struct sigaction default_action {};
    default_action.sa_handler = SIG_DFL;
    sigaction(SIGPIPE, &default_action, nullptr);
    const int in = open("/dev/null", O_RDONLY);
    if (in < 0) child_fail(error_pipe[1], 3);
    const int out = open_output(out_path);
    if (out < 0) child_fail(error_pipe[1], 1);
    const int err = open_output(err_path);
    if (err < 0) child_fail(error_pipe[1], 2);
    if (dup2(in, 0) < 0 || dup2(out, 1) < 0 || dup2(err, 2) < 0) child_fail(error_pipe[1], 5);
    if (in > 2) close(in);
    if (out > 2) close(out);
    if (err > 2) close(err);
    if (spec.memory_limit_bytes && setrlimit(RLIMIT_AS, &memory) != 0) child_fail(error_pipe[1], 4);
    execv(program.c_str(), argv.data());
    child_fail(error_pipe[1], 0);
  }

  // Parent. Also set the group here: whichever of the two runs first, the group exists before
  // the parent may need to signal it.
  setpgid(pid, pid);
  close(error_pipe[1]);
  int payload[2] = {0, 0};
  size_t got = 0;
  while (got < sizeof(payload)) {
    const ssize_t n = read(error_pipe[0], reinterpret_cast<char*>(payload) + got, sizeof(payload) - got);
    if (n > 0) {
      got += size_t(n);
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  close(error_pipe[0]);
  const bool exec_failed = got == sizeof(payload);

  // Wait for the child to end without reaping it (WNOWAIT): while it is a zombie its pid, and
  // so its process group id, cannot be reused, so the group can be killed safely afterwards.
  std::chrono::microseconds pause(500);
  for (;;) {
    siginfo_t info{};
    const int r = waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT);
    if (r != 0) {
      if (errno == EINTR) continue;
      break;  // ECHILD: someone else reaped it (should not happen); wait4 below reports it
    }
    if (info.si_pid == pid) break;
    const double elapsed = seconds_between(start, std::chrono::steady_clock::now());
    if (!result.timed_out && spec.timeout_seconds > 0.0 && elapsed >= spec.timeout_seconds) {
      kill(-pid, SIGKILL);
      result.timed_out = true;
    }
    if (!result.timed_out && !result.cancelled && spec.cancel && spec.cancel->load()) {
      kill(-pid, SIGKILL);
      result.cancelled = true;
    }
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(20000));
  }
  // Whatever the child left running in its group goes with it.
  kill(-pid, SIGKILL);

  int status = 0;
  rusage usage{};
  pid_t reaped;
  do {
    reaped = wait4(pid, &status, 0, &usage);
  } while (reaped < 0 && errno == EINTR);
  result.wall_seconds = seconds_between(start, std::chrono::steady_clock::now());
  if (reaped != pid) {
    result.error = std::string("cannot wait for the child: ") + std::strerror(errno);
    return result;
  }
  if (exec_failed) {
    const int step = payload[1] >= 0 && payload[1] < int(sizeof(kSteps) / sizeof(kSteps[0])) ? payload[1] : 0;
    result.error = std::string("cannot ") + kSteps[step] + " for " + spec.argv[0] + ": " + std::strerror(payload[0]);
    return result;
  }
  result.started = true;
  result.cpu_seconds = timeval_seconds(usage.ru_utime) + timeval_seconds(usage.ru_stime);
  result.peak_rss_mb = double(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
  if (WIFEXITED(status)) {
    result.exited = true;
    result.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    result.signaled = true;
    result.signal = WTERMSIG(status);
  }
  // A child that ended on its own just as the limit passed is not a timeout.
  if (result.timed_out && !(result.signaled && result.signal == SIGKILL)) result.timed_out = false;
  if (result.cancelled && !(result.signaled && result.signal == SIGKILL)) result.cancelled = false;
  return result;
}

bool likely_out_of_memory(const JobResult& result, const std::string& stderr_text) {
  if (!result.started || result.timed_out || result.cancelled) return false;
  if (result.exited && result.exit_code == 0) return false;
  std::string lower(stderr_text);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (lower.find("out of memory") != std::string::npos || lower.find("bad_alloc") != std::string::npos ||
      lower.find("cannot allocate memory") != std::string::npos ||
      lower.find("failed to map segment") != std::string::npos ||  // ld.so under a small RLIMIT_AS
      lower.find("memory budget") != std::string::npos)
    return true;
  // SIGKILL that the runner did not send: the kernel's OOM killer.
  return result.signaled && result.signal == SIGKILL;
}

std::string read_file_head(const std::string& path, size_t max_bytes) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return "";
  std::string text(max_bytes, '\0');
  const size_t n = std::fread(&text[0], 1, max_bytes, f);
  std::fclose(f);
  text.resize(n);
  return text;
}

std::string describe(const JobResult& result) {
  char buffer[160];
  if (!result.started) return "not started: " + result.error;
  if (result.timed_out) {
    std::snprintf(buffer, sizeof(buffer), "timed out after %.1f s", result.wall_seconds);
  } else if (result.cancelled) {
    std::snprintf(buffer, sizeof(buffer), "cancelled after %.1f s", result.wall_seconds);
  } else if (result.signaled) {
    std::snprintf(buffer, sizeof(buffer), "signal %d (%s)", result.signal, signal_name(result.signal));
  } else {
    std::snprintf(buffer, sizeof(buffer), "exit %d", result.exit_code);
  }
  return buffer;
}

}  // namespace cagekit_jobs
