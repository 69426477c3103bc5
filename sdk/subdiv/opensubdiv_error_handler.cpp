// SPDX-License-Identifier: GPL-3.0-or-later
#include "subdiv/opensubdiv_error_handler.h"

#include <opensubdiv/far/error.h>

#include <mutex>

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {
namespace {

namespace Far = OpenSubdiv::Far;

thread_local std::string t_error;
thread_local std::string t_warning;

// Called from inside OpenSubdiv: must neither throw nor print. Only the first message is kept,
// since later ones are usually consequences of it.
void remember(std::string* slot, const char* message) noexcept {
  try {
    if (slot->empty()) *slot = message && *message ? message : "(no message)";
  } catch (...) {
    // Out of memory while recording a diagnostic: the failure itself is still detected.
  }
}

void on_error(Far::ErrorType, const char* message) { remember(&t_error, message); }

void on_warning(const char* message) { remember(&t_warning, message); }

}  // namespace

void begin_opensubdiv_call() {
  static std::once_flag installed;
  std::call_once(installed, [] {
    Far::SetErrorCallback(&on_error);
    Far::SetWarningCallback(&on_warning);
  });
  t_error.clear();
  t_warning.clear();
}

std::string last_opensubdiv_message() {
  if (!t_error.empty()) return "OpenSubdiv error: " + t_error;
  if (!t_warning.empty()) return "OpenSubdiv warning: " + t_warning;
  return std::string();
}

void fail_on_opensubdiv_error(Status status, const std::string& what) {
  if (!t_error.empty()) fail(status, what + ": OpenSubdiv error: " + t_error);
}

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
