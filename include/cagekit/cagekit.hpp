// SPDX-License-Identifier: GPL-3.0-or-later
//
// CageKit — a header-only C++17 layer over the C API of <cagekit/cagekit.h>, in the manner of
// Vulkan-Hpp and OpenXR-Hpp: it adds no symbol to libcagekit and no ABI of its own. Everything
// here is inline and calls the C functions; a host that includes it links libcagekit as a C host
// does.
//
// What it adds:
// - RAII handles (cagekit::Context, Mesh, Cage, Surface, Hierarchy, Binding, CpuDeformer,
//   LimitPatches, LimitSurfaces, Blob; GlDeformer in <cagekit/cagekit_gl.hpp>): movable, not copyable; the
//   destructor releases the reference. share() is the explicit copy: it retains the C handle
//   and returns a second owner of the same object. get() is the raw handle for C calls,
//   release() detaches it (the caller then owns that reference), adopt()/borrow() wrap a raw
//   handle (taking over its reference / adding one).
// - Errors as exceptions: a failing C call throws cagekit::Error (a std::runtime_error) with the
//   cagekit_status, the C function's name and the SDK's message (cagekit_last_error_message of
//   the object's context, on the calling thread).
// - cagekit::View<T>: a pointer and an element count over caller memory (std::vector, std::array,
//   C arrays, braced lists for inputs), for array inputs and for outputs written in place.
// - Two-call outputs (count, allocate, fill) wrapped as functions that return std::vector.
// - Options are the C structs; cagekit::defaults<T>() returns one with its CAGEKIT_*_INIT
//   defaults (reports and infos: zeroed with struct_size set). Functions that fill a report set
//   its struct_size themselves.
//
// Example (a scan bound to its fitted cage, deformed on the CPU):
//   cagekit::Context context = cagekit::Context::create();
//   cagekit::Mesh scan = context.create_mesh(positions, triangles);      // xyz triples, 3 per face
//   cagekit::Hierarchy hierarchy = scan.create_hierarchy();
//   hierarchy.set_level(hierarchy.find_level(CAGEKIT_LEVEL_BY_FACES, 60));
//   cagekit::Cage fitted = hierarchy.build_cage().fit(scan).cage;
//   cagekit::CpuDeformer deformer = fitted.bind(scan).create_cpu_deformer();
//   std::vector<double> control = fitted.mesh().positions();            // move these
//   cagekit::Deformed<double> frame = deformer.deform(control);          // frame.positions, .normals
//   // or, every frame, into the host's own arrays:
//   deformer.deform(control, CAGEKIT_NORMALS_APPROXIMATE, host_positions, host_normals);
//
// Threading: a wrapper follows the rules of its C object (cagekit.h: calls documented as reads may
// run concurrently, those that modify need exclusive access). share() and the destructor only
// touch the atomic reference counts.
//
// Contexts, callbacks and lifetimes. A Context made here owns its log and progress callbacks as
// std::function (Context::Options). Every wrapper made from a context keeps those callbacks
// alive (a shared state, with the context's raw handle for error messages), because the C
// library keeps the context alive as long as any object made with it: the callbacks must not
// die first. An object detached with release() no longer keeps them: keep a wrapper of its
// context alive while the raw handle is used. The C library calls the callbacks; no exception
// crosses the C ABI: an exception thrown by a progress callback cancels the operation and is
// rethrown (as thrown) by the C++ call that ran it; one thrown by a log callback is swallowed.
//
// Namespace. `cagekit::` is the namespace of this header: no installed header uses it (the
// installed headers are C). The library's own sources use a `cagekit` namespace internally, with
// classes of the same names (Error, Cage, Context); they are hidden inside libcagekit (not
// exported), so a host sees only these. Code that links the SDK's internal static libraries
// (the repository's unit tests) must not include this header.
#ifndef CAGEKIT_CAGEKIT_HPP
#define CAGEKIT_CAGEKIT_HPP

#include <cagekit/cagekit.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace cagekit {

// ------------------------------------------------------------------------------------------------
// Versions and status names
// ------------------------------------------------------------------------------------------------

// The loaded library's version (CAGEKIT_MAKE_VERSION packing), "MAJOR.MINOR.PATCH" and ABI major.
inline uint32_t version() noexcept { return cagekit_version(); }
inline const char* version_string() noexcept { return cagekit_version_string(); }
inline uint32_t abi_version() noexcept { return cagekit_abi_version(); }
// An English name of a status ("invalid argument").
inline const char* status_string(cagekit_status status) noexcept { return cagekit_status_string(status); }

// ------------------------------------------------------------------------------------------------
// Errors
// ------------------------------------------------------------------------------------------------

// A failed C call: status() is its cagekit_status, function() the C function ("cagekit_mesh_create";
// a string literal), message() the SDK's message (cagekit_last_error_message), what() both:
// "cagekit_mesh_create: <message>". Errors found by this layer before any C call (an array whose
// length is no multiple of 3, a count above 2^32 - 1) carry INVALID_ARGUMENT / LIMIT_EXCEEDED.
class Error : public std::runtime_error {
 public:
  Error(cagekit_status status, const char* function, const std::string& message)
      : std::runtime_error(std::string(function) + ": " + message), status_(status), function_(function),
        message_(message) {}
  cagekit_status status() const noexcept { return status_; }
  const char* function() const noexcept { return function_; }
  // The SDK's message alone (never empty: the status's name when the SDK gave none).
  const char* message() const noexcept { return message_.what(); }

 private:
  cagekit_status status_;
  const char* function_;
  std::runtime_error message_;  // a copy that cannot throw when the Error is copied
};

// ------------------------------------------------------------------------------------------------
// Options, reports and infos
// ------------------------------------------------------------------------------------------------

// A versioned struct ready to pass: options with their CAGEKIT_*_INIT defaults, reports and infos
// zeroed with struct_size = sizeof(T).
template <class T>
inline T defaults() noexcept {
  static_assert(std::is_same<decltype(T::struct_size), size_t>::value, "a versioned CageKit struct");
  T value{};
  value.struct_size = sizeof(T);
  return value;
}

#define CAGEKIT_HPP_DEFAULTS(type, init) \
  template <>                            \
  inline type defaults<type>() noexcept { \
    type value = init;                   \
    return value;                        \
  }
CAGEKIT_HPP_DEFAULTS(cagekit_context_desc, CAGEKIT_CONTEXT_DESC_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_mesh_desc, CAGEKIT_MESH_DESC_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_repair_options, CAGEKIT_REPAIR_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_write_options, CAGEKIT_WRITE_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_subdivide_options, CAGEKIT_SUBDIVIDE_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_surface_options, CAGEKIT_SURFACE_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_simplify_options, CAGEKIT_SIMPLIFY_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_cage_options, CAGEKIT_CAGE_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_anisotropic_options, CAGEKIT_ANISOTROPIC_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_quad_remesh_options, CAGEKIT_QUAD_REMESH_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_fit_options, CAGEKIT_FIT_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_scan_to_cage_options, CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_bind_options, CAGEKIT_BIND_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_limit_patch_options, CAGEKIT_LIMIT_PATCH_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_limit_surface_options, CAGEKIT_LIMIT_SURFACE_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_render_item_options, CAGEKIT_RENDER_ITEM_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_render_scalar_options, CAGEKIT_RENDER_SCALAR_OPTIONS_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_render_camera, CAGEKIT_RENDER_CAMERA_INIT)
CAGEKIT_HPP_DEFAULTS(cagekit_render_options, CAGEKIT_RENDER_OPTIONS_INIT)
#undef CAGEKIT_HPP_DEFAULTS

// ------------------------------------------------------------------------------------------------
// View: caller memory (pointer + element count)
// ------------------------------------------------------------------------------------------------

// A non-owning view of `size()` contiguous elements. View<const T> is an input (made from a
// std::vector, std::array, C array, another view or a braced list), View<T> an output written in
// place. Arrays of points are xyz triples: 3 scalars per point. Views never outlive the call they
// are passed to in this API (nothing keeps caller pointers).
template <class T>
class View {
 public:
  using value_type = typename std::remove_cv<T>::type;

  constexpr View() noexcept = default;
  constexpr View(std::nullptr_t) noexcept {}  // NOLINT: an absent array
  constexpr View(T* data, size_t size) noexcept : data_(data), size_(size) {}
  template <size_t N>
  constexpr View(T (&array)[N]) noexcept : data_(array), size_(N) {}  // NOLINT: implicit by design
  // Any contiguous container with data() and size() whose elements are T (or non-const T for a
  // View<const T>): std::vector, std::array, std::string, View.
  template <class Container,
            class Element = typename std::remove_pointer<decltype(std::declval<Container&>().data())>::type,
            class = typename std::enable_if<std::is_convertible<Element (*)[], T (*)[]>::value &&
                                            !std::is_same<typename std::decay<Container>::type, View>::value>::type>
  constexpr View(Container&& container) noexcept  // NOLINT: implicit by design
      : data_(container.data()), size_(container.size()) {}
  // A braced list, for inputs: valid for the call it is passed to.
  template <class U = T, class = typename std::enable_if<std::is_const<U>::value>::type>
  constexpr View(const std::initializer_list<value_type>& list) noexcept  // NOLINT: implicit by design
      : size_(list.size()) {
    data_ = list.begin();  // the braced list lives until the end of the call it is passed to
  }

