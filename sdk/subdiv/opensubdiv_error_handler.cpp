// SPDX-License-Identifier: GPL-3.0-or-later
#include "subdiv/opensubdiv_error_handler.h"

#include <opensubdiv/far/error.h>

#include <mutex>

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {
namespace {

namespace Far = OpenSubdiv::Far;

thread_local std::string t_last_message;

// Called from inside OpenSubdiv: must neither throw nor print. Only the first message of a
// call is kept, since later ones are usually consequences of it.
void remember_message(const char* kind, const char* message) noexcept {
  try {
    if (t_last_message.empty()) t_last_message = std::string(kind) + (message ? message : "(no message)");
  } catch (...) {
    // Out of memory while recording a diagnostic: the caller still sees the failure itself.
  }
}

void on_error(Far::ErrorType type, const char* message) {
  remember_message(type == Far::FAR_FATAL_ERROR ? "OpenSubdiv fatal error: " : "OpenSubdiv error: ", message);
}

void on_warning(const char* message) { remember_message("OpenSubdiv warning: ", message); }

}  // namespace

void begin_opensubdiv_call() {
  static std::once_flag installed;
  std::call_once(installed, [] {
    Far::SetErrorCallback(&on_error);
    Far::SetWarningCallback(&on_warning);
  });
  t_last_message.clear();
}

std::string last_opensubdiv_message() { return t_last_message; }

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
