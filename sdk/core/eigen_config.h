// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Include before any Eigen header: Eigen's internal assertions (active in builds without NDEBUG,
// e.g. a host's Debug build of CageKit) throw Error(internal_error) instead of calling abort(),
// so they end at the C API's exception barrier as CAGEKIT_ERROR_INTERNAL and never take down the
// host process.
#include <string>

#include "core/status.h"

#ifndef eigen_assert
#define eigen_assert(x)                                                                        \
  do {                                                                                         \
    if (!(x)) ::cagekit::fail(::cagekit::Status::internal_error, "Eigen assertion failed: " #x); \
  } while (false)
#endif