  constexpr T* data() const noexcept { return data_; }
  constexpr size_t size() const noexcept { return size_; }
  constexpr bool empty() const noexcept { return size_ == 0; }
  constexpr T* begin() const noexcept { return data_; }
  constexpr T* end() const noexcept { return data_ + size_; }
  constexpr T& operator[](size_t i) const noexcept { return data_[i]; }

 private:
  T* data_ = nullptr;
  size_t size_ = 0;
};

// ------------------------------------------------------------------------------------------------
// Internals shared by the wrappers
// ------------------------------------------------------------------------------------------------

class Context;

namespace detail {

// What every wrapper made from one context shares: the raw context (for error messages; valid
// while the wrapper holds its object, which keeps the context alive) and the C++ callbacks the
// C context points at (they live as long as any wrapper of the context).
struct ContextState {
  cagekit_context context = nullptr;
  std::function<void(cagekit_log_level, const char*)> log;
  std::function<bool(const char*, double)> progress;
};
using ContextRef = std::shared_ptr<ContextState>;

// The exception a C++ callback threw during the C call now running on this thread; the C call
// is cancelled and check() rethrows it.
inline std::exception_ptr& pending_exception() noexcept {
  thread_local std::exception_ptr pending;
  return pending;
}

// The C callbacks the layer installs: they never let an exception out (the C ABI cannot carry one).
inline void log_trampoline(void* user_data, cagekit_log_level level, const char* message) noexcept {
  const auto* state = static_cast<const ContextState*>(user_data);
  try {
    if (state->log) state->log(level, message);
  } catch (...) {
    // A log line is not worth failing the operation for: swallowed (documented above).
  }
}

inline int progress_trampoline(void* user_data, const char* stage, double fraction) noexcept {
  const auto* state = static_cast<const ContextState*>(user_data);
  try {
    return !state->progress || state->progress(stage, fraction) ? 1 : 0;
  } catch (...) {
    pending_exception() = std::current_exception();
    return 0;  // cancels; the C++ caller rethrows the exception
  }
}

[[noreturn]] inline void throw_error(cagekit_status status, cagekit_context context, const char* function) {
  const char* message = cagekit_last_error_message(context);
  throw Error(status, function,
              message != nullptr && message[0] != '\0' ? std::string(message) : std::string(status_string(status)));
}

// Throws for a failed status: the callback's exception when one cancelled the call, else Error.
// A call that succeeded although a callback threw (it had no cancellation point left) returns
// normally: its outputs are valid and owned by the caller, so the exception is dropped.
inline void check(cagekit_status status, const ContextRef& context, const char* function) {
  std::exception_ptr pending = std::move(pending_exception());
  pending_exception() = nullptr;
  if (!CAGEKIT_FAILED(status)) return;
  if (pending) std::rethrow_exception(pending);
  throw_error(status, context ? context->context : nullptr, function);
}

// Element counts of views, as the C API's 32-bit counts.
inline uint32_t count32(size_t count, const char* what, const char* function) {
  if (count > UINT32_MAX)
    throw Error(CAGEKIT_ERROR_LIMIT_EXCEEDED, function,
                std::string(what) + " has " + std::to_string(count) + " elements, more than 2^32 - 1");
  return static_cast<uint32_t>(count);
}

// The number of xyz triples in `values` scalars.
inline uint32_t triples(size_t values, const char* what, const char* function) {
  if (values % 3 != 0)
    throw Error(CAGEKIT_ERROR_INVALID_ARGUMENT, function,
                std::string(what) + " holds " + std::to_string(values) + " values, not xyz triples");
  return count32(values / 3, what, function);
}

// The shared capacity (in points) of two optional xyz output arrays.
inline uint32_t shared_triples(size_t a, size_t b, const char* function) {
  if (a != 0 && b != 0 && a != b)
    throw Error(CAGEKIT_ERROR_INVALID_ARGUMENT, function,
                "positions and normals hold " + std::to_string(a) + " and " + std::to_string(b) +
                    " values: one capacity is shared, give equal sizes");
  return triples(a != 0 ? a : b, "positions / normals", function);
}

template <class T>
T* data_or_null(std::vector<T>& values) noexcept {
  return values.empty() ? nullptr : values.data();
}

// Builds wrappers from raw handles; the wrappers' (handle, context) constructors are private.
struct Access {
  template <class Wrapper>
  static Wrapper wrap(typename Wrapper::handle_type handle, ContextRef context) noexcept {
    return Wrapper(handle, std::move(context));
  }
  template <class Wrapper>
  static const ContextRef& context_of(const Wrapper& wrapper) noexcept {
    return wrapper.context_;
  }
};

// The RAII base of every handle type: one reference of `H`, released by the destructor.
template <class Derived, class H, void (*Retain)(H), void (*Release)(H)>
class Handle {
 public:
  using handle_type = H;

  Handle() noexcept = default;
  ~Handle() { Release(handle_); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : handle_(other.handle_), context_(std::move(other.context_)) {
    other.handle_ = nullptr;
  }
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      Release(handle_);
      handle_ = other.handle_;
      other.handle_ = nullptr;
      context_ = std::move(other.context_);
    }
    return *this;
  }

  // The raw handle (still owned by this wrapper), for C calls.
  H get() const noexcept { return handle_; }
  explicit operator bool() const noexcept { return handle_ != nullptr; }
  // Detaches the raw handle: the caller owns its reference (release it with the C *_release).
  H release() noexcept {
    H handle = handle_;
    handle_ = nullptr;
    context_.reset();
    return handle;
  }
  // Drops the reference now (the wrapper becomes empty).
  void reset() noexcept {
    Release(handle_);
    handle_ = nullptr;
    context_.reset();
  }
  // The explicit copy: retains the C handle and returns a second owner of the same object.
  Derived share() const noexcept {
    Retain(handle_);
    return Access::wrap<Derived>(handle_, context_);
  }
  // Wraps a raw handle made with `context`: adopt takes over the caller's reference, borrow adds
  // one (the caller keeps its own). `context` gives the error messages and keeps its callbacks.
  static Derived adopt(H handle, const Context& context) noexcept;
  static Derived borrow(H handle, const Context& context) noexcept {
    Retain(handle);
    return adopt(handle, context);
  }

 protected:
  friend struct Access;
  Handle(H handle, ContextRef context) noexcept : handle_(handle), context_(std::move(context)) {}
  void check(cagekit_status status, const char* function) const { detail::check(status, context_, function); }
  template <class Wrapper>
  Wrapper wrap(typename Wrapper::handle_type handle) const noexcept {
    return Access::wrap<Wrapper>(handle, context_);
  }

  H handle_ = nullptr;
  ContextRef context_;
};

}  // namespace detail

#define CAGEKIT_HPP_HANDLE(Name, H, retain, release)                  \
 public:                                                              \
  Name() noexcept = default;                                          \
                                                                      \
 private:                                                             \
  friend struct detail::Access;                                       \
  friend class detail::Handle<Name, H, retain, release>;              \
  Name(H handle, detail::ContextRef context) noexcept                 \
      : detail::Handle<Name, H, retain, release>(handle, std::move(context)) {} \
                                                                      \
 public:

class Mesh;
class Cage;
class Surface;
class Hierarchy;
class Binding;
class CpuDeformer;
class LimitPatches;
class LimitSurfaces;
class Blob;
class RenderScene;

// Faces of a polygon mesh: face_sizes[f] vertex indices per face, one face after another.
struct Faces {
  std::vector<uint32_t> face_sizes;
  std::vector<uint32_t> face_indices;
};

// ------------------------------------------------------------------------------------------------
// Blob: library-owned bytes
// ------------------------------------------------------------------------------------------------

class Blob : public detail::Handle<Blob, cagekit_blob, cagekit_blob_retain, cagekit_blob_release> {
  CAGEKIT_HPP_HANDLE(Blob, cagekit_blob, cagekit_blob_retain, cagekit_blob_release)
  const void* data() const noexcept { return cagekit_blob_data(handle_); }
  size_t size() const noexcept { return cagekit_blob_size(handle_); }
  View<const unsigned char> bytes() const noexcept {
    return View<const unsigned char>(static_cast<const unsigned char*>(data()), size());
  }
};

// ------------------------------------------------------------------------------------------------
// Context
// ------------------------------------------------------------------------------------------------

// The C++ form of cagekit_context_desc: callbacks as std::function (they may throw: see the top).
struct ContextOptions {
  std::function<void(cagekit_log_level, const char*)> log;
  cagekit_log_level log_level = CAGEKIT_LOG_WARNING;
  // Returns false to cancel the operation.
  std::function<bool(const char* stage, double fraction)> progress;
  uint64_t memory_budget_bytes = 0;  // 0: unlimited
};

class Context : public detail::Handle<Context, cagekit_context, cagekit_context_retain, cagekit_context_release> {
  CAGEKIT_HPP_HANDLE(Context, cagekit_context, cagekit_context_retain, cagekit_context_release)

  using Options = ContextOptions;

