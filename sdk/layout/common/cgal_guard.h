// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Private to the *_cgal.cpp translation units of sdk/layout (the only ones that include CGAL).
//
// CGAL's checks (preconditions, assertions, postconditions) are compiled into those translation
// units in every build type: sdk/layout/CMakeLists.txt defines CGAL_DEBUG for them, which undoes
// the CGAL_NDEBUG that NDEBUG implies (CGAL/assertions.h), so a violated precondition throws
// CGAL::Failure_exception instead of being undefined behaviour (a crash, or a silently wrong
// triangulation, invisible to the sanitizer runs, which build with NDEBUG). Every SDK function
// that calls CGAL runs its body through cgal_guarded, which turns such an exception into
// Error(internal_error) naming the function, the violated condition and where CGAL checks it:
// no CGAL exception leaves these functions.
#include <CGAL/exceptions.h>

#include <string>
#include <utility>

#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN
namespace detail {

inline std::string describe_cgal_failure(const CGAL::Failure_exception& e) {
  const char* kind = dynamic_cast<const CGAL::Precondition_exception*>(&e)    ? "precondition"
                     : dynamic_cast<const CGAL::Postcondition_exception*>(&e) ? "postcondition"
                     : dynamic_cast<const CGAL::Assertion_exception*>(&e)     ? "assertion"
                                                                              : "check";
  std::string text = "CGAL " + std::string(kind) + " violated: " + e.expression() + " (" + e.filename() + ":" +
                     std::to_string(e.line_number()) + ")";
  if (!e.message().empty()) text += ": " + e.message();
  return text;
}

template <class Body>
auto cgal_guarded(const char* function, Body&& body) -> decltype(std::forward<Body>(body)()) {
  try {
    return std::forward<Body>(body)();
  } catch (const CGAL::Failure_exception& e) {
    fail(Status::internal_error, std::string(function) + ": " + describe_cgal_failure(e));
  }
}

}  // namespace detail
CAGEKIT_NAMESPACE_END
