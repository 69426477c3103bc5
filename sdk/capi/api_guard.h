// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The exception barrier of the C ABI and small helpers shared by every entry point:
// handle checks, versioned-struct reading/writing, two-call buffer sizing.
#include <algorithm>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <new>
#include <string>
#include <type_traits>

#include "capi/handles.h"
#include "core/memory_budget.h"
#include "core/status.h"

namespace cagekit_capi {

// A caller's enum value as an integer, read without loading an enum object: a value outside the
// enumerators' range (such as -1) would be undefined behaviour in C++ (UBSan -fsanitize=enum).
// Take enum parameters by reference and check raw_enum(param) before using them.
template <class E>
int32_t raw_enum(const E& value) {
  static_assert(sizeof(E) == sizeof(int32_t), "C API enums are 32-bit");
  int32_t raw;
  std::memcpy(&raw, &value, sizeof(raw));
  return raw;
}

using cagekit::Error;
using cagekit::Status;
using cagekit::fail;

// Stores `message` as the calling thread's last error of `context` (nullptr: the thread-global
// slot used when no context is known) and returns `status`. Never throws.
cagekit_status record_error(cagekit_context context, cagekit_status status, const char* message) noexcept;

template <class H>
bool is_live(const H* handle) {
  return handle != nullptr && handle->type.load(std::memory_order_relaxed) == H::kType;
}

// Runs `body`; translates any exception into a status recorded on `context`. Never throws.
template <class Body>
cagekit_status guarded(cagekit_context context, Body&& body) noexcept {
  try {
    // The context's memory budget applies to everything this call does on this thread.
    const cagekit::ScopedMemoryBudget budget(context != nullptr && is_live(context) ? context->memory_budget : 0);
    body();
    return CAGEKIT_SUCCESS;
  } catch (const Error& e) {
    return record_error(context, static_cast<cagekit_status>(e.status()), e.what());
  } catch (const std::bad_alloc&) {
    return record_error(context, CAGEKIT_ERROR_OUT_OF_MEMORY, "out of memory");
  } catch (const std::length_error& e) {
    return record_error(context, CAGEKIT_ERROR_OUT_OF_MEMORY, e.what());
  } catch (const std::exception& e) {
    return record_error(context, CAGEKIT_ERROR_INTERNAL, (std::string("internal error: ") + e.what()).c_str());
  } catch (...) {
    return record_error(context, CAGEKIT_ERROR_INTERNAL, "internal error: unknown exception");
  }
}


// The context an object reports errors to (nullptr for a dead or null handle).
template <class H>
cagekit_context context_of(const H* handle) {
  return is_live(handle) ? handle->context : nullptr;
}

template <class H>
H& checked(H* handle, const char* what) {
  if (!is_live(handle)) fail(Status::invalid_handle, std::string(what) + " is not a valid handle");
  return *handle;
}

// A new object's handle, for create_from: a unique_ptr gives up its object, a raw handle passes.
template <class T>
T* release_new(std::unique_ptr<T> object) {
  return object.release();
}
template <class T>
T* release_new(T* handle) {
  return handle;
}

// The shape of every call that makes a new object out of `source` (named `source_name` in
// errors): `out` must not be NULL and is set to NULL first; `make(source's object)` returns the
// new object (a unique_ptr, or a handle made by a make_*_handle helper), which `out` receives
// only when everything else succeeded, so a failing call leaves nothing to release.
template <class Out, class Source, class Make>
cagekit_status create_from(Source* source, const char* source_name, Out** out, Make&& make) noexcept {
  return guarded(context_of(source), [&] {
    require_not_null(out, "out");
    *out = nullptr;
    *out = release_new(make(checked(source, source_name)));
  });
}

template <class H>
void retain_handle(H* handle) {
  if (is_live(handle)) handle->references.fetch_add(1, std::memory_order_relaxed);
}

template <class H>
void release_handle(H* handle) {
  if (is_live(handle) && handle->references.fetch_sub(1, std::memory_order_acq_rel) == 1) delete handle;
}

template <class T>
void require_not_null(const T* pointer, const char* name) {
  if (pointer == nullptr) fail(Status::invalid_argument, std::string(name) + " must not be NULL");
}

// A cagekit_bool32 input field: 0 or 1, anything else is invalid_argument naming
// "cagekit_<struct>.<field>" (`name`).
inline bool bool_from_c(cagekit_bool32 value, const char* name) {
  if (value > CAGEKIT_TRUE)
    fail(Status::invalid_argument, std::string(name) + " must be 0 or 1, not " + std::to_string(value));
  return value == CAGEKIT_TRUE;
}

// Copies a caller's versioned input struct over `defaults`, reading only struct_size bytes.
template <class T>
T read_versioned(const T* in, const T& defaults, const char* name) {
  T value = defaults;
  if (in == nullptr) return value;
  const size_t size = in->struct_size;
  if (size < sizeof(size_t) || size > (1u << 16))
    fail(Status::invalid_argument, std::string(name) + ".struct_size is " + std::to_string(size) +
                                       "; set it to sizeof(" + name + ")");
  std::memcpy(static_cast<void*>(&value), in, std::min(size, sizeof(T)));
  value.struct_size = sizeof(T);
  return value;
}

// Writes a versioned output struct: only the bytes the caller's struct_size covers.
template <class T>
void write_versioned(T* out, const T& value, const char* name) {
  if (out == nullptr) return;
  const size_t caller_size = out->struct_size;
  if (caller_size < sizeof(size_t) || caller_size > (1u << 16))
    fail(Status::invalid_argument, std::string(name) + ".struct_size is " + std::to_string(caller_size) +
                                       "; set it to sizeof(" + name + ")");
  std::memcpy(static_cast<void*>(out), &value, std::min(caller_size, sizeof(T)));
  out->struct_size = caller_size;
}

// One array output of the two-call shape: its parameter name (for messages) and the caller's
// pointer (nullptr: not given).
struct OutArray {
  const char* name;
  const void* data;
};

// Writes the required count of a two-call output into `count_out` (the parameter <x>_count_out,
// which must not be NULL). A function with several capacity/count pairs calls this for every
// pair before its first two_call_check, so that one pair's size_insufficient still leaves every
// count written.
template <class Count>
void write_count(const char* x, std::common_type_t<Count> required, Count* count_out) {
  if (count_out == nullptr) fail(Status::invalid_argument, std::string(x) + "_count_out must not be NULL");
  *count_out = required;
}

// The two-call shape of every array output (cagekit.h, "Buffers"), the one implementation of its
// rules. `x` names the parameters <x>_capacity and <x>_count_out; `arrays` are the arrays the
// count sizes: one, or several sharing the count, each of which may then be NULL to skip it.
// - count_out NULL: invalid_argument; otherwise *count_out = required, also on size_insufficient;
// - capacity 0: returns false (a query: the arrays may be NULL and are not touched);
// - a nonzero capacity with a lone array NULL: invalid_argument;
// - a nonzero capacity below `required`: size_insufficient naming the arrays and both numbers.
// Returns true when the arrays (those not NULL) are to be filled. No string is built unless it
// fails: the deformers call it every frame.
template <class Count>
bool two_call_check(const char* x, std::common_type_t<Count> required, std::common_type_t<Count> capacity,
                    Count* count_out, std::initializer_list<OutArray> arrays) {
  write_count<Count>(x, required, count_out);
  if (capacity == 0) return false;
  if (arrays.size() == 1 && arrays.begin()->data == nullptr)
    fail(Status::invalid_argument, std::string(arrays.begin()->name) + " is NULL but " + x + "_capacity is " +
                                       std::to_string(capacity));
  if (capacity < required) {
    std::string names;
    for (const OutArray& a : arrays) names += (names.empty() ? "" : "/") + std::string(a.name);
    fail(Status::size_insufficient, names + ": " + x + "_capacity " + std::to_string(capacity) +
                                        " is less than the required " + std::to_string(required));
  }
  return true;
}

}  // namespace cagekit_capi