  // A context with C++ callbacks (none by default).
  static Context create(Options options = Options()) {
    detail::ContextRef state = std::make_shared<detail::ContextState>();
    state->log = std::move(options.log);
    state->progress = std::move(options.progress);
    cagekit_context_desc desc = defaults<cagekit_context_desc>();
    desc.log = state->log ? detail::log_trampoline : nullptr;
    desc.log_user_data = state.get();
    desc.log_level = options.log_level;
    desc.progress = state->progress ? detail::progress_trampoline : nullptr;
    desc.progress_user_data = state.get();
    desc.memory_budget_bytes = options.memory_budget_bytes;
    return create_with(desc, std::move(state));
  }
  // A context from the C description (C callbacks, which must not throw; abi_version as given).
  static Context create(const cagekit_context_desc& desc) {
    return create_with(desc, std::make_shared<detail::ContextState>());
  }
  // Wraps a raw context: adopt takes over the caller's reference, borrow adds one.
  static Context adopt(cagekit_context handle) {
    detail::ContextRef state = std::make_shared<detail::ContextState>();
    state->context = handle;
    return Context(handle, std::move(state));
  }
  static Context borrow(cagekit_context handle) {
    cagekit_context_retain(handle);
    return adopt(handle);
  }

  // Replaces the progress callback (empty: none). Modifies the context (no call may run with it).
  void set_progress(std::function<bool(const char* stage, double fraction)> progress) {
    require_handle("cagekit_context_set_progress");
    const bool installed = static_cast<bool>(progress);
    std::function<bool(const char*, double)> previous = std::move(context_->progress);
    context_->progress = std::move(progress);
    try {
      check(cagekit_context_set_progress(handle_, installed ? detail::progress_trampoline : nullptr,
                                         installed ? context_.get() : nullptr),
            "cagekit_context_set_progress");
    } catch (...) {
      context_->progress = std::move(previous);
      throw;
    }
  }
  // Installs a C progress callback (which must not throw) in place of any C++ one.
  void set_progress(cagekit_progress_fn progress, void* user_data) {
    require_handle("cagekit_context_set_progress");
    check(cagekit_context_set_progress(handle_, progress, user_data), "cagekit_context_set_progress");
    context_->progress = nullptr;
  }
  // Cancels the running and later long operations (any thread), until reset_cancel().
  void cancel() const noexcept { cagekit_context_cancel(handle_); }
  void reset_cancel() const noexcept { cagekit_context_reset_cancel(handle_); }
  // The last failure's message on this thread (Error carries it already).
  std::string last_error_message() const { return cagekit_last_error_message(handle_); }

  // --- objects made with the context ---

  // A mesh copied from caller buffers (cagekit_mesh_create; not validated).
  Mesh create_mesh(const cagekit_mesh_desc& desc) const;
  // Positions as xyz triples; faces of `face_size` vertices each (3: triangles).
  Mesh create_mesh(View<const double> positions, View<const uint32_t> face_indices, uint32_t face_size = 3) const;
  // Polygons of mixed sizes.
  Mesh create_mesh(View<const double> positions, View<const uint32_t> face_sizes,
                   View<const uint32_t> face_indices) const;
  Mesh read_mesh(const std::string& path, cagekit_file_format format = CAGEKIT_FORMAT_AUTO) const;
  Mesh read_mesh(const void* data, size_t size, cagekit_file_format format = CAGEKIT_FORMAT_AUTO) const;
  Cage read_cage(const std::string& path, cagekit_file_format format = CAGEKIT_FORMAT_AUTO) const;
  Cage read_cage(const void* data, size_t size, cagekit_file_format format = CAGEKIT_FORMAT_AUTO) const;
  // A saved binding (.ckb); threads 0 = all cores.
  Binding read_binding(const std::string& path, uint32_t threads = 0) const;
  Binding read_binding(const void* data, size_t size, uint32_t threads = 0) const;
  // An empty render scene (cagekit.h, "Rendering").
  RenderScene create_render_scene() const;
  // Encodes a caller's RGBA8 image (rows top first) as a PNG file, or as PNG bytes.
  void write_png(const std::string& path, View<const uint8_t> rgba, uint32_t width, uint32_t height) const;
  Blob encode_png(View<const uint8_t> rgba, uint32_t width, uint32_t height) const;

 private:
  void require_handle(const char* function) const {
    if (!context_) throw Error(CAGEKIT_ERROR_INVALID_HANDLE, function, "the cagekit::Context is empty");
  }
  static Context create_with(const cagekit_context_desc& desc, detail::ContextRef state) {
    cagekit_context handle = nullptr;
    // A failed create reports on the thread's context-less slot: check with no context.
    detail::check(cagekit_context_create(&desc, &handle), nullptr, "cagekit_context_create");
    state->context = handle;
    return Context(handle, std::move(state));
  }
};

template <class Derived, class H, void (*Retain)(H), void (*Release)(H)>
inline Derived detail::Handle<Derived, H, Retain, Release>::adopt(H handle, const Context& context) noexcept {
  return Access::wrap<Derived>(handle, Access::context_of(context));
}

// ------------------------------------------------------------------------------------------------
// Mesh
// ------------------------------------------------------------------------------------------------

struct MeshCounts {
  uint32_t vertices = 0;
  uint32_t faces = 0;
  uint64_t face_indices = 0;
};

class Mesh : public detail::Handle<Mesh, cagekit_mesh, cagekit_mesh_retain, cagekit_mesh_release> {
  CAGEKIT_HPP_HANDLE(Mesh, cagekit_mesh, cagekit_mesh_retain, cagekit_mesh_release)

  MeshCounts counts() const {
    MeshCounts c;
    check(cagekit_mesh_get_counts(handle_, &c.vertices, &c.faces, &c.face_indices), "cagekit_mesh_get_counts");
    return c;
  }
  // xyz triples (3 * vertex count values).
  std::vector<double> positions() const { return positions_as<double>(CAGEKIT_SCALAR_FLOAT64); }
  std::vector<float> positions_f32() const { return positions_as<float>(CAGEKIT_SCALAR_FLOAT32); }
  // Into caller memory (3 values per vertex); returns the vertex count.
  uint32_t positions(View<double> out) const { return positions_into(CAGEKIT_SCALAR_FLOAT64, out.data(), out.size()); }
  uint32_t positions(View<float> out) const { return positions_into(CAGEKIT_SCALAR_FLOAT32, out.data(), out.size()); }
  Faces faces() const {
    Faces f;
    uint32_t face_count = 0;
    uint64_t index_count = 0;
    check(cagekit_mesh_get_faces(handle_, 0, &face_count, nullptr, 0, &index_count, nullptr), "cagekit_mesh_get_faces");
    f.face_sizes.resize(face_count);
    f.face_indices.resize(static_cast<size_t>(index_count));
    check(cagekit_mesh_get_faces(handle_, face_count, &face_count, detail::data_or_null(f.face_sizes), index_count,
                                 &index_count, detail::data_or_null(f.face_indices)),
          "cagekit_mesh_get_faces");
    return f;
  }

  // The validation report; an invalid mesh is no error here (report.valid == 0).
  cagekit_validation_report validate() const {
    cagekit_validation_report report = defaults<cagekit_validation_report>();
    const cagekit_status status = cagekit_mesh_validate(handle_, &report);
    if (status != CAGEKIT_ERROR_INVALID_MESH) check(status, "cagekit_mesh_validate");
    return report;
  }
  // Throws Error(CAGEKIT_ERROR_INVALID_MESH) naming each kind of problem when the mesh is invalid.
  void require_valid() const { check(cagekit_mesh_validate(handle_, nullptr), "cagekit_mesh_validate"); }
  // A repaired copy; `report` (may be null) receives what was done.
  Mesh repair(const cagekit_repair_options& options = defaults<cagekit_repair_options>(),
              cagekit_repair_report* report = nullptr) const;
  cagekit_mesh_info info() const {
    cagekit_mesh_info info = defaults<cagekit_mesh_info>();
    check(cagekit_mesh_get_info(handle_, &info), "cagekit_mesh_get_info");
    return info;
  }

  cagekit_write_report write_file(const std::string& path,
                                  const cagekit_write_options& options = defaults<cagekit_write_options>()) const {
    cagekit_write_report report = defaults<cagekit_write_report>();
    check(cagekit_mesh_write_file(handle_, path.c_str(), &options, &report), "cagekit_mesh_write_file");
    return report;
  }
  // Encoded in memory: options.format must name a format.
  Blob write_memory(const cagekit_write_options& options, cagekit_write_report* report = nullptr) const {
    cagekit_blob blob = nullptr;
    if (report != nullptr) report->struct_size = sizeof(*report);
    check(cagekit_mesh_write_memory(handle_, &options, &blob, report), "cagekit_mesh_write_memory");
    return wrap<Blob>(blob);
  }

