// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// OpenSubdiv reports errors and warnings through process-global callbacks that print to stdout
// by default (Far::SetErrorCallback / Far::SetWarningCallback). CageKit installs, once per
// process, callbacks that print nothing and only remember the first error and the first warning
// of the calling thread, so that a failed OpenSubdiv call becomes a cagekit::Error.
//
// Note: the callbacks are global to the process. A host that also uses OpenSubdiv (Blender)
// loses OpenSubdiv's stdout diagnostics once CageKit has created its first refiner.
#include <string>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {

// Installs the callbacks (thread-safe, idempotent) and clears this thread's messages.
void begin_opensubdiv_call();

// The first error (or, if none, warning) OpenSubdiv reported on this thread since
// begin_opensubdiv_call(), "" when there was none.
std::string last_opensubdiv_message();

// Throws Error(status, what + ": " + message) when OpenSubdiv reported an error (not a warning)
// on this thread since begin_opensubdiv_call().
void fail_on_opensubdiv_error(Status status, const std::string& what);

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
