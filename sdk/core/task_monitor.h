// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// TaskMonitor: progress reporting, cancellation and log messages of long operations.
// A default-constructed monitor does nothing. Long loops call report() every so often;
// report() throws Error(Status::cancelled) when the progress callback asks to stop.
#include <functional>
#include <string>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

enum class LogLevel : int { debug = 0, info = 1, warning = 2, error = 3 };

class TaskMonitor {
 public:
  // Returns false to cancel. fraction is in [0, 1].
  using ProgressFn = std::function<bool(const char* stage, double fraction)>;
  using LogFn = std::function<void(LogLevel level, const std::string& message)>;

  TaskMonitor() = default;
  TaskMonitor(ProgressFn progress, LogFn log) : progress_(std::move(progress)), log_(std::move(log)) {}

  void report(const char* stage, double fraction) const {
    if (progress_ && !progress_(stage, fraction))
      fail(Status::cancelled, std::string("cancelled by the progress callback during ") + stage);
  }
  void log(LogLevel level, const std::string& message) const {
    if (log_) log_(level, message);
  }

 private:
  ProgressFn progress_;
  LogFn log_;
};

CAGEKIT_NAMESPACE_END