  // A cage whose control mesh is this (valid) mesh, without tags.
  Cage create_cage() const;
  // The simplification hierarchy (thesis ch. 3).
  Hierarchy create_hierarchy(const cagekit_simplify_options& options = defaults<cagekit_simplify_options>()) const;
  // Distances of `approximation` to this mesh, relative to its bounding-box diagonal.
  cagekit_approximation_error measure_error(const Mesh& approximation) const {
    cagekit_approximation_error error = defaults<cagekit_approximation_error>();
    check(cagekit_mesh_measure_error(handle_, approximation.get(), &error), "cagekit_mesh_measure_error");
    return error;
  }
  Cage remesh_anisotropic(const cagekit_anisotropic_options& options = defaults<cagekit_anisotropic_options>(),
                          cagekit_anisotropic_report* report = nullptr) const;
  Cage remesh_quad(const cagekit_quad_remesh_options& options = defaults<cagekit_quad_remesh_options>(),
                   cagekit_quad_remesh_report* report = nullptr) const;

 private:
  template <class T>
  std::vector<T> positions_as(cagekit_scalar_type type) const {
    uint32_t count = 0;
    check(cagekit_mesh_get_positions(handle_, type, 0, &count, nullptr), "cagekit_mesh_get_positions");
    std::vector<T> values(3 * static_cast<size_t>(count));
    if (count != 0)
      check(cagekit_mesh_get_positions(handle_, type, count, &count, values.data()), "cagekit_mesh_get_positions");
    return values;
  }
  uint32_t positions_into(cagekit_scalar_type type, void* data, size_t values) const {
    uint32_t count = 0;
    check(cagekit_mesh_get_positions(handle_, type, detail::triples(values, "positions", "cagekit_mesh_get_positions"),
                                     &count, data),
          "cagekit_mesh_get_positions");
    return count;
  }
};

// ------------------------------------------------------------------------------------------------
// Cage
// ------------------------------------------------------------------------------------------------

// Crease tags: edge k joins vertex_pairs[2k] and vertex_pairs[2k + 1] with sharpness[k].
struct Creases {
  std::vector<uint32_t> vertex_pairs;
  std::vector<float> sharpness;
};
// Corner tags: vertices[k] with sharpness[k].
struct Corners {
  std::vector<uint32_t> vertices;
  std::vector<float> sharpness;
};
// Limit positions and unit normals of the control vertices (xyz triples).
struct LimitPoints {
  std::vector<double> positions;
  std::vector<double> normals;
};
class Cage : public detail::Handle<Cage, cagekit_cage, cagekit_cage_retain, cagekit_cage_release> {
  CAGEKIT_HPP_HANDLE(Cage, cagekit_cage, cagekit_cage_retain, cagekit_cage_release)

  struct Fit;         // cagekit_cage_fit's outputs (below)
  struct ScanToCage;  // cagekit_scan_to_cage's outputs (below)

  // A copy of the control mesh.
  Mesh mesh() const {
    cagekit_mesh out = nullptr;
    check(cagekit_cage_get_mesh(handle_, &out), "cagekit_cage_get_mesh");
    return wrap<Mesh>(out);
  }
  // Replaces the tags. An empty sharpness view means CAGEKIT_SHARP for all.
  void set_creases(View<const uint32_t> vertex_pairs, View<const float> sharpness = nullptr) {
    const char* fn = "cagekit_cage_set_creases";
    if (vertex_pairs.size() % 2 != 0)
      throw Error(CAGEKIT_ERROR_INVALID_ARGUMENT, fn, "vertex_pairs holds an odd number of indices");
    const uint32_t count = detail::count32(vertex_pairs.size() / 2, "vertex_pairs", fn);
    check_tag_sharpness(sharpness, count, fn);
    check(cagekit_cage_set_creases(handle_, count, vertex_pairs.data(), sharpness.empty() ? nullptr : sharpness.data()),
          fn);
  }
  Creases creases() const {
    Creases c;
    uint32_t count = 0;
    check(cagekit_cage_get_creases(handle_, 0, &count, nullptr, nullptr), "cagekit_cage_get_creases");
    c.vertex_pairs.resize(2 * static_cast<size_t>(count));
    c.sharpness.resize(count);
    if (count != 0)
      check(cagekit_cage_get_creases(handle_, count, &count, c.vertex_pairs.data(), c.sharpness.data()),
            "cagekit_cage_get_creases");
    return c;
  }
  void set_corners(View<const uint32_t> vertices, View<const float> sharpness = nullptr) {
    const char* fn = "cagekit_cage_set_corners";
    const uint32_t count = detail::count32(vertices.size(), "vertices", fn);
    check_tag_sharpness(sharpness, count, fn);
    check(cagekit_cage_set_corners(handle_, count, vertices.data(), sharpness.empty() ? nullptr : sharpness.data()),
          fn);
  }
  Corners corners() const {
    Corners c;
    uint32_t count = 0;
    check(cagekit_cage_get_corners(handle_, 0, &count, nullptr, nullptr), "cagekit_cage_get_corners");
    c.vertices.resize(count);
    c.sharpness.resize(count);
    if (count != 0)
      check(cagekit_cage_get_corners(handle_, count, &count, c.vertices.data(), c.sharpness.data()),
            "cagekit_cage_get_corners");
    return c;
  }
  void set_holes(View<const uint32_t> faces) {
    check(cagekit_cage_set_holes(handle_, detail::count32(faces.size(), "faces", "cagekit_cage_set_holes"),
                                 faces.data()),
          "cagekit_cage_set_holes");
  }
  std::vector<uint32_t> holes() const {
    uint32_t count = 0;
    check(cagekit_cage_get_holes(handle_, 0, &count, nullptr), "cagekit_cage_get_holes");
    std::vector<uint32_t> faces(count);
    if (count != 0) check(cagekit_cage_get_holes(handle_, count, &count, faces.data()), "cagekit_cage_get_holes");
    return faces;
  }
  void set_boundary_rule(cagekit_boundary_rule rule) {
    check(cagekit_cage_set_boundary_rule(handle_, rule), "cagekit_cage_set_boundary_rule");
  }
  cagekit_boundary_rule boundary_rule() const {
    cagekit_boundary_rule rule = CAGEKIT_BOUNDARY_EDGES_ONLY;
    check(cagekit_cage_get_boundary_rule(handle_, &rule), "cagekit_cage_get_boundary_rule");
    return rule;
  }
  cagekit_mesh_info info() const {
    cagekit_mesh_info info = defaults<cagekit_mesh_info>();
    check(cagekit_cage_get_info(handle_, &info), "cagekit_cage_get_info");
    return info;
  }

  cagekit_write_report write_file(const std::string& path,
                                  const cagekit_write_options& options = defaults<cagekit_write_options>()) const {
    cagekit_write_report report = defaults<cagekit_write_report>();
    check(cagekit_cage_write_file(handle_, path.c_str(), &options, &report), "cagekit_cage_write_file");
    return report;
  }
  Blob write_memory(const cagekit_write_options& options, cagekit_write_report* report = nullptr) const {
    cagekit_blob blob = nullptr;
    if (report != nullptr) report->struct_size = sizeof(*report);
    check(cagekit_cage_write_memory(handle_, &options, &blob, report), "cagekit_cage_write_memory");
    return wrap<Blob>(blob);
  }

  // Catmull-Clark subdivision into a new cage.
  Cage subdivide(const cagekit_subdivide_options& options = defaults<cagekit_subdivide_options>()) const {
    cagekit_cage out = nullptr;
    check(cagekit_cage_subdivide(handle_, &options, &out), "cagekit_cage_subdivide");
    return wrap<Cage>(out);
  }
  LimitPoints limit_points() const {
    LimitPoints p;
    uint32_t count = 0;
    check(cagekit_cage_get_limit_points(handle_, 0, &count, nullptr, nullptr), "cagekit_cage_get_limit_points");
    p.positions.resize(3 * static_cast<size_t>(count));
    p.normals.resize(3 * static_cast<size_t>(count));
    if (count != 0)
      check(cagekit_cage_get_limit_points(handle_, count, &count, p.positions.data(), p.normals.data()),
            "cagekit_cage_get_limit_points");
    return p;
  }
  // Into caller memory (either view may be empty); returns the vertex count.
  uint32_t limit_points(View<double> positions, View<double> normals) const {
    const char* fn = "cagekit_cage_get_limit_points";
    uint32_t count = 0;
    check(cagekit_cage_get_limit_points(handle_, detail::shared_triples(positions.size(), normals.size(), fn), &count,
                                        positions.data(), normals.data()),
          fn);
    return count;
  }
  Surface create_surface(const cagekit_surface_options& options = defaults<cagekit_surface_options>()) const;
  LimitPatches create_limit_patches(
      const cagekit_limit_patch_options& options = defaults<cagekit_limit_patch_options>()) const;
  LimitSurfaces create_limit_surfaces(
      const cagekit_limit_surface_options& options = defaults<cagekit_limit_surface_options>()) const;

  // Fits the limit surface to `scan` (cagekit_cage_fit); this cage is unchanged.
  Fit fit(const Mesh& scan, const cagekit_fit_options& options = defaults<cagekit_fit_options>()) const;
  // Binds `scan` to the limit surface (cagekit_multires_bind).
  Binding bind(const Mesh& scan, const cagekit_bind_options& options = defaults<cagekit_bind_options>()) const;

