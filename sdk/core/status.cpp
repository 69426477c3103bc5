// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/status.h"

CAGEKIT_NAMESPACE_BEGIN

const char* status_name(Status status) {
  switch (status) {
    case Status::success: return "success";
    case Status::invalid_argument: return "invalid argument";
    case Status::invalid_handle: return "invalid handle";
    case Status::out_of_memory: return "out of memory";
    case Status::size_insufficient: return "buffer too small";
    case Status::io_error: return "I/O error";
    case Status::parse_error: return "parse error";
    case Status::unsupported_format: return "unsupported format";
    case Status::invalid_mesh: return "invalid mesh";
    case Status::limit_exceeded: return "limit exceeded";
    case Status::cancelled: return "cancelled";
    case Status::internal_error: return "internal error";
    case Status::version_mismatch: return "version mismatch";
    case Status::quality: return "result misses its quality bounds";
    case Status::unsupported_feature: return "unsupported feature";
    case Status::invalid_operation: return "invalid operation";
  }
  return "unknown status";
}

void fail(Status status, const std::string& message) { throw Error(status, message); }

CAGEKIT_NAMESPACE_END
