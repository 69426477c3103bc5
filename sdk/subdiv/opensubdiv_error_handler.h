// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// OpenSubdiv reports errors and warnings through process-global callbacks that print to stdout
// by default (Far::SetErrorCallback / Far::SetWarningCallback). CageKit installs, once per
// process, callbacks that print nothing and only remember the last message of the calling
// thread, so that a failed OpenSubdiv call can be turned into a cagekit::Error.
//
// Note: the callbacks are global to the process. A host that also uses OpenSubdiv (Blender)
// loses OpenSubdiv's stdout diagnostics once CageKit has created its first refiner.
#include <string>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN
namespace subdiv_detail {

// Installs the callbacks (thread-safe, idempotent) and clears this thread's last message.
void begin_opensubdiv_call();

// The last error or warning OpenSubdiv reported on this thread since begin_opensubdiv_call(),
// or "" when there was none.
std::string last_opensubdiv_message();

}  // namespace subdiv_detail
CAGEKIT_NAMESPACE_END