 private:
  static void check_tag_sharpness(View<const float> sharpness, uint32_t count, const char* fn) {
    if (!sharpness.empty() && sharpness.size() != count)
      throw Error(CAGEKIT_ERROR_INVALID_ARGUMENT, fn,
                  "sharpness holds " + std::to_string(sharpness.size()) + " values for " + std::to_string(count) +
                      " tags");
  }
};

// cagekit_cage_fit's outputs.
struct Cage::Fit {
  Cage cage;
  cagekit_fit_report report = defaults<cagekit_fit_report>();
  std::vector<cagekit_fit_pass> passes;  // entry 0 the initial cage; report.best_pass is returned
};

// cagekit_scan_to_cage's outputs.
struct Cage::ScanToCage {
  Cage cage;
  Cage limit;  // the fitted cage refined onto its limit (empty when not asked for)
  cagekit_scan_to_cage_report report = defaults<cagekit_scan_to_cage_report>();
  cagekit_fit_report fit_report = defaults<cagekit_fit_report>();
  std::vector<cagekit_fit_pass> fit_passes;
};

// The whole journey from a scan to a fitted cage (cagekit_scan_to_cage). `with_limit`: also
// return the refined limit mesh.
inline Cage::ScanToCage scan_to_cage(const Mesh& scan,
                                     const cagekit_scan_to_cage_options& options =
                                         defaults<cagekit_scan_to_cage_options>(),
                                     bool with_limit = true) {
  Cage::ScanToCage result;
  // max_passes + 1 entries always suffice (no second run of the journey).
  const uint32_t capacity = (options.fit != nullptr ? options.fit->max_passes : defaults<cagekit_fit_options>().max_passes) + 1;
  result.fit_passes.resize(capacity);
  cagekit_cage cage = nullptr, limit = nullptr;
  uint32_t count = 0;
  const detail::ContextRef& context = detail::Access::context_of(scan);
  detail::check(cagekit_scan_to_cage(scan.get(), &options, &cage, with_limit ? &limit : nullptr, &result.report,
                                     &result.fit_report, capacity, &count, result.fit_passes.data()),
                context, "cagekit_scan_to_cage");
  result.cage = detail::Access::wrap<Cage>(cage, context);
  result.limit = detail::Access::wrap<Cage>(limit, context);
  result.fit_passes.resize(count);
  return result;
}

// ------------------------------------------------------------------------------------------------
// Surface: limit-surface evaluation
// ------------------------------------------------------------------------------------------------

// The basis functions non-zero at a location: position = sum_k w[k] * control[indices[k]], ...
struct Basis {
  std::vector<uint32_t> indices;
  std::vector<double> w, wu, wv, wuu, wuv, wvv;
};

class Surface : public detail::Handle<Surface, cagekit_surface, cagekit_surface_retain, cagekit_surface_release> {
  CAGEKIT_HPP_HANDLE(Surface, cagekit_surface, cagekit_surface_retain, cagekit_surface_release)

  uint32_t ptex_face_count() const {
    uint32_t count = 0;
    check(cagekit_surface_get_counts(handle_, &count, nullptr), "cagekit_surface_get_counts");
    return count;
  }
  uint32_t control_vertex_count() const {
    uint32_t count = 0;
    check(cagekit_surface_get_counts(handle_, nullptr, &count), "cagekit_surface_get_counts");
    return count;
  }
  uint32_t ptex_face(uint32_t cage_face, uint32_t corner = 0) const {
    uint32_t face = 0;
    check(cagekit_surface_get_ptex_face(handle_, cage_face, corner, &face), "cagekit_surface_get_ptex_face");
    return face;
  }
  // One point per location; `control`: empty for the cage's positions, else xyz per control vertex.
  std::vector<cagekit_surface_point> evaluate(View<const cagekit_surface_location> locations,
                                              View<const double> control = nullptr) const {
    std::vector<cagekit_surface_point> points(locations.size());
    evaluate(locations, points, control);
    return points;
  }
  void evaluate(View<const cagekit_surface_location> locations, View<cagekit_surface_point> points,
                View<const double> control = nullptr) const {
    const char* fn = "cagekit_surface_evaluate";
    if (points.size() != locations.size())
      throw Error(CAGEKIT_ERROR_INVALID_ARGUMENT, fn, "points and locations differ in length");
    // The C call takes the control points without a count: check it here.
    if (!control.empty() && control.size() != 3 * static_cast<size_t>(control_vertex_count()))
      throw Error(CAGEKIT_ERROR_INVALID_ARGUMENT, fn,
                  "control holds " + std::to_string(control.size()) + " values, not xyz for each of the " +
                      std::to_string(control_vertex_count()) + " control vertices");
    check(cagekit_surface_evaluate(handle_, control.empty() ? nullptr : control.data(),
                                   detail::count32(locations.size(), "locations", fn), locations.data(), points.data()),
          fn);
  }
  Basis evaluate_basis(const cagekit_surface_location& location) const {
    const char* fn = "cagekit_surface_evaluate_basis";
    Basis b;
    uint32_t count = 0;
    check(cagekit_surface_evaluate_basis(handle_, &location, 0, &count, nullptr, nullptr, nullptr, nullptr, nullptr,
                                         nullptr, nullptr),
          fn);
    for (std::vector<double>* v : {&b.w, &b.wu, &b.wv, &b.wuu, &b.wuv, &b.wvv}) v->resize(count);
    b.indices.resize(count);
    if (count != 0)
      check(cagekit_surface_evaluate_basis(handle_, &location, count, &count, b.indices.data(), b.w.data(),
                                           b.wu.data(), b.wv.data(), b.wuu.data(), b.wuv.data(), b.wvv.data()),
            fn);
    return b;
  }
};

// ------------------------------------------------------------------------------------------------
// Limit patches: the limit surface as bicubic Bezier patches
// ------------------------------------------------------------------------------------------------

class LimitPatches
    : public detail::Handle<LimitPatches, cagekit_limit_patches, cagekit_limit_patches_retain,
                            cagekit_limit_patches_release> {
  CAGEKIT_HPP_HANDLE(LimitPatches, cagekit_limit_patches, cagekit_limit_patches_retain, cagekit_limit_patches_release)

  cagekit_limit_patch_info info() const {
    cagekit_limit_patch_info info = defaults<cagekit_limit_patch_info>();
    check(cagekit_limit_patches_get_info(handle_, &info), "cagekit_limit_patches_get_info");
    return info;
  }
  std::vector<cagekit_limit_patch> patches() const {
    uint32_t count = 0;
    check(cagekit_limit_patches_get(handle_, 0, &count, nullptr), "cagekit_limit_patches_get");
    std::vector<cagekit_limit_patch> patches(count);
    if (count != 0)
      check(cagekit_limit_patches_get(handle_, count, &count, patches.data()), "cagekit_limit_patches_get");
    return patches;
  }
};

// ------------------------------------------------------------------------------------------------
// Limit surfaces: the limit surface as one B-spline surface per ptex face
// ------------------------------------------------------------------------------------------------

class LimitSurfaces
    : public detail::Handle<LimitSurfaces, cagekit_limit_surfaces, cagekit_limit_surfaces_retain,
                            cagekit_limit_surfaces_release> {
  CAGEKIT_HPP_HANDLE(LimitSurfaces, cagekit_limit_surfaces, cagekit_limit_surfaces_retain,
                     cagekit_limit_surfaces_release)

  cagekit_limit_surface_info info() const {
    cagekit_limit_surface_info info = defaults<cagekit_limit_surface_info>();
    check(cagekit_limit_surfaces_get_info(handle_, &info), "cagekit_limit_surfaces_get_info");
    return info;
  }
  // Surface `index` without its knots and control points (0 .. info().surface_count - 1).
  cagekit_limit_surface surface(uint32_t index) const {
    cagekit_limit_surface surface{};
    check(cagekit_limit_surfaces_get_surface(handle_, index, &surface), "cagekit_limit_surfaces_get_surface");
    return surface;
  }
  // The knot vector of surface `index` in `direction` (clamped, with the repeated end knots).
  std::vector<double> knots(uint32_t index, cagekit_surface_direction direction) const {
    const char* fn = "cagekit_limit_surfaces_get_knots";
    uint32_t count = 0;
    check(cagekit_limit_surfaces_get_knots(handle_, index, direction, 0, &count, nullptr), fn);
    std::vector<double> knots(count);
    if (count != 0) check(cagekit_limit_surfaces_get_knots(handle_, index, direction, count, &count, knots.data()), fn);
    return knots;
  }
  // The control points of surface `index` as xyz triples, row-major with u inner.
  std::vector<double> control_points(uint32_t index) const {
    const char* fn = "cagekit_limit_surfaces_get_control_points";
    uint32_t count = 0;
    check(cagekit_limit_surfaces_get_control_points(handle_, index, 0, &count, nullptr), fn);
    std::vector<double> points(3 * static_cast<size_t>(count));
    if (count != 0) check(cagekit_limit_surfaces_get_control_points(handle_, index, count, &count, points.data()), fn);
    return points;
  }
  // The neighbours of surface `index` across its side `side` (0..3).
  std::vector<cagekit_limit_surface_neighbour> neighbours(uint32_t index, uint32_t side) const {
    const char* fn = "cagekit_limit_surfaces_get_neighbours";
    uint32_t count = 0;
    check(cagekit_limit_surfaces_get_neighbours(handle_, index, side, 0, &count, nullptr), fn);
    std::vector<cagekit_limit_surface_neighbour> out(count);
    if (count != 0) check(cagekit_limit_surfaces_get_neighbours(handle_, index, side, count, &count, out.data()), fn);
    return out;
  }
};

