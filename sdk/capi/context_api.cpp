// SPDX-License-Identifier: GPL-3.0-or-later
// Context, versioning, status strings and last-error messages of the C API.
#include <cstdio>

#include "capi/api_guard.h"

using namespace cagekit_capi;

namespace {

thread_local std::string g_contextless_error;  // errors with no (valid) context

}  // namespace

namespace cagekit_capi {

cagekit_status record_error(cagekit_context context, cagekit_status status, const char* message) noexcept {
  try {
    if (is_live(context)) {
      {
        std::lock_guard<std::mutex> lock(context->error_mutex);
        context->last_error[std::this_thread::get_id()] = message;
      }
      context->log_message(CAGEKIT_LOG_ERROR, message);
    } else {
      g_contextless_error = message;
    }
  } catch (...) {
    // Out of memory while storing the message: the status alone still reaches the caller.
  }
  return status;
}

}  // namespace cagekit_capi

cagekit::TaskMonitor cagekit_context_t::monitor() {
  if (cancel_requested.load()) fail(Status::cancelled, "cancelled: cagekit_context_cancel() was called");
  auto progress_fn = [this](const char* stage, double fraction) {
    if (cancel_requested.load(std::memory_order_relaxed)) return false;
    return progress == nullptr || progress(progress_user_data, stage, fraction) != 0;
  };
  auto log_fn = [this](cagekit::LogLevel level, const std::string& message) {
    log_message(static_cast<cagekit_log_level>(level), message);
  };
  return cagekit::TaskMonitor(progress_fn, log_fn);
}

void cagekit_context_t::log_message(cagekit_log_level level, const std::string& message) {
  if (log != nullptr && level >= log_level) log(log_user_data, level, message.c_str());
}

ContextBound::ContextBound(HandleType t, cagekit_context c) : Handle(t), context(c) {
  cagekit_context_retain(c);
}

ContextBound::~ContextBound() { cagekit_context_release(context); }

static_assert(static_cast<int>(Status::success) == CAGEKIT_SUCCESS);
static_assert(static_cast<int>(Status::invalid_argument) == CAGEKIT_ERROR_INVALID_ARGUMENT);
static_assert(static_cast<int>(Status::invalid_handle) == CAGEKIT_ERROR_INVALID_HANDLE);
static_assert(static_cast<int>(Status::out_of_memory) == CAGEKIT_ERROR_OUT_OF_MEMORY);
static_assert(static_cast<int>(Status::size_insufficient) == CAGEKIT_ERROR_SIZE_INSUFFICIENT);
static_assert(static_cast<int>(Status::io_error) == CAGEKIT_ERROR_IO);
static_assert(static_cast<int>(Status::parse_error) == CAGEKIT_ERROR_PARSE);
static_assert(static_cast<int>(Status::unsupported_format) == CAGEKIT_ERROR_UNSUPPORTED_FORMAT);
static_assert(static_cast<int>(Status::invalid_mesh) == CAGEKIT_ERROR_INVALID_MESH);
static_assert(static_cast<int>(Status::limit_exceeded) == CAGEKIT_ERROR_LIMIT_EXCEEDED);
static_assert(static_cast<int>(Status::cancelled) == CAGEKIT_ERROR_CANCELLED);
static_assert(static_cast<int>(Status::internal_error) == CAGEKIT_ERROR_INTERNAL);
static_assert(static_cast<int>(Status::version_mismatch) == CAGEKIT_ERROR_VERSION_MISMATCH);
static_assert(static_cast<int>(Status::quality) == CAGEKIT_ERROR_QUALITY);
static_assert(static_cast<int>(Status::unsupported_feature) == CAGEKIT_ERROR_UNSUPPORTED_FEATURE);
static_assert(static_cast<int>(Status::invalid_operation) == CAGEKIT_ERROR_INVALID_OPERATION);
static_assert(static_cast<int>(cagekit::LogLevel::warning) == CAGEKIT_LOG_WARNING);

extern "C" {

CAGEKIT_API uint32_t cagekit_version(void) { return CAGEKIT_VERSION; }

CAGEKIT_API const char* cagekit_version_string(void) {
#define CAGEKIT_STR2(x) #x
#define CAGEKIT_STR(x) CAGEKIT_STR2(x)
  return CAGEKIT_STR(CAGEKIT_VERSION_MAJOR) "." CAGEKIT_STR(CAGEKIT_VERSION_MINOR) "." CAGEKIT_STR(
      CAGEKIT_VERSION_PATCH);
}

CAGEKIT_API uint32_t cagekit_abi_version(void) { return CAGEKIT_ABI_VERSION; }

CAGEKIT_API const char* cagekit_status_string(cagekit_status status) {
  if (status > 0) return "success";
  if (status < CAGEKIT_ERROR_INVALID_OPERATION) return "unknown status";
  return cagekit::status_name(static_cast<Status>(status));
}

CAGEKIT_API cagekit_status cagekit_context_create(const cagekit_context_desc* desc, cagekit_context* out) {
  return guarded(nullptr, [&] {
    require_not_null(out, "out");
    *out = nullptr;
    cagekit_context_desc defaults = CAGEKIT_CONTEXT_DESC_INIT;
    const cagekit_context_desc d = read_versioned(desc, defaults, "cagekit_context_desc");
    if (d.abi_version != CAGEKIT_ABI_VERSION)
      fail(Status::version_mismatch, "the host was built for CageKit ABI " + std::to_string(d.abi_version) +
                                         " but the loaded libcagekit has ABI " +
                                         std::to_string(CAGEKIT_ABI_VERSION));
    if (raw_enum(d.log_level) < CAGEKIT_LOG_DEBUG || raw_enum(d.log_level) > CAGEKIT_LOG_ERROR)
      fail(Status::invalid_argument, "cagekit_context_desc.log_level is out of range");
    auto context = std::make_unique<cagekit_context_t>();
    context->log = d.log;
    context->log_user_data = d.log_user_data;
    context->log_level = d.log_level;
    context->progress = d.progress;
    context->progress_user_data = d.progress_user_data;
    context->memory_budget = d.memory_budget_bytes;
    *out = context.release();
  });
}

CAGEKIT_API void cagekit_context_retain(cagekit_context context) { retain_handle(context); }
CAGEKIT_API void cagekit_context_release(cagekit_context context) { release_handle(context); }

CAGEKIT_API cagekit_status cagekit_context_set_progress(cagekit_context context, cagekit_progress_fn progress,
                                                        void* user_data) {
  return guarded(context, [&] {
    cagekit_context_t& c = checked(context, "context");
    c.progress = progress;
    c.progress_user_data = user_data;
  });
}

CAGEKIT_API void cagekit_context_cancel(cagekit_context context) {
  if (is_live(context)) context->cancel_requested.store(true);
}

CAGEKIT_API void cagekit_context_reset_cancel(cagekit_context context) {
  if (is_live(context)) context->cancel_requested.store(false);
}

CAGEKIT_API const char* cagekit_last_error_message(cagekit_context context) {
  if (!is_live(context)) return g_contextless_error.c_str();
  std::lock_guard<std::mutex> lock(context->error_mutex);
  auto it = context->last_error.find(std::this_thread::get_id());
  return it == context->last_error.end() ? "" : it->second.c_str();
}

}  // extern "C"
