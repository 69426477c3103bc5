// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Error reporting inside the SDK. C++ code throws cagekit::Error; the C shim (sdk/capi)
// catches every exception at the ABI boundary and turns it into a cagekit_status.
#include <stdexcept>
#include <string>

#include "core/namespace.h"

CAGEKIT_NAMESPACE_BEGIN

// Values are identical to the C header's cagekit_status (checked by static_assert in capi).
enum class Status : int {
  success = 0,
  invalid_argument = -1,
  invalid_handle = -2,
  out_of_memory = -3,
  size_insufficient = -4,
  io_error = -5,
  parse_error = -6,
  unsupported_format = -7,
  invalid_mesh = -8,
  limit_exceeded = -9,
  cancelled = -10,
  internal_error = -11,
  version_mismatch = -12,
  quality = -13,  // a result was computed but misses its quality bounds
  unsupported_feature = -14,  // the host's environment lacks a feature the call needs (GL version, ...)
  invalid_operation = -15,    // the call is not allowed in the object's current state (call order)
};

const char* status_name(Status status);

class Error : public std::runtime_error {
 public:
  Error(Status status, const std::string& message) : std::runtime_error(message), status_(status) {}
  Status status() const { return status_; }

 private:
  Status status_;
};

[[noreturn]] void fail(Status status, const std::string& message);

CAGEKIT_NAMESPACE_END