// ------------------------------------------------------------------------------------------------
// Hierarchy: structure-preserving simplification
// ------------------------------------------------------------------------------------------------

// The current level's faces: loops_per_face[f] loops per face (outer first, then holes), each
// loop loop_sizes[l] input vertex indices in loop_vertices.
struct LevelFaces {
  std::vector<uint32_t> loops_per_face;
  std::vector<uint32_t> loop_sizes;
  std::vector<uint32_t> loop_vertices;
};

class Hierarchy
    : public detail::Handle<Hierarchy, cagekit_hierarchy, cagekit_hierarchy_retain, cagekit_hierarchy_release> {
  CAGEKIT_HPP_HANDLE(Hierarchy, cagekit_hierarchy, cagekit_hierarchy_retain, cagekit_hierarchy_release)

  uint32_t level_count() const {
    uint32_t count = 0;
    check(cagekit_hierarchy_get_level_count(handle_, &count), "cagekit_hierarchy_get_level_count");
    return count;
  }
  cagekit_level_info level_info(uint32_t level) const {
    cagekit_level_info info = defaults<cagekit_level_info>();
    check(cagekit_hierarchy_get_level_info(handle_, level, &info), "cagekit_hierarchy_get_level_info");
    return info;
  }
  uint32_t find_level(cagekit_level_query query, double value) const {
    uint32_t level = 0;
    check(cagekit_hierarchy_find_level(handle_, query, value, &level), "cagekit_hierarchy_find_level");
    return level;
  }
  void set_level(uint32_t level) { check(cagekit_hierarchy_set_level(handle_, level), "cagekit_hierarchy_set_level"); }
  uint32_t current_level() const {
    uint32_t level = 0;
    check(cagekit_hierarchy_get_current_level(handle_, &level), "cagekit_hierarchy_get_current_level");
    return level;
  }
  cagekit_polygonal_level_info current_info() const {
    cagekit_polygonal_level_info info = defaults<cagekit_polygonal_level_info>();
    check(cagekit_hierarchy_get_current_info(handle_, &info), "cagekit_hierarchy_get_current_info");
    return info;
  }
  LevelFaces faces() const {
    const char* fn = "cagekit_hierarchy_get_faces";
    LevelFaces f;
    uint32_t faces = 0, loops = 0;
    uint64_t indices = 0;
    check(cagekit_hierarchy_get_faces(handle_, 0, &faces, nullptr, 0, &loops, nullptr, 0, &indices, nullptr), fn);
    f.loops_per_face.resize(faces);
    f.loop_sizes.resize(loops);
    f.loop_vertices.resize(static_cast<size_t>(indices));
    check(cagekit_hierarchy_get_faces(handle_, faces, &faces, detail::data_or_null(f.loops_per_face), loops, &loops,
                                      detail::data_or_null(f.loop_sizes), indices, &indices,
                                      detail::data_or_null(f.loop_vertices)),
          fn);
    return f;
  }
  // Per input face, the current level's face containing it.
  std::vector<uint32_t> clusters() const {
    uint32_t count = 0;
    check(cagekit_hierarchy_get_clusters(handle_, 0, &count, nullptr), "cagekit_hierarchy_get_clusters");
    std::vector<uint32_t> clusters(count);
    if (count != 0)
      check(cagekit_hierarchy_get_clusters(handle_, count, &count, clusters.data()), "cagekit_hierarchy_get_clusters");
    return clusters;
  }
  Mesh polygon_mesh() const {
    cagekit_mesh out = nullptr;
    check(cagekit_hierarchy_get_polygon_mesh(handle_, &out), "cagekit_hierarchy_get_polygon_mesh");
    return wrap<Mesh>(out);
  }
  Mesh refined_polygon_mesh(double chord_tolerance) const {
    cagekit_mesh out = nullptr;
    check(cagekit_hierarchy_get_refined_polygon_mesh(handle_, chord_tolerance, &out),
          "cagekit_hierarchy_get_refined_polygon_mesh");
    return wrap<Mesh>(out);
  }
  // The current level's quad-dominant cage with crease tags.
  Cage build_cage(const cagekit_cage_options& options = defaults<cagekit_cage_options>(),
                  cagekit_cage_report* report = nullptr) const {
    cagekit_cage out = nullptr;
    if (report != nullptr) report->struct_size = sizeof(*report);
    check(cagekit_hierarchy_build_cage(handle_, &options, &out, report), "cagekit_hierarchy_build_cage");
    return wrap<Cage>(out);
  }
};

// ------------------------------------------------------------------------------------------------
// Binding and the CPU deformer (multiresolution editing)
// ------------------------------------------------------------------------------------------------

class Binding : public detail::Handle<Binding, cagekit_binding, cagekit_binding_retain, cagekit_binding_release> {
  CAGEKIT_HPP_HANDLE(Binding, cagekit_binding, cagekit_binding_retain, cagekit_binding_release)

  cagekit_binding_info info() const {
    cagekit_binding_info info = defaults<cagekit_binding_info>();
    check(cagekit_binding_get_info(handle_, &info), "cagekit_binding_get_info");
    return info;
  }
  void write_file(const std::string& path) const {
    check(cagekit_binding_write_file(handle_, path.c_str()), "cagekit_binding_write_file");
  }
  Blob write_memory() const {
    cagekit_blob blob = nullptr;
    check(cagekit_binding_write_memory(handle_, &blob), "cagekit_binding_write_memory");
    return wrap<Blob>(blob);
  }
  // Per bound vertex, the scan vertex it copies (identity without a sector split).
  std::vector<uint32_t> vertex_sources() const {
    uint32_t count = 0;
    check(cagekit_binding_get_vertex_sources(handle_, 0, &count, nullptr), "cagekit_binding_get_vertex_sources");
    std::vector<uint32_t> sources(count);
    if (count != 0)
      check(cagekit_binding_get_vertex_sources(handle_, count, &count, sources.data()),
            "cagekit_binding_get_vertex_sources");
    return sources;
  }
  // The scan's faces over the bound vertices (empty without a sector split).
  Faces faces() const {
    const char* fn = "cagekit_binding_get_faces";
    Faces f;
    uint32_t face_count = 0;
    uint64_t index_count = 0;
    check(cagekit_binding_get_faces(handle_, 0, &face_count, nullptr, 0, &index_count, nullptr), fn);
    f.face_sizes.resize(face_count);
    f.face_indices.resize(static_cast<size_t>(index_count));
    check(cagekit_binding_get_faces(handle_, face_count, &face_count, detail::data_or_null(f.face_sizes), index_count,
                                    &index_count, detail::data_or_null(f.face_indices)),
          fn);
    return f;
  }
  std::vector<uint32_t> deformer_vertex_order() const {
    const char* fn = "cagekit_binding_get_deformer_vertex_order";
    uint32_t count = 0;
    check(cagekit_binding_get_deformer_vertex_order(handle_, 0, &count, nullptr), fn);
    std::vector<uint32_t> order(count);
    if (count != 0) check(cagekit_binding_get_deformer_vertex_order(handle_, count, &count, order.data()), fn);
    return order;
  }
  // A copy of the cage the binding was made on.
  Cage cage() const {
    cagekit_cage out = nullptr;
    check(cagekit_binding_get_cage(handle_, &out), "cagekit_binding_get_cage");
    return wrap<Cage>(out);
  }
  // threads: 0 = all cores.
  CpuDeformer create_cpu_deformer(uint32_t threads = 0) const;
};

// A deformer's output as vectors: xyz triples per bound vertex.
template <class T>
struct Deformed {
  std::vector<T> positions;
  std::vector<T> normals;
  uint32_t vertex_count = 0;
};

class CpuDeformer
    : public detail::Handle<CpuDeformer, cagekit_cpu_deformer, cagekit_cpu_deformer_retain,
                            cagekit_cpu_deformer_release> {
  CAGEKIT_HPP_HANDLE(CpuDeformer, cagekit_cpu_deformer, cagekit_cpu_deformer_retain, cagekit_cpu_deformer_release)

  // The number of bound vertices (the outputs hold 3 values per vertex).
  uint32_t vertex_count() const {
    uint32_t count = 0;
    const double unused = 0;
    check(cagekit_cpu_deformer_deform(handle_, &unused, 0, CAGEKIT_NORMALS_APPROXIMATE, 0, &count, nullptr, nullptr),
          "cagekit_cpu_deformer_deform");
    return count;
  }

  // Full recompute from `control` (xyz per cage vertex) into caller memory: positions and normals
  // hold 3 values per bound vertex, or are empty to skip. Returns the vertex count written.
  uint32_t deform(View<const double> control, cagekit_normal_mode mode, View<double> positions,
                  View<double> normals) {
    return deform_into<double>(cagekit_cpu_deformer_deform, "cagekit_cpu_deformer_deform", control, mode, positions,
                               normals);
  }
  uint32_t deform_f32(View<const double> control, cagekit_normal_mode mode, View<float> positions,
                      View<float> normals) {
    return deform_into<float>(cagekit_cpu_deformer_deform_f32, "cagekit_cpu_deformer_deform_f32", control, mode,
                              positions, normals);
  }
  // Incremental: only `moved` control points changed since the last deform/update. Writes only the
  // vertices in their support; returns the number recomputed.
  uint32_t update(View<const double> control, View<const uint32_t> moved, cagekit_normal_mode mode,
                  View<double> positions, View<double> normals) {
    return update_into<double>(cagekit_cpu_deformer_update, "cagekit_cpu_deformer_update", control, moved, mode,
                               positions, normals);
  }
  uint32_t update_f32(View<const double> control, View<const uint32_t> moved, cagekit_normal_mode mode,
                      View<float> positions, View<float> normals) {
    return update_into<float>(cagekit_cpu_deformer_update_f32, "cagekit_cpu_deformer_update_f32", control, moved,
                              mode, positions, normals);
  }

  // The same as vectors (positions and normals).
  Deformed<double> deform(View<const double> control, cagekit_normal_mode mode = CAGEKIT_NORMALS_APPROXIMATE) {
    Deformed<double> out = sized<double>();
    out.vertex_count = deform(control, mode, out.positions, out.normals);
    return out;
  }
  Deformed<float> deform_f32(View<const double> control, cagekit_normal_mode mode = CAGEKIT_NORMALS_APPROXIMATE) {
    Deformed<float> out = sized<float>();
    out.vertex_count = deform_f32(control, mode, out.positions, out.normals);
    return out;
  }

 private:
  template <class T>
  Deformed<T> sized() const {
    Deformed<T> out;
    const size_t values = 3 * static_cast<size_t>(vertex_count());
    out.positions.resize(values);
    out.normals.resize(values);
    return out;
  }
  template <class T, class Fn>
  uint32_t deform_into(Fn fn, const char* name, View<const double> control, cagekit_normal_mode mode,
                       View<T> positions, View<T> normals) {
    uint32_t count = 0;
    const uint32_t capacity = detail::shared_triples(positions.size(), normals.size(), name);
    check(fn(handle_, control.data(), detail::triples(control.size(), "control", name), mode, capacity, &count,
             positions.empty() ? nullptr : positions.data(), normals.empty() ? nullptr : normals.data()),
          name);
    return count;
  }
  template <class T, class Fn>
  uint32_t update_into(Fn fn, const char* name, View<const double> control, View<const uint32_t> moved,
                       cagekit_normal_mode mode, View<T> positions, View<T> normals) {
    uint32_t count = 0, updated = 0;
    const uint32_t capacity = detail::shared_triples(positions.size(), normals.size(), name);
    check(fn(handle_, control.data(), detail::triples(control.size(), "control", name), moved.data(),
             detail::count32(moved.size(), "moved", name), mode, capacity, &count,
             positions.empty() ? nullptr : positions.data(), normals.empty() ? nullptr : normals.data(), &updated),
          name);
    return updated;
  }
};

// ------------------------------------------------------------------------------------------------
// Definitions that need the complete types
// ------------------------------------------------------------------------------------------------

// ------------------------------------------------------------------------------------------------
// Rendering
// ------------------------------------------------------------------------------------------------

// An RGBA8 image: width * height pixels of 4 bytes, rows top first.
struct Image {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

// Geometry an item draws: xyz per vertex, three vertex indices per triangle.
struct RenderGeometry {
  std::vector<double> positions;
  std::vector<uint32_t> triangles;
};

class RenderScene
    : public detail::Handle<RenderScene, cagekit_render_scene, cagekit_render_scene_retain,
                            cagekit_render_scene_release> {
  CAGEKIT_HPP_HANDLE(RenderScene, cagekit_render_scene, cagekit_render_scene_retain, cagekit_render_scene_release)

  void set_options(const cagekit_render_options& options) {
    check(cagekit_render_scene_set_options(handle_, &options), "cagekit_render_scene_set_options");
  }
  // The current options (egl_library points into the scene: valid until the next set_options).
  cagekit_render_options options() const {
    cagekit_render_options o = defaults<cagekit_render_options>();
    check(cagekit_render_scene_get_options(handle_, &o), "cagekit_render_scene_get_options");
    return o;
  }
  // One camera per row of the image.
  void set_views(View<const cagekit_render_camera> cameras) {
    const char* fn = "cagekit_render_scene_set_views";
    check(cagekit_render_scene_set_views(handle_, detail::count32(cameras.size(), "cameras", fn), cameras.data()), fn);
  }
  // The same by view kind (each with the default fov).
  void set_views(std::initializer_list<cagekit_render_view> views) {
    std::vector<cagekit_render_camera> cameras;
    for (cagekit_render_view v : views) {
      cagekit_render_camera c = defaults<cagekit_render_camera>();
      c.view = v;
      cameras.push_back(c);
    }
    set_views(View<const cagekit_render_camera>(cameras.data(), cameras.size()));
  }
  // Adds an item; returns its index.
  uint32_t add_mesh(const Mesh& mesh, cagekit_render_item_kind kind = CAGEKIT_RENDER_ITEM_MESH,
                    const cagekit_render_item_options& options = defaults<cagekit_render_item_options>());
  uint32_t add_cage(const Cage& cage,
                    const cagekit_render_item_options& options = defaults<cagekit_render_item_options>());
  void set_scalars(uint32_t item, View<const double> values,
                   const cagekit_render_scalar_options& options = defaults<cagekit_render_scalar_options>()) {
    const char* fn = "cagekit_render_scene_set_scalars";
    check(cagekit_render_scene_set_scalars(handle_, item, detail::count32(values.size(), "values", fn), values.data(),
                                           &options),
          fn);
  }
  void set_distance_to_scan(uint32_t item, const Mesh& scan,
                            const cagekit_render_scalar_options& options = defaults<cagekit_render_scalar_options>());
  std::vector<double> scalars(uint32_t item) const {
    const char* fn = "cagekit_render_scene_get_scalars";
    uint32_t count = 0;
    check(cagekit_render_scene_get_scalars(handle_, item, 0, &count, nullptr), fn);
    std::vector<double> out(count);
    if (count != 0) check(cagekit_render_scene_get_scalars(handle_, item, count, &count, out.data()), fn);
    return out;
  }
  RenderGeometry geometry(uint32_t item) const {
    const char* fn = "cagekit_render_scene_get_item_geometry";
    uint32_t vertices = 0, triangles = 0;
    check(cagekit_render_scene_get_item_geometry(handle_, item, 0, &vertices, nullptr, 0, &triangles, nullptr), fn);
    RenderGeometry g;
    g.positions.resize(3 * size_t(vertices));
    g.triangles.resize(3 * size_t(triangles));
    check(cagekit_render_scene_get_item_geometry(handle_, item, vertices, &vertices, detail::data_or_null(g.positions),
                                                 triangles, &triangles, detail::data_or_null(g.triangles)),
          fn);
    return g;
  }
  uint32_t item_count() const {
    uint32_t count = 0;
    check(cagekit_render_scene_get_item_count(handle_, &count), "cagekit_render_scene_get_item_count");
    return count;
  }
  cagekit_render_item_info item_info(uint32_t item) const {
    cagekit_render_item_info info = defaults<cagekit_render_item_info>();
    check(cagekit_render_scene_get_item_info(handle_, item, &info), "cagekit_render_scene_get_item_info");
    return info;
  }
  // Draws headless (the library's own EGL context).
  Image draw() const {
    const char* fn = "cagekit_render_scene_draw";
    uint32_t count = 0;
    check(cagekit_render_scene_draw(handle_, 0, &count, nullptr), fn);
    Image image = sized_image(count);
    check(cagekit_render_scene_draw(handle_, count, &count, image.rgba.data()), fn);
    return image;
  }
  void write_png(const std::string& path) const {
    check(cagekit_render_scene_write_png(handle_, path.c_str()), "cagekit_render_scene_write_png");
  }
  Blob encode_png() const;

 private:
  Image sized_image(uint32_t count) const {
    const cagekit_render_options o = options();
    Image image;
    image.rgba.resize(4 * size_t(count));
    image.width = o.width;
    image.height = o.height;
    return image;
  }
};

inline Mesh Context::create_mesh(const cagekit_mesh_desc& desc) const {
  cagekit_mesh out = nullptr;
  check(cagekit_mesh_create(handle_, &desc, &out), "cagekit_mesh_create");
  return wrap<Mesh>(out);
}

inline Mesh Context::create_mesh(View<const double> positions, View<const uint32_t> face_indices,
                                 uint32_t face_size) const {
  const char* fn = "cagekit_mesh_create";
  cagekit_mesh_desc desc = defaults<cagekit_mesh_desc>();
  desc.vertex_count = detail::triples(positions.size(), "positions", fn);
  desc.positions = positions.data();
  desc.uniform_face_size = face_size;
  if (face_size == 0 || face_indices.size() % face_size != 0)
    throw Error(CAGEKIT_ERROR_INVALID_ARGUMENT, fn,
                "face_indices holds " + std::to_string(face_indices.size()) + " indices, not faces of " +
                    std::to_string(face_size));
  desc.face_count = detail::count32(face_indices.size() / face_size, "faces", fn);
  desc.face_indices = face_indices.data();
  return create_mesh(desc);
}

inline Mesh Context::create_mesh(View<const double> positions, View<const uint32_t> face_sizes,
                                 View<const uint32_t> face_indices) const {
  const char* fn = "cagekit_mesh_create";
  cagekit_mesh_desc desc = defaults<cagekit_mesh_desc>();
  desc.vertex_count = detail::triples(positions.size(), "positions", fn);
  desc.positions = positions.data();
  desc.face_count = detail::count32(face_sizes.size(), "face_sizes", fn);
  desc.face_sizes = face_sizes.data();
  desc.face_indices = face_indices.data();
  uint64_t total = 0;
  for (uint32_t size : face_sizes) total += size;
  if (total != face_indices.size())
    throw Error(CAGEKIT_ERROR_INVALID_ARGUMENT, fn,
                "the face sizes add up to " + std::to_string(total) + " indices but face_indices holds " +
                    std::to_string(face_indices.size()));
  return create_mesh(desc);
}

inline Mesh Context::read_mesh(const std::string& path, cagekit_file_format format) const {
  cagekit_mesh out = nullptr;
  check(cagekit_mesh_read_file(handle_, path.c_str(), format, &out), "cagekit_mesh_read_file");
  return wrap<Mesh>(out);
}

inline Mesh Context::read_mesh(const void* data, size_t size, cagekit_file_format format) const {
  cagekit_mesh out = nullptr;
  check(cagekit_mesh_read_memory(handle_, data, size, format, &out), "cagekit_mesh_read_memory");
  return wrap<Mesh>(out);
}

inline Cage Context::read_cage(const std::string& path, cagekit_file_format format) const {
  cagekit_cage out = nullptr;
  check(cagekit_cage_read_file(handle_, path.c_str(), format, &out), "cagekit_cage_read_file");
  return wrap<Cage>(out);
}

inline Cage Context::read_cage(const void* data, size_t size, cagekit_file_format format) const {
  cagekit_cage out = nullptr;
  check(cagekit_cage_read_memory(handle_, data, size, format, &out), "cagekit_cage_read_memory");
  return wrap<Cage>(out);
}

inline Binding Context::read_binding(const std::string& path, uint32_t threads) const {
  cagekit_binding out = nullptr;
  check(cagekit_binding_read_file(handle_, path.c_str(), threads, &out), "cagekit_binding_read_file");
  return wrap<Binding>(out);
}

inline Binding Context::read_binding(const void* data, size_t size, uint32_t threads) const {
  cagekit_binding out = nullptr;
  check(cagekit_binding_read_memory(handle_, data, size, threads, &out), "cagekit_binding_read_memory");
  return wrap<Binding>(out);
}

inline Mesh Mesh::repair(const cagekit_repair_options& options, cagekit_repair_report* report) const {
  cagekit_mesh out = nullptr;
  if (report != nullptr) report->struct_size = sizeof(*report);
  check(cagekit_mesh_repair(handle_, &options, &out, report), "cagekit_mesh_repair");
  return wrap<Mesh>(out);
}

inline Cage Mesh::create_cage() const {
  cagekit_cage out = nullptr;
  check(cagekit_cage_create(handle_, &out), "cagekit_cage_create");
  return wrap<Cage>(out);
}

inline Hierarchy Mesh::create_hierarchy(const cagekit_simplify_options& options) const {
  cagekit_hierarchy out = nullptr;
  check(cagekit_hierarchy_create(handle_, &options, &out), "cagekit_hierarchy_create");
  return wrap<Hierarchy>(out);
}

inline Cage Mesh::remesh_anisotropic(const cagekit_anisotropic_options& options,
                                     cagekit_anisotropic_report* report) const {
  cagekit_cage out = nullptr;
  if (report != nullptr) report->struct_size = sizeof(*report);
  check(cagekit_mesh_remesh_anisotropic(handle_, &options, &out, report), "cagekit_mesh_remesh_anisotropic");
  return wrap<Cage>(out);
}

inline Cage Mesh::remesh_quad(const cagekit_quad_remesh_options& options, cagekit_quad_remesh_report* report) const {
  cagekit_cage out = nullptr;
  if (report != nullptr) report->struct_size = sizeof(*report);
  check(cagekit_mesh_remesh_quad(handle_, &options, &out, report), "cagekit_mesh_remesh_quad");
  return wrap<Cage>(out);
}

inline Surface Cage::create_surface(const cagekit_surface_options& options) const {
  cagekit_surface out = nullptr;
  check(cagekit_surface_create(handle_, &options, &out), "cagekit_surface_create");
  return wrap<Surface>(out);
}

inline LimitPatches Cage::create_limit_patches(const cagekit_limit_patch_options& options) const {
  cagekit_limit_patches out = nullptr;
  check(cagekit_limit_patches_create(handle_, &options, &out), "cagekit_limit_patches_create");
  return wrap<LimitPatches>(out);
}

inline LimitSurfaces Cage::create_limit_surfaces(const cagekit_limit_surface_options& options) const {
  cagekit_limit_surfaces out = nullptr;
  check(cagekit_limit_surfaces_create(handle_, &options, &out), "cagekit_limit_surfaces_create");
  return wrap<LimitSurfaces>(out);
}

inline Cage::Fit Cage::fit(const Mesh& scan, const cagekit_fit_options& options) const {
  Fit result;
  // max_passes + 1 entries always suffice, so the fit runs once.
  const uint32_t capacity = options.max_passes + 1;
  result.passes.resize(capacity);
  cagekit_cage out = nullptr;
  uint32_t count = 0;
  check(cagekit_cage_fit(handle_, scan.get(), &options, &out, &result.report, capacity, &count, result.passes.data()),
        "cagekit_cage_fit");
  result.cage = wrap<Cage>(out);
  result.passes.resize(count);
  return result;
}

inline Binding Cage::bind(const Mesh& scan, const cagekit_bind_options& options) const {
  cagekit_binding out = nullptr;
  check(cagekit_multires_bind(handle_, scan.get(), &options, &out), "cagekit_multires_bind");
  return wrap<Binding>(out);
}

inline CpuDeformer Binding::create_cpu_deformer(uint32_t threads) const {
  cagekit_cpu_deformer out = nullptr;
  check(cagekit_cpu_deformer_create(handle_, threads, &out), "cagekit_cpu_deformer_create");
  return wrap<CpuDeformer>(out);
}


inline RenderScene Context::create_render_scene() const {
  cagekit_render_scene out = nullptr;
  check(cagekit_render_scene_create(handle_, &out), "cagekit_render_scene_create");
  return wrap<RenderScene>(out);
}

inline void Context::write_png(const std::string& path, View<const uint8_t> rgba, uint32_t width,
                               uint32_t height) const {
  const char* fn = "cagekit_render_encode_png";
  if (rgba.size() != 4 * size_t(width) * size_t(height))
    throw Error(CAGEKIT_ERROR_INVALID_ARGUMENT, fn, "rgba holds " + std::to_string(rgba.size()) + " bytes, not 4 * " +
                                                        std::to_string(width) + " * " + std::to_string(height));
  check(cagekit_render_encode_png(handle_, rgba.data(), width, height, path.c_str(), nullptr), fn);
}

inline Blob Context::encode_png(View<const uint8_t> rgba, uint32_t width, uint32_t height) const {
  const char* fn = "cagekit_render_encode_png";
  if (rgba.size() != 4 * size_t(width) * size_t(height))
    throw Error(CAGEKIT_ERROR_INVALID_ARGUMENT, fn, "rgba holds " + std::to_string(rgba.size()) + " bytes, not 4 * " +
                                                        std::to_string(width) + " * " + std::to_string(height));
  cagekit_blob out = nullptr;
  check(cagekit_render_encode_png(handle_, rgba.data(), width, height, nullptr, &out), fn);
  return wrap<Blob>(out);
}

inline uint32_t RenderScene::add_mesh(const Mesh& mesh, cagekit_render_item_kind kind,
                                      const cagekit_render_item_options& options) {
  uint32_t item = 0;
  check(cagekit_render_scene_add_mesh(handle_, mesh.get(), kind, &options, &item), "cagekit_render_scene_add_mesh");
  return item;
}

inline uint32_t RenderScene::add_cage(const Cage& cage, const cagekit_render_item_options& options) {
  uint32_t item = 0;
  check(cagekit_render_scene_add_cage(handle_, cage.get(), &options, &item), "cagekit_render_scene_add_cage");
  return item;
}

inline void RenderScene::set_distance_to_scan(uint32_t item, const Mesh& scan,
                                              const cagekit_render_scalar_options& options) {
  check(cagekit_render_scene_set_distance_to_scan(handle_, item, scan.get(), &options),
        "cagekit_render_scene_set_distance_to_scan");
}

inline Blob RenderScene::encode_png() const {
  cagekit_blob out = nullptr;
  check(cagekit_render_scene_encode_png(handle_, &out), "cagekit_render_scene_encode_png");
  return wrap<Blob>(out);
}

}  // namespace cagekit

#endif  // CAGEKIT_CAGEKIT_HPP
