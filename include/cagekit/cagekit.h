/*
 * CageKit — structure-preserving Catmull-Clark models from dense triangle meshes.
 * SPDX-License-Identifier: GPL-3.0-or-later
 *
 * The public C API of libcagekit. C99; also compiles as C++.
 *
 * Conventions (the same for every call; individual functions only state exceptions):
 *
 * - Handles. Objects are opaque, reference-counted handles (cagekit_context, cagekit_mesh,
 *   cagekit_cage, cagekit_surface, cagekit_blob). A function that creates a handle hands the
 *   caller one reference; release it with the type's *_release() function. *_retain() adds a
 *   reference. Every object keeps its context alive, so a context may be released before the
 *   objects made with it. Releasing NULL is a no-op.
 *
 * - Status codes. Every call that can fail returns a cagekit_status: 0 on success, negative on
 *   error (CAGEKIT_FAILED(s)). On error, output handles are set to NULL, output buffers are left
 *   in an unspecified state, and nothing is allocated. A human-readable message describing the
 *   failure precisely (file and line, element index, ...) is available from
 *   cagekit_last_error_message() on the same thread.
 *
 * - No C++ exception, abort() or exit() ever leaves the library. Bad input (corrupt files, NaN,
 *   out-of-range indices, hostile sizes) yields an error status, never a crash.
 *
 * - Options and report structs begin with `struct_size`, which the caller sets to
 *   sizeof(the struct) as compiled (use the CAGEKIT_*_INIT helpers or the *_init functions).
 *   Fields may be added at the end in later minor versions without breaking the ABI: the library
 *   reads/writes only the fields that fit in struct_size. Passing NULL for an options struct
 *   means "all defaults".
 *
 * - Buffers. Inputs are copied: the library never keeps a caller pointer after a call returns.
 *   Every array output has one shape, OpenXR's two-call idiom: the parameters
 *   `uint32_t <x>_capacity` (uint64_t where counts can exceed 2^32), `uint32_t* <x>_count_out`
 *   and the array or arrays the count sizes (`T* <x>s`, or named for what they hold). Capacities
 *   and counts are in elements (vertices, creases, ...): an array of xyz triples holds
 *   3 * capacity scalars. Call with capacity 0 to get the count, allocate, call again. The rules:
 *   - <x>_count_out must not be NULL (INVALID_ARGUMENT naming it); it receives the required
 *     count on success and on SIZE_INSUFFICIENT.
 *   - <x>_capacity 0: only the count is written; the array may be NULL and is not touched.
 *   - A nonzero capacity below the required count: CAGEKIT_ERROR_SIZE_INSUFFICIENT (the message
 *     names the array and both numbers); the array's contents are then unspecified.
 *   - A nonzero capacity with a NULL array: INVALID_ARGUMENT.
 *   - Several arrays sized by one count (positions and normals, ...) share one capacity/count
 *     pair; each of them may be NULL to skip it.
 *   Functions say "Two-call (Buffers)" and what is counted. An array whose length the caller
 *   gives as an input (cagekit_surface_evaluate's points, one per location) is not two-call.
 *
 * - Enumerations have a *_MAX_ENUM member (as Vulkan's) so that they are 32-bit and any int a
 *   caller passes is a defined value; out-of-range values are rejected with INVALID_ARGUMENT.
 *
 * - Thread safety. All functions may be called concurrently from several threads on DIFFERENT
 *   objects. A single object may be used by several threads at once only through calls that
 *   are documented as read-only on it ("reads"); calls marked "modifies" need exclusive access.
 *   Contexts are safe to share between threads (the last error is kept per thread).
 *
 * - Long operations report progress through the context's progress callback (on the calling
 *   thread) and can be cancelled: by returning 0 from the callback, or by
 *   cagekit_context_cancel() from any thread. They then return CAGEKIT_ERROR_CANCELLED.
 *
 * - Each function's comment says what it does, then "Ownership:" (what it returns or keeps, and
 *   for how long; only where a handle, pointer or buffer crosses the call), "Errors:" (the status
 *   codes it returns and when; "none" for calls that cannot fail) and "Threading:" (what it reads
 *   or modifies, and from which threads it may be called). Besides the codes listed, any call
 *   that returns a status may return CAGEKIT_ERROR_INTERNAL.
 */
#ifndef CAGEKIT_CAGEKIT_H
#define CAGEKIT_CAGEKIT_H

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32)
#  if defined(CAGEKIT_BUILDING_LIBRARY)
#    define CAGEKIT_API __declspec(dllexport)
#  else
#    define CAGEKIT_API __declspec(dllimport)
#  endif
#else
#  define CAGEKIT_API __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------------------------ */
/* Versioning                                                                                 */
/* ------------------------------------------------------------------------------------------ */

/* Packs a version as 10 bits major, 10 bits minor, 12 bits patch. */
#define CAGEKIT_MAKE_VERSION(major, minor, patch) \
  ((((uint32_t)(major)) << 22) | (((uint32_t)(minor)) << 12) | ((uint32_t)(patch)))
#define CAGEKIT_VERSION_MAJOR 0
#define CAGEKIT_VERSION_MINOR 2
#define CAGEKIT_VERSION_PATCH 0
#define CAGEKIT_VERSION \
  CAGEKIT_MAKE_VERSION(CAGEKIT_VERSION_MAJOR, CAGEKIT_VERSION_MINOR, CAGEKIT_VERSION_PATCH)

/* The ABI major version: incremented on any change that breaks binary compatibility (it is the
 * number in the shared library's soname, libcagekit.so.N, and in its symbol version CAGEKIT_N).
 * A host built against this header passes CAGEKIT_ABI_VERSION in cagekit_context_desc; a
 * library of another ABI refuses it (CAGEKIT_ERROR_VERSION_MISMATCH) instead of reading structs
 * laid out for another version. ABI 2 (0.2): the 1.0 contract in the making (ABI 1 was 0.1). */
#define CAGEKIT_ABI_VERSION 2

/* Version of the loaded library (CAGEKIT_MAKE_VERSION packing).
 * Errors: none.
 * Threading: any thread (thread-safe). */
CAGEKIT_API uint32_t cagekit_version(void);
/* "MAJOR.MINOR.PATCH" of the loaded library.
 * Ownership: a static string of the library (never freed).
 * Errors: none.
 * Threading: any thread (thread-safe). */
CAGEKIT_API const char* cagekit_version_string(void);
/* ABI major version of the loaded library.
 * Errors: none.
 * Threading: any thread (thread-safe). */
CAGEKIT_API uint32_t cagekit_abi_version(void);

/* ------------------------------------------------------------------------------------------ */
/* Booleans                                                                                   */
/* ------------------------------------------------------------------------------------------ */

/* The one boolean type of the API, in every options, report and info struct: CAGEKIT_FALSE (0)
 * or CAGEKIT_TRUE (1). An input field of any other value is rejected with
 * CAGEKIT_ERROR_INVALID_ARGUMENT ("cagekit_<struct>.<field> must be 0 or 1, not N"); the library
 * writes only 0 or 1. */
typedef uint32_t cagekit_bool32;
#define CAGEKIT_FALSE 0u
#define CAGEKIT_TRUE 1u

/* ------------------------------------------------------------------------------------------ */
/* Status codes and errors                                                                    */
/* ------------------------------------------------------------------------------------------ */

typedef enum cagekit_status {
  CAGEKIT_SUCCESS = 0,
  CAGEKIT_ERROR_INVALID_ARGUMENT = -1,   /* NULL where not allowed, value out of range */
  CAGEKIT_ERROR_INVALID_HANDLE = -2,     /* not a live handle of the expected type */
  CAGEKIT_ERROR_OUT_OF_MEMORY = -3,
  CAGEKIT_ERROR_SIZE_INSUFFICIENT = -4,  /* output capacity too small (two-call idiom) */
  CAGEKIT_ERROR_IO = -5,                 /* a file could not be opened, read or written */
  CAGEKIT_ERROR_PARSE = -6,              /* malformed or corrupt file content */
  CAGEKIT_ERROR_UNSUPPORTED_FORMAT = -7, /* unknown file format, or a format version or variant not read */
  CAGEKIT_ERROR_INVALID_MESH = -8,       /* the mesh fails validation for this operation */
  CAGEKIT_ERROR_LIMIT_EXCEEDED = -9,     /* a size beyond what the library accepts */
  CAGEKIT_ERROR_CANCELLED = -10,         /* cancelled by the progress callback or _cancel() */
  CAGEKIT_ERROR_INTERNAL = -11,          /* a bug in CageKit: please report it */
  CAGEKIT_ERROR_VERSION_MISMATCH = -12,  /* the host was built for another ABI version */
  CAGEKIT_ERROR_QUALITY = -13,           /* a result was computed but misses its quality bounds (the
                                            message names the figure); nothing is returned */
  CAGEKIT_ERROR_UNSUPPORTED_FEATURE = -14, /* the host's environment or the object lacks a feature the
                                              call needs (a GL context older than the deformer needs,
                                              exact normals on the GPU); the message names it */
  CAGEKIT_ERROR_INVALID_OPERATION = -15, /* the call is not allowed in the object's current state or
                                            order (an update before a first deform, no GL context
                                            current); the message names what must come first */
  CAGEKIT_STATUS_MAX_ENUM = 0x7fffffff   /* forces 32-bit enums (any int value is representable) */
} cagekit_status;

#define CAGEKIT_SUCCEEDED(status) ((status) >= 0)
#define CAGEKIT_FAILED(status) ((status) < 0)

/* An English name of a status ("invalid argument"), or "unknown status" for a negative value that
 * is no status code.
 * Ownership: a static string of the library (never freed).
 * Errors: none.
 * Threading: any thread (thread-safe). */
CAGEKIT_API const char* cagekit_status_string(cagekit_status status);

/* ------------------------------------------------------------------------------------------ */
/* Context                                                                                    */
/* ------------------------------------------------------------------------------------------ */

typedef struct cagekit_context_t* cagekit_context;
typedef struct cagekit_mesh_t* cagekit_mesh;
typedef struct cagekit_cage_t* cagekit_cage;
typedef struct cagekit_surface_t* cagekit_surface;
typedef struct cagekit_blob_t* cagekit_blob;

typedef enum cagekit_log_level {
  CAGEKIT_LOG_DEBUG = 0,
  CAGEKIT_LOG_INFO = 1,
  CAGEKIT_LOG_WARNING = 2,
  CAGEKIT_LOG_ERROR = 3,
  CAGEKIT_LOG_MAX_ENUM = 0x7fffffff
} cagekit_log_level;

/* Receives log messages at or above the context's log level. Called on the thread that made
 * the library call; `message` is valid only during the callback. Must not call back into
 * CageKit with the same context. */
typedef void (*cagekit_log_fn)(void* user_data, cagekit_log_level level, const char* message);

/* Receives the progress of a long operation: `stage` names the step ("reading",
 * "subdivide", ...), `fraction` is in [0, 1] and non-decreasing within a stage. Return nonzero to
 * continue, 0 to cancel (the operation then returns CAGEKIT_ERROR_CANCELLED). Called on the
 * thread that made the library call, at most every few milliseconds of work, and often enough that
 * a cancel takes effect within about half a second (measured on a 1.1M-triangle scan on a 2-core
 * machine: at most 0.3 s between calls, the call returning within 0.35 s of the cancelling one).
 * Must not call back into CageKit with the same context. */
typedef int (*cagekit_progress_fn)(void* user_data, const char* stage, double fraction);

typedef struct cagekit_context_desc {
  size_t struct_size;             /* sizeof(cagekit_context_desc) */
  uint32_t abi_version;           /* CAGEKIT_ABI_VERSION of the header the host was built with */
  cagekit_log_fn log;             /* may be NULL */
  void* log_user_data;
  cagekit_log_level log_level;    /* lowest level passed to `log` (default WARNING) */
  cagekit_progress_fn progress;   /* may be NULL */
  void* progress_user_data;
  /* Memory budget of one call made with this context, in bytes (0 = unlimited, the default).
   * Before its large allocations and before handing work to a library (OpenSubdiv, CGAL, Draco,
   * Eigen), each call compares its estimated peak memory with this budget and fails with
   * CAGEKIT_ERROR_OUT_OF_MEMORY ("... needs about N MiB, more than the context's memory budget
   * of M MiB") instead of allocating. Estimates cover the dominant arrays of each step (input
   * and output meshes, refinement levels, patch tables, hierarchies, least-squares systems);
   * they are not an accounting of every allocation, so keep some headroom. The budget is per
   * call, not shared between concurrent calls. */
  uint64_t memory_budget_bytes;
} cagekit_context_desc;

#define CAGEKIT_CONTEXT_DESC_INIT \
  { sizeof(cagekit_context_desc), CAGEKIT_ABI_VERSION, NULL, NULL, CAGEKIT_LOG_WARNING, NULL, NULL, 0 }

/* Creates a context, the owner of settings and callbacks for the objects made with it.
 * desc may be NULL (no callbacks).
 * Ownership: *out receives one reference (release it with cagekit_context_release). desc is read
 *   during the call only; the context keeps its callbacks and user_data pointers.
 * Errors: INVALID_ARGUMENT (out NULL, bad struct_size, log_level out of range), VERSION_MISMATCH
 *   (desc->abi_version differs from the library's), OUT_OF_MEMORY. The message of a failed
 *   create is available from cagekit_last_error_message(NULL).
 * Threading: any thread (thread-safe). */
CAGEKIT_API cagekit_status cagekit_context_create(const cagekit_context_desc* desc, cagekit_context* out);
/* Adds a reference (retain) or drops one (release). The context is destroyed when its last
 * reference is gone, which includes those held by the objects made with it. NULL is ignored.
 * Errors: none.
 * Threading: any thread (the reference count is atomic). */
CAGEKIT_API void cagekit_context_retain(cagekit_context context);
CAGEKIT_API void cagekit_context_release(cagekit_context context);

/* Replaces the progress callback (NULL removes it).
 * Ownership: the context keeps `progress` and `user_data` until they are replaced or the context
 *   is destroyed.
 * Errors: INVALID_HANDLE.
 * Threading: modifies the context: must not run while another thread is inside a call using this
 *   context. */
CAGEKIT_API cagekit_status cagekit_context_set_progress(cagekit_context context, cagekit_progress_fn progress,
                                                        void* user_data);

/* Requests cancellation of every long operation running with this context and of those that
 * start later, until cagekit_context_reset_cancel(). NULL is ignored.
 * Errors: none.
 * Threading: any thread, e.g. a UI thread, at any time. */
CAGEKIT_API void cagekit_context_cancel(cagekit_context context);
/* Clears a cancellation request. NULL is ignored.
 * Errors: none.
 * Threading: any thread. */
CAGEKIT_API void cagekit_context_reset_cancel(cagekit_context context);

/* The message of the most recent failed call made on the calling thread with objects of this
 * context (context NULL: of a failed cagekit_context_create on this thread), or "" if none.
 * Ownership: the string is owned by the library and stays valid until the next failing call on
 *   this thread with this context, or until the context is destroyed.
 * Errors: none.
 * Threading: any thread (thread-safe: messages are kept per thread). */
CAGEKIT_API const char* cagekit_last_error_message(cagekit_context context);

/* ------------------------------------------------------------------------------------------ */
/* Blob: a library-owned byte buffer (file contents encoded in memory)                        */
/* ------------------------------------------------------------------------------------------ */

/* The bytes of a blob (data) and their number (size); NULL and 0 for a NULL blob.
 * Ownership: the bytes are owned by the blob and valid until its last release.
 * Errors: none.
 * Threading: reads `blob`; thread-safe. */
CAGEKIT_API const void* cagekit_blob_data(cagekit_blob blob);
CAGEKIT_API size_t cagekit_blob_size(cagekit_blob blob);
/* Adds a reference (retain) or drops one (release; the last one frees the bytes). NULL is ignored.
 * Errors: none.
 * Threading: any thread (the reference count is atomic). */
CAGEKIT_API void cagekit_blob_retain(cagekit_blob blob);
CAGEKIT_API void cagekit_blob_release(cagekit_blob blob);

/* ------------------------------------------------------------------------------------------ */
/* Mesh: an indexed polygon mesh                                                              */
/* ------------------------------------------------------------------------------------------ */

typedef enum cagekit_scalar_type {
  CAGEKIT_SCALAR_FLOAT32 = 0,
  CAGEKIT_SCALAR_FLOAT64 = 1,
  CAGEKIT_SCALAR_MAX_ENUM = 0x7fffffff
} cagekit_scalar_type;

typedef struct cagekit_mesh_desc {
  size_t struct_size;                /* sizeof(cagekit_mesh_desc) */
  uint32_t vertex_count;
  const void* positions;             /* vertex_count xyz triples of position_type */
  cagekit_scalar_type position_type;
  size_t position_stride;            /* bytes from one vertex to the next; 0 = 3 packed scalars */
  uint32_t face_count;
  const uint32_t* face_sizes;        /* face_count sizes; NULL = every face has uniform_face_size */
  uint32_t uniform_face_size;        /* used when face_sizes is NULL (3 for triangle meshes) */
  const uint32_t* face_indices;      /* sum of face sizes vertex indices, faces one after another */
} cagekit_mesh_desc;

#define CAGEKIT_MESH_DESC_INIT \
  { sizeof(cagekit_mesh_desc), 0, NULL, CAGEKIT_SCALAR_FLOAT64, 0, 0, NULL, 3, NULL }

/* Creates a mesh by copying caller buffers. The content is NOT validated here (so that
 * cagekit_mesh_validate can report and cagekit_mesh_repair can fix it); operations that need a
 * valid mesh check it and fail with CAGEKIT_ERROR_INVALID_MESH. Structural errors of the
 * description itself fail (below).
 * Ownership: *out receives one reference (release it with cagekit_mesh_release); desc and the
 *   arrays it points to are read during the call only.
 * Errors: INVALID_HANDLE (context), INVALID_ARGUMENT (out or desc NULL, bad struct_size, NULL
 *   buffers with nonzero counts, face sizes of 0, position_type out of range, a position_stride
 *   smaller than one xyz triple), LIMIT_EXCEEDED (2^31 or more vertices, faces or face indices),
 *   OUT_OF_MEMORY.
 * Threading: any thread (thread-safe). */
CAGEKIT_API cagekit_status cagekit_mesh_create(cagekit_context context, const cagekit_mesh_desc* desc,
                                               cagekit_mesh* out);
/* Adds a reference (retain) or drops one (release; the last one destroys the mesh). NULL is
 * ignored.
 * Errors: none.
 * Threading: any thread (the reference count is atomic). */
CAGEKIT_API void cagekit_mesh_retain(cagekit_mesh mesh);
CAGEKIT_API void cagekit_mesh_release(cagekit_mesh mesh);

/* Element counts. Any output pointer may be NULL.
 * Errors: INVALID_HANDLE.
 * Threading: reads `mesh`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_mesh_get_counts(cagekit_mesh mesh, uint32_t* vertex_count, uint32_t* face_count,
                                                   uint64_t* face_index_count);

/* Copies the positions as `type` xyz triples (3 * vertex_count scalars) into `positions`.
 * Two-call (Buffers) over vertices.
 * Ownership: `positions` is the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (type out of range, vertex_count_out NULL, positions
 *   NULL with a nonzero capacity), SIZE_INSUFFICIENT.
 * Threading: reads `mesh`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_mesh_get_positions(cagekit_mesh mesh, cagekit_scalar_type type,
                                                      uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                      void* positions);

/* Copies the faces: face_sizes (face_count entries) and face_indices (sum of sizes entries).
 * Two-call (Buffers) on each array, over faces and over indices; both counts are written before
 * either capacity is checked.
 * Ownership: the arrays are the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (a count pointer NULL, an array NULL with a nonzero
 *   capacity), SIZE_INSUFFICIENT.
 * Threading: reads `mesh`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_mesh_get_faces(cagekit_mesh mesh, uint32_t face_capacity, uint32_t* face_count_out,
                                                  uint32_t* face_sizes, uint64_t index_capacity,
                                                  uint64_t* index_count_out, uint32_t* face_indices);

/* --- validation and repair --- */

/* Kinds of problems; bit (1u << kind) is set in cagekit_validation_report.issue_flags. */
typedef enum cagekit_mesh_issue {
  CAGEKIT_ISSUE_INDEX_OUT_OF_RANGE = 0,
  CAGEKIT_ISSUE_NON_FINITE_POSITION = 1,
  CAGEKIT_ISSUE_DEGENERATE_FACE = 2,
  CAGEKIT_ISSUE_DUPLICATE_FACE = 3,
  CAGEKIT_ISSUE_NON_MANIFOLD_EDGE = 4,
  CAGEKIT_ISSUE_NON_MANIFOLD_VERTEX = 5,
  CAGEKIT_ISSUE_INCONSISTENT_ORIENTATION = 6,
  CAGEKIT_ISSUE_UNREFERENCED_VERTEX = 7, /* a warning only: does not make a mesh invalid */
  CAGEKIT_ISSUE_KIND_COUNT = 8,
  CAGEKIT_ISSUE_MAX_ENUM = 0x7fffffff
} cagekit_mesh_issue;

typedef struct cagekit_validation_report {
  size_t struct_size;                        /* sizeof(cagekit_validation_report) */
  cagekit_bool32 valid;                      /* 1 when no error-level issue was found */
  uint32_t issue_flags;                      /* bit (1u << cagekit_mesh_issue) per kind found */
  uint64_t issue_counts[CAGEKIT_ISSUE_KIND_COUNT];
} cagekit_validation_report;

/* Checks the mesh for every cagekit_mesh_issue. Returns CAGEKIT_SUCCESS when it is valid and
 * CAGEKIT_ERROR_INVALID_MESH when not; in both cases *report (may be NULL) is filled.
 * Errors: INVALID_HANDLE, INVALID_MESH (the mesh is not valid: the last error message lists each
 *   kind of problem with its count and first example, "face 12 refers to vertex 9000 but the mesh
 *   has 6475 vertices"), INVALID_ARGUMENT (report's bad struct_size), OUT_OF_MEMORY.
 * Threading: reads `mesh`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_mesh_validate(cagekit_mesh mesh, cagekit_validation_report* report);

enum {
  CAGEKIT_REPAIR_DROP_INVALID_FACES = 1u << 0,    /* out-of-range indices, non-finite positions */
  CAGEKIT_REPAIR_DROP_DEGENERATE_FACES = 1u << 1,
  CAGEKIT_REPAIR_DROP_DUPLICATE_FACES = 1u << 2,
  CAGEKIT_REPAIR_SPLIT_NON_MANIFOLD = 1u << 3,    /* split non-manifold edges and vertices */
  CAGEKIT_REPAIR_ORIENT = 1u << 4,                /* orient each component consistently */
  CAGEKIT_REPAIR_REMOVE_UNREFERENCED = 1u << 5,
  CAGEKIT_REPAIR_WELD = 1u << 6,                  /* merge vertices within weld_tolerance */
  CAGEKIT_REPAIR_DEFAULT = 0x1f | (1u << 6)
};

typedef struct cagekit_repair_options {
  size_t struct_size;       /* sizeof(cagekit_repair_options) */
  uint32_t steps;           /* CAGEKIT_REPAIR_* flags */
  double weld_tolerance;    /* absolute distance, model units; 0 merges exact duplicates only */
} cagekit_repair_options;

#define CAGEKIT_REPAIR_OPTIONS_INIT { sizeof(cagekit_repair_options), CAGEKIT_REPAIR_DEFAULT, 0.0 }

typedef struct cagekit_repair_report {
  size_t struct_size;       /* sizeof(cagekit_repair_report) */
  uint64_t welded_vertices;
  uint64_t dropped_invalid_faces;
  uint64_t dropped_degenerate_faces;
  uint64_t dropped_duplicate_faces;
  uint64_t split_vertices;
  uint64_t flipped_faces;
  uint64_t removed_unreferenced_vertices;
  uint64_t removed_non_finite_vertices;   /* NaN/Inf vertices (with DROP_INVALID_FACES) */
  uint64_t non_orientable_components;     /* Moebius-like components cut open to orient them */
} cagekit_repair_report;

/* Makes a repaired copy of `mesh` (the input is unchanged). With every step enabled the
 * result always passes cagekit_mesh_validate. options may be NULL (defaults); report may be NULL.
 * Long operation (progress, cancel).
 * Ownership: *out receives one reference (release it with cagekit_mesh_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL, bad struct_size of options or report, an
 *   option out of range, naming it), CANCELLED, OUT_OF_MEMORY.
 * Threading: reads `mesh`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_mesh_repair(cagekit_mesh mesh, const cagekit_repair_options* options,
                                               cagekit_mesh* out, cagekit_repair_report* report);

/* --- statistics --- */

typedef struct cagekit_mesh_info {
  size_t struct_size;           /* sizeof(cagekit_mesh_info) */
  uint64_t vertices, faces, edges;
  uint64_t triangles, quads, other_polygons;
  uint64_t boundary_edges, boundary_loops, components, unreferenced_vertices;
  int64_t genus;                /* -1 when the mesh is not manifold */
  cagekit_bool32 manifold;      /* 1 when edge- and vertex-manifold with valid indices */
  double bbox_min[3], bbox_max[3], bbox_diagonal;
  uint64_t creases, corners, holes; /* tags (cages only; 0 for meshes) */
  uint64_t invalid_faces;       /* faces with bad indices or < 3 distinct vertices (ignored above) */
} cagekit_mesh_info;

/* Fills *info with the mesh's statistics.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (info NULL or bad struct_size), OUT_OF_MEMORY.
 * Threading: reads `mesh`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_mesh_get_info(cagekit_mesh mesh, cagekit_mesh_info* info);

/* ------------------------------------------------------------------------------------------ */
/* Files and streams: OBJ, PLY (ascii/binary), OFF, Draco; STL (read only)                    */
/* ------------------------------------------------------------------------------------------ */

typedef enum cagekit_file_format {
  CAGEKIT_FORMAT_AUTO = 0,  /* by file extension; in memory, by sniffing the content */
  CAGEKIT_FORMAT_OBJ = 1,   /* cages: OpenSubdiv-style `t crease` / `t corner` / `t hole` lines */
  CAGEKIT_FORMAT_PLY = 2,   /* polygons only; no tags */
  CAGEKIT_FORMAT_OFF = 3,   /* polygons only; no tags */
  CAGEKIT_FORMAT_DRACO = 4, /* compressed; keeps polygons and cage tags */
  CAGEKIT_FORMAT_STL = 5,   /* read only (binary or ascii); bit-identical corners welded; writing
                             * is CAGEKIT_ERROR_UNSUPPORTED_FORMAT */
  CAGEKIT_FORMAT_MAX_ENUM = 0x7fffffff
} cagekit_file_format;

typedef struct cagekit_write_options {
  size_t struct_size;               /* sizeof(cagekit_write_options) */
  cagekit_file_format format;       /* AUTO: from the file extension (files only) */
  cagekit_bool32 ply_binary;        /* 1: binary little-endian PLY (default), 0: ascii */
  int draco_position_bits;          /* position quantization, 1..30 (default 14) */
  int draco_speed;                  /* 0 (smallest) .. 10 (fastest) (default 5) */
} cagekit_write_options;

#define CAGEKIT_WRITE_OPTIONS_INIT \
  { sizeof(cagekit_write_options), CAGEKIT_FORMAT_AUTO, 1, 14, 5 }

typedef struct cagekit_write_report {
  size_t struct_size;               /* sizeof(cagekit_write_report) */
  uint64_t bytes;                   /* size of the encoded file */
  double max_position_error;        /* largest position change the encoding caused (measured) */
} cagekit_write_report;

/* Reads a mesh (tags in the file are ignored) or a cage from a file or a memory buffer. Long
 * operation (progress, cancel).
 * Ownership: *out receives one reference (release it with cagekit_mesh_release or
 *   cagekit_cage_release); `path` and `data` are only read during the call.
 * Errors: INVALID_HANDLE (context), INVALID_ARGUMENT (out or path NULL, data NULL with a nonzero
 *   size, format out of range), IO (cannot open/read), PARSE (the message names the file and the
 *   line or byte offset of the first problem), UNSUPPORTED_FORMAT, LIMIT_EXCEEDED (hostile element
 *   counts), INVALID_MESH (cages only: crease, corner or hole tags that do not fit the mesh),
 *   CANCELLED, OUT_OF_MEMORY (also: the context's memory budget would be exceeded).
 * Threading: any thread (thread-safe). */
CAGEKIT_API cagekit_status cagekit_mesh_read_file(cagekit_context context, const char* path,
                                                  cagekit_file_format format, cagekit_mesh* out);
CAGEKIT_API cagekit_status cagekit_mesh_read_memory(cagekit_context context, const void* data, size_t size,
                                                    cagekit_file_format format, cagekit_mesh* out);
CAGEKIT_API cagekit_status cagekit_cage_read_file(cagekit_context context, const char* path,
                                                  cagekit_file_format format, cagekit_cage* out);
CAGEKIT_API cagekit_status cagekit_cage_read_memory(cagekit_context context, const void* data, size_t size,
                                                    cagekit_file_format format, cagekit_cage* out);

/* Writes to a file atomically (a temporary file renamed over `path` on success: a failed write
 * never leaves a partial file), or encodes into a new blob. options/report may be NULL, except
 * that writing to memory needs options->format to name a format (AUTO reads the file extension).
 * Writing a cage with tags to PLY or OFF drops the tags and logs a warning; STL cannot be
 * written.
 * Ownership: `path` is read during the call only; the memory calls' *out receives a new blob
 *   (one reference: release it with cagekit_blob_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (path or out NULL, bad struct_size of options or
 *   report, an option out of range, format AUTO when writing to memory), UNSUPPORTED_FORMAT
 *   (STL, or a file extension that names no format), INVALID_MESH (nothing the format can hold:
 *   no vertices or faces, a non-finite position, a face with fewer than 3 vertices or a bad index;
 *   Draco: a mesh it cannot store), IO (files), CANCELLED, OUT_OF_MEMORY.
 * Threading: reads the object; thread-safe. */
CAGEKIT_API cagekit_status cagekit_mesh_write_file(cagekit_mesh mesh, const char* path,
                                                   const cagekit_write_options* options,
                                                   cagekit_write_report* report);
CAGEKIT_API cagekit_status cagekit_mesh_write_memory(cagekit_mesh mesh, const cagekit_write_options* options,
                                                     cagekit_blob* out, cagekit_write_report* report);
CAGEKIT_API cagekit_status cagekit_cage_write_file(cagekit_cage cage, const char* path,
                                                   const cagekit_write_options* options,
                                                   cagekit_write_report* report);
CAGEKIT_API cagekit_status cagekit_cage_write_memory(cagekit_cage cage, const cagekit_write_options* options,
                                                     cagekit_blob* out, cagekit_write_report* report);

/* ------------------------------------------------------------------------------------------ */
/* Cage: a Catmull-Clark control mesh with crease tags                                        */
/* ------------------------------------------------------------------------------------------ */

/* Sharpness of an infinitely sharp crease or corner (the thesis's binary tag). Values in
 * (0, CAGEKIT_SHARP) are OpenSubdiv semi-sharp creases; values >= CAGEKIT_SHARP are infinite. */
#define CAGEKIT_SHARP 10.0f

typedef enum cagekit_boundary_rule {
  /* Boundary edges are infinitely sharp; boundary vertices follow the crease rules and are not
   * pinned (the thesis's rule, §2.2.1). The default. */
  CAGEKIT_BOUNDARY_EDGES_ONLY = 0,
  /* As above, and boundary vertices with only two incident edges are pinned corners. */
  CAGEKIT_BOUNDARY_EDGES_AND_CORNERS = 1,
  CAGEKIT_BOUNDARY_MAX_ENUM = 0x7fffffff
} cagekit_boundary_rule;

/* Creates a cage whose control mesh is a copy of `mesh`, with no tags and the default boundary
 * rule. The mesh must be valid (cagekit_mesh_validate).
 * Ownership: *out receives one reference (release it with cagekit_cage_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL), INVALID_MESH (the mesh is not valid: the
 *   first problem is in the message), OUT_OF_MEMORY.
 * Threading: reads `mesh`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_cage_create(cagekit_mesh mesh, cagekit_cage* out);
/* Adds a reference (retain) or drops one (release; the last one destroys the cage). NULL is
 * ignored.
 * Errors: none.
 * Threading: any thread (the reference count is atomic). */
CAGEKIT_API void cagekit_cage_retain(cagekit_cage cage);
CAGEKIT_API void cagekit_cage_release(cagekit_cage cage);

/* A new mesh handle holding a copy of the cage's control mesh.
 * Ownership: *out receives one reference (release it with cagekit_mesh_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL), OUT_OF_MEMORY.
 * Threading: reads `cage`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_cage_get_mesh(cagekit_cage cage, cagekit_mesh* out);

/* Replaces the crease tags: `count` edges given as vertex pairs (2 * count indices, each pair
 * an edge of the control mesh, either orientation) with a sharpness each (`sharpness` may be
 * NULL: all CAGEKIT_SHARP). A sharpness of 0 removes the tag.
 * Ownership: the arrays are read during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (vertex_pairs NULL with a nonzero count; naming the
 *   first pair that is not an edge or a sharpness that is negative or not finite; the tags are
 *   then unchanged), OUT_OF_MEMORY.
 * Threading: modifies `cage`: one thread at a time, with no other call on the cage meanwhile. */
CAGEKIT_API cagekit_status cagekit_cage_set_creases(cagekit_cage cage, uint32_t count, const uint32_t* vertex_pairs,
                                                    const float* sharpness);
/* Reads the crease tags. Two-call (Buffers) over creases, shared by vertex_pairs (2 per crease)
 * and sharpness.
 * Ownership: the arrays are the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (crease_count_out NULL), SIZE_INSUFFICIENT.
 * Threading: reads `cage`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_cage_get_creases(cagekit_cage cage, uint32_t crease_capacity,
                                                    uint32_t* crease_count_out, uint32_t* vertex_pairs,
                                                    float* sharpness);

/* Replaces the corner tags (vertex indices with sharpness; sharpness NULL = CAGEKIT_SHARP). A
 * sharpness of 0 removes the tag.
 * Ownership: the arrays are read during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (vertices NULL with a nonzero count; naming the first
 *   vertex index out of range or sharpness that is negative or not finite; the tags are then
 *   unchanged), OUT_OF_MEMORY.
 * Threading: modifies `cage`: one thread at a time, with no other call on the cage meanwhile. */
CAGEKIT_API cagekit_status cagekit_cage_set_corners(cagekit_cage cage, uint32_t count, const uint32_t* vertices,
                                                    const float* sharpness);
/* Reads the corner tags. Two-call (Buffers) over corners, shared by vertices and sharpness.
 * Ownership: the arrays are the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (corner_count_out NULL), SIZE_INSUFFICIENT.
 * Threading: reads `cage`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_cage_get_corners(cagekit_cage cage, uint32_t corner_capacity,
                                                    uint32_t* corner_count_out, uint32_t* vertices, float* sharpness);

/* Replaces the set of hole faces (faces that are not part of the limit surface). The set is kept
 * sorted, without repeats.
 * Ownership: `faces` is read during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (faces NULL with a nonzero count; naming the first face
 *   index out of range; the holes are then unchanged), OUT_OF_MEMORY.
 * Threading: modifies `cage`: one thread at a time, with no other call on the cage meanwhile. */
CAGEKIT_API cagekit_status cagekit_cage_set_holes(cagekit_cage cage, uint32_t count, const uint32_t* faces);
/* Reads the hole faces. Two-call (Buffers) over holes.
 * Ownership: `faces` is the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (hole_count_out NULL, faces NULL with a nonzero
 *   capacity), SIZE_INSUFFICIENT.
 * Threading: reads `cage`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_cage_get_holes(cagekit_cage cage, uint32_t hole_capacity, uint32_t* hole_count_out,
                                                  uint32_t* faces);

/* Sets / gets the boundary interpolation rule.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (set: rule out of range; get: rule NULL).
 * Threading: set modifies `cage` (one thread at a time, with no other call on the cage
 *   meanwhile); get reads it (thread-safe). */
CAGEKIT_API cagekit_status cagekit_cage_set_boundary_rule(cagekit_cage cage, cagekit_boundary_rule rule);
CAGEKIT_API cagekit_status cagekit_cage_get_boundary_rule(cagekit_cage cage, cagekit_boundary_rule* rule);

/* Statistics of the control mesh plus tag counts, into *info.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (info NULL or bad struct_size), OUT_OF_MEMORY.
 * Threading: reads `cage`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_cage_get_info(cagekit_cage cage, cagekit_mesh_info* info);

/* ------------------------------------------------------------------------------------------ */
/* Catmull-Clark subdivision                                                                  */
/* ------------------------------------------------------------------------------------------ */

#define CAGEKIT_MAX_SUBDIVISION_LEVELS 8

typedef struct cagekit_subdivide_options {
  size_t struct_size;       /* sizeof(cagekit_subdivide_options) */
  uint32_t levels;          /* 0 .. CAGEKIT_MAX_SUBDIVISION_LEVELS (default 1) */
  cagekit_bool32 limit_positions; /* 1: move the refined vertices onto the limit surface */
} cagekit_subdivide_options;

#define CAGEKIT_SUBDIVIDE_OPTIONS_INIT { sizeof(cagekit_subdivide_options), 1, 0 }

/* Uniformly refines the cage `levels` times. The result is a new cage of quads whose tags are
 * the refined tags (an infinitely sharp edge's two halves stay infinitely sharp; semi-sharp
 * values decrease by 1 per level). options may be NULL (defaults). Long operation (progress,
 * cancel).
 * Ownership: *out receives one reference (release it with cagekit_cage_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL, bad struct_size, an option out of range,
 *   naming it), LIMIT_EXCEEDED (before allocating, when the result would exceed 2^31 indices),
 *   INVALID_MESH (a cage that cannot be subdivided), CANCELLED, OUT_OF_MEMORY.
 * Threading: reads `cage`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_cage_subdivide(cagekit_cage cage, const cagekit_subdivide_options* options,
                                                  cagekit_cage* out);

/* Limit-surface positions and unit normals of the cage's control vertices (xyz per vertex).
 * Two-call (Buffers) over vertices, shared by positions and normals.
 * Ownership: the arrays are the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (vertex_count_out NULL), SIZE_INSUFFICIENT,
 *   INVALID_MESH (a cage that cannot be subdivided), OUT_OF_MEMORY.
 * Threading: reads `cage`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_cage_get_limit_points(cagekit_cage cage, uint32_t vertex_capacity,
                                                         uint32_t* vertex_count_out, double* positions,
                                                         double* normals);

/* --- evaluation at any parametric location --- */

typedef struct cagekit_surface_options {
  size_t struct_size;       /* sizeof(cagekit_surface_options) */
  uint32_t isolation_level; /* adaptive isolation level, 1..10 (default 2). Smooth interior extraordinary
                               vertices are evaluated exactly (Stam) at any level. */
  uint32_t sharp_isolation_level; /* isolation around extraordinary vertices on creases/boundaries, which use
                                     Gregory end caps: exact patches beyond 2^-level of them, 1..10 (default 10) */
} cagekit_surface_options;

#define CAGEKIT_SURFACE_OPTIONS_INIT { sizeof(cagekit_surface_options), 2, 10 }

/* A parametric location on the limit surface. Faces are "ptex" faces: a quad of the cage is one
 * face with (u, v) in [0,1]^2, any other n-gon is n faces, one per corner (see
 * cagekit_surface_get_ptex_face). */
typedef struct cagekit_surface_location {
  uint32_t face;
  double u, v;
} cagekit_surface_location;

typedef struct cagekit_surface_point {
  double position[3];
  double du[3], dv[3];             /* first derivatives */
  double duu[3], duv[3], dvv[3];   /* second derivatives */
} cagekit_surface_point;

/* Builds an evaluator for the limit surface of `cage` (a snapshot: later changes to the cage do
 * not affect it). options may be NULL (defaults). Long operation (progress, cancel).
 * Ownership: *out receives one reference (release it with cagekit_surface_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL, bad struct_size, an option out of range,
 *   naming it), INVALID_MESH (a cage whose limit surface cannot be built), CANCELLED,
 *   OUT_OF_MEMORY.
 * Threading: reads `cage`; thread-safe. The surface is immutable: all its functions are
 *   read-only and may run concurrently from many threads. */
CAGEKIT_API cagekit_status cagekit_surface_create(cagekit_cage cage, const cagekit_surface_options* options,
                                                  cagekit_surface* out);
/* Adds a reference (retain) or drops one (release; the last one destroys the surface). NULL is
 * ignored.
 * Errors: none.
 * Threading: any thread (the reference count is atomic). */
CAGEKIT_API void cagekit_surface_retain(cagekit_surface surface);
CAGEKIT_API void cagekit_surface_release(cagekit_surface surface);

/* Number of ptex faces and of control vertices. Either pointer may be NULL.
 * Errors: INVALID_HANDLE.
 * Threading: reads `surface`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_surface_get_counts(cagekit_surface surface, uint32_t* ptex_face_count,
                                                      uint32_t* control_vertex_count);
/* The ptex face of corner `corner` of cage face `cage_face` (corner must be 0 for quads).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (ptex_face NULL, cage_face out of range, a corner the
 *   face has no ptex face for).
 * Threading: reads `surface`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_surface_get_ptex_face(cagekit_surface surface, uint32_t cage_face,
                                                         uint32_t corner, uint32_t* ptex_face);

/* Evaluates `count` locations into `points` (count entries). control_positions: NULL to use the
 * cage's positions, or 3 * control_vertex_count doubles (moved control vertices).
 * Ownership: control_positions and locations are read during the call only; `points` is the
 *   caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (locations or points NULL with a nonzero count; naming
 *   the first location with a bad face index or (u, v) outside [0,1]^2 or NaN, or on a hole face,
 *   which has no limit surface), OUT_OF_MEMORY.
 * Threading: reads `surface`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_surface_evaluate(cagekit_surface surface, const double* control_positions,
                                                    uint32_t count, const cagekit_surface_location* locations,
                                                    cagekit_surface_point* points);

/* The basis functions phi_j (thesis (2.24)) that are non-zero at `location`, and their
 * derivatives: position = sum_k w[k] * control[indices[k]], du = sum_k wu[k] * control[...], etc.
 * Two-call (Buffers) over the control vertices involved, shared by the seven arrays.
 * Ownership: `location` is read during the call only; the arrays are the caller's, written during
 *   the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (location NULL or bad as in cagekit_surface_evaluate,
 *   basis_count_out NULL), SIZE_INSUFFICIENT, OUT_OF_MEMORY.
 * Threading: reads `surface`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_surface_evaluate_basis(cagekit_surface surface,
                                                          const cagekit_surface_location* location,
                                                          uint32_t basis_capacity, uint32_t* basis_count_out,
                                                          uint32_t* indices, double* w, double* wu, double* wv,
                                                          double* wuu, double* wuv, double* wvv);

/* ------------------------------------------------------------------------------------------ */
/* Structure-preserving simplification (thesis chapter 3)                                     */
/* ------------------------------------------------------------------------------------------ */

/* A progressive hierarchy of polygonal meshes made by greedy face merging (L2/L2,1 priority,
 * every face injectively projectable to its proxy plane, valence-2 contour decimation), from
 * the input (level 0) to the coarsest level where no valid operation is left. Faces are
 * general polygons, possibly with holes; their vertices are always input vertices. */
typedef struct cagekit_hierarchy_t* cagekit_hierarchy;

typedef struct cagekit_simplify_options {
  size_t struct_size;           /* sizeof(cagekit_simplify_options) */
  double tie_break_epsilon;     /* weight of the valence/angle tie-break (3.8), >= 0 (default 0.01) */
  /* The host's sharp edges (e.g. the edges a Blender user marked sharp): sharp_edge_count edges
   * of the input mesh as vertex pairs, 2 * sharp_edge_count indices. They stay borders of every level
   * (no merge crosses one; a line of them is straightened like any border), and the hierarchy
   * keeps them: cagekit_hierarchy_build_cage tags the cage edges along them as creases.
   * NULL with 0 (default). Read during the call; a pair that is not an edge of the mesh is
   * INVALID_ARGUMENT. */
  const uint32_t* sharp_edges;
  uint32_t sharp_edge_count;
} cagekit_simplify_options;

#define CAGEKIT_SIMPLIFY_OPTIONS_INIT { sizeof(cagekit_simplify_options), 0.01, NULL, 0 }

/* Simplifies `mesh` to its coarsest level, recording every operation. The mesh must be valid
 * apart from unreferenced vertices (cagekit_mesh_repair fixes most problems). The hierarchy
 * starts at its coarsest level. options may be NULL (defaults). Long operation (progress, cancel).
 * Ownership: *out receives one reference (release it with cagekit_hierarchy_release); the
 *   hierarchy keeps its own copy of the mesh; the options' sharp_edges are read during the call.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL, bad struct_size, an option out of range or
 *   a sharp-edge pair that is not an edge, naming it), INVALID_MESH (naming the problem),
 *   CANCELLED, OUT_OF_MEMORY.
 * Threading: reads `mesh`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_hierarchy_create(cagekit_mesh mesh, const cagekit_simplify_options* options,
                                                    cagekit_hierarchy* out);
/* Adds a reference (retain) or drops one (release; the last one destroys the hierarchy). NULL is
 * ignored.
 * Errors: none.
 * Threading: any thread (the reference count is atomic). */
CAGEKIT_API void cagekit_hierarchy_retain(cagekit_hierarchy hierarchy);
CAGEKIT_API void cagekit_hierarchy_release(cagekit_hierarchy hierarchy);

/* Number of levels (level 0 = the input).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (count NULL).
 * Threading: reads `hierarchy`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_hierarchy_get_level_count(cagekit_hierarchy hierarchy, uint32_t* count);

typedef struct cagekit_level_info {
  size_t struct_size;           /* sizeof(cagekit_level_info) */
  uint64_t faces;               /* polygonal faces of the level */
  uint64_t vertices;            /* input vertices the level uses */
  double error;                 /* normalised priority of the operation that made the level (0 for level 0) */
} cagekit_level_info;

/* Counts of any level, without moving there.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (info NULL or bad struct_size, level not below the
 *   level count).
 * Threading: reads `hierarchy`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_hierarchy_get_level_info(cagekit_hierarchy hierarchy, uint32_t level,
                                                            cagekit_level_info* info);

typedef enum cagekit_level_query {
  CAGEKIT_LEVEL_BY_FACES = 0,    /* the finest level with at most `value` faces */
  CAGEKIT_LEVEL_BY_VERTICES = 1, /* the finest level with at most `value` vertices */
  CAGEKIT_LEVEL_BY_ERROR = 2,    /* the coarsest level whose error is <= `value` */
  CAGEKIT_LEVEL_QUERY_MAX_ENUM = 0x7fffffff
} cagekit_level_query;

/* Finds a level (the coarsest level when none has so few faces/vertices).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (level NULL, value negative or NaN, query out of
 *   range).
 * Threading: reads `hierarchy`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_hierarchy_find_level(cagekit_hierarchy hierarchy, cagekit_level_query query,
                                                        double value, uint32_t* level);

/* Moves to `level`, applying or undoing recorded operations (constant time per level stepped,
 * plus one pass to refresh the current level's faces).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (level not below the level count), OUT_OF_MEMORY.
 * Threading: modifies `hierarchy`: one thread at a time, with no other call on the hierarchy
 *   meanwhile. */
CAGEKIT_API cagekit_status cagekit_hierarchy_set_level(cagekit_hierarchy hierarchy, uint32_t level);
/* The current level.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (level NULL).
 * Threading: reads `hierarchy`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_hierarchy_get_current_level(cagekit_hierarchy hierarchy, uint32_t* level);

typedef struct cagekit_polygonal_level_info {
  size_t struct_size;           /* sizeof(cagekit_polygonal_level_info) */
  uint32_t level;
  uint64_t faces, vertices, faces_with_holes;
  uint64_t invalid_faces;       /* faces failing the injectivity test, re-checked independently (0 expected) */
  double l2_error;              /* sum of the faces' (3.3) terms, lengths in units of sqrt(the input's mean
                                   face area) */
  double l21_error;             /* sum of the faces' (3.4) terms, normalised */
} cagekit_polygonal_level_info;

/* Summary of the current level, into *info.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (info NULL or bad struct_size), OUT_OF_MEMORY.
 * Threading: reads `hierarchy`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_hierarchy_get_current_info(cagekit_hierarchy hierarchy,
                                                              cagekit_polygonal_level_info* info);

/* The current level's faces: for face f, loops_per_face[f] loops (the first is the outer loop,
 * counter-clockwise seen from outside; the others are holes); for each loop in order,
 * loop_sizes[l] INPUT vertex indices in loop_vertices. Two-call (Buffers) on each array, over
 * faces, loops and indices; every count is written before any capacity is checked.
 * Ownership: the arrays are the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (a count pointer NULL, an array NULL with a nonzero
 *   capacity), SIZE_INSUFFICIENT.
 * Threading: reads `hierarchy`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_hierarchy_get_faces(cagekit_hierarchy hierarchy, uint32_t face_capacity,
                                                       uint32_t* face_count_out, uint32_t* loops_per_face,
                                                       uint32_t loop_capacity, uint32_t* loop_count_out,
                                                       uint32_t* loop_sizes, uint64_t index_capacity,
                                                       uint64_t* index_count_out, uint32_t* loop_vertices);

/* The cluster map of the current level: for each input face, the index of the level face that
 * contains it. Two-call (Buffers) over input faces.
 * Ownership: cluster_of_input_face is the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (input_face_count_out NULL, cluster_of_input_face NULL
 *   with a nonzero capacity), SIZE_INSUFFICIENT.
 * Threading: reads `hierarchy`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_hierarchy_get_clusters(cagekit_hierarchy hierarchy, uint32_t input_face_capacity,
                                                          uint32_t* input_face_count_out,
                                                          uint32_t* cluster_of_input_face);

/* The current level as a polygon mesh over the input vertices it uses (renumbered densely):
 * faces without holes as they are, faces with holes split into their constrained Delaunay
 * triangles (a polygon mesh cannot hold holes).
 * Ownership: *out receives one reference (release it with cagekit_mesh_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL), OUT_OF_MEMORY.
 * Threading: reads `hierarchy`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_hierarchy_get_polygon_mesh(cagekit_hierarchy hierarchy, cagekit_mesh* out);

/* As cagekit_hierarchy_get_polygon_mesh, with the contours refined: chapter 3 removes every
 * valence-2 contour vertex, so a level edge is a straight chord across a curved border between two
 * clusters of input faces; this puts border vertices back (Douglas-Peucker on each border chain,
 * the same vertices for both faces of an edge) while the border strays farther than
 * chord_tolerance * (input bounding-box diagonal) from the chord. A face whose refined loops would
 * not project injectively gets its edges' tolerance doubled until they do. Same faces and clusters,
 * more vertices (all input vertices); at the coarsest levels a much smaller distance to the input
 * (VSA's meshing step does the same). chord_tolerance: finite, > 0 (e.g. 5 mean input edge lengths,
 * VSA's default).
 * Ownership: *out receives one reference (release it with cagekit_mesh_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL, chord_tolerance not finite or not > 0),
 *   OUT_OF_MEMORY.
 * Threading: reads `hierarchy`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_hierarchy_get_refined_polygon_mesh(cagekit_hierarchy hierarchy,
                                                                      double chord_tolerance, cagekit_mesh* out);

/* Which cage edges between two clusters become infinitely sharp creases. */
typedef enum cagekit_crease_rule {
  /* Where the scan itself is sharp (the default): at least 90 % of the length of the input edges
   * along the cage edge's border between the two clusters run along sharp input features, the
   * one definition all methods use (both remeshers follow it too): input edges whose two faces'
   * normals differ by more than feature_angle_degrees, confirmed by the mean normals of the faces
   * around the edge on either side differing by more than half that angle (a scan's noise is not
   * sharp), on connected feature lines of at least 2 % of the bounding-box diagonal. Organic
   * scans get smooth cages, CAD parts keep their edges. */
  CAGEKIT_CREASES_SHARP_INPUT = 0,
  /* The thesis's rule (section 3.4): the two clusters' normals differ by more than
   * crease_angle_degrees (and, with input_crease_angle_degrees >= 0, the input's mean dihedral
   * angle along their border exceeds that). Faceted "smooth" surfaces on organic scans. */
  CAGEKIT_CREASES_CLUSTER_ANGLE = 1,
  CAGEKIT_CREASE_RULE_MAX_ENUM = 0x7fffffff
} cagekit_crease_rule;

typedef struct cagekit_cage_options {
  size_t struct_size;           /* sizeof(cagekit_cage_options) */
  double crease_angle_degrees;  /* CLUSTER_ANGLE: tag cage edges between clusters whose normals differ more
                                   (default 30; < 0: never). SHARP_INPUT: unused */
  cagekit_bool32 tag_boundary_edges; /* 1: tag the mesh-boundary edges as creases (default 1) */
  uint32_t exact_partition_limit; /* faces up to this many vertices are partitioned optimally (default 20) */
  /* CLUSTER_ANGLE: also require the input itself to be sharp along the two clusters' border:
   * the length-weighted mean angle between the normals of the input faces on either side of the
   * input edges that separate the clusters must exceed this (degrees). Default -1: off (the
   * clusters' normals alone decide). SHARP_INPUT: unused. */
  double input_crease_angle_degrees;
  cagekit_crease_rule crease_rule;  /* default CAGEKIT_CREASES_SHARP_INPUT */
  double feature_angle_degrees;     /* SHARP_INPUT: the dihedral angle above which an input edge may be a
                                       sharp feature, in [0, 180] (default 40; the remeshers' default too) */
  /* The host's sharp edges (e.g. the edges a Blender user marked sharp): sharp_edge_count edges
   * of the input mesh as vertex pairs, 2 * sharp_edge_count indices. SHARP_INPUT: sharp features whatever
   * their angle, so the cage edges along them become creases (with those the hierarchy was made
   * with). CLUSTER_ANGLE: unused (the thesis's rule alone).
   * NULL with 0 (default). Read during the call; a pair that is not an edge of the mesh is
   * INVALID_ARGUMENT. */
  const uint32_t* sharp_edges;
  uint32_t sharp_edge_count;
} cagekit_cage_options;

#define CAGEKIT_CAGE_OPTIONS_INIT { sizeof(cagekit_cage_options), 30.0, 1, 20, -1.0, CAGEKIT_CREASES_SHARP_INPUT, 40.0, NULL, 0 }

typedef struct cagekit_cage_report {
  size_t struct_size;           /* sizeof(cagekit_cage_report) */
  uint64_t quads, triangles, pentagons, other_polygons;
  uint64_t creases;
  uint64_t non_optimal_faces;   /* level faces whose partition is not proven optimal */
  uint64_t non_manifold_edges;  /* cage edges used by more than two faces (0 expected) */
  uint64_t diagonals_flipped;   /* diagonals flipped out of a face because another face joined
                                   their two vertices (the face was partitioned again) */
  uint64_t cells_merged;        /* such diagonals no flip removed: their two cells became one */
} cagekit_cage_report;

/* Partitions every face of the current level into convex quad-dominant cells (only diagonals
 * of its constrained Delaunay triangulation, no new vertices; thesis §3.4) and returns the
 * control cage with crease tags. options may be NULL (defaults); report may be NULL. Long
 * operation (progress, cancel; stage "cage").
 * Ownership: *out receives one reference (release it with cagekit_cage_release); the options'
 *   sharp_edges are read during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL, bad struct_size of options or report, an
 *   option out of range or a sharp-edge pair that is not an edge, naming it), CANCELLED,
 *   OUT_OF_MEMORY.
 * Threading: reads `hierarchy`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_hierarchy_build_cage(cagekit_hierarchy hierarchy, const cagekit_cage_options* options,
                                                        cagekit_cage* out, cagekit_cage_report* report);

typedef struct cagekit_approximation_error {
  size_t struct_size;           /* sizeof(cagekit_approximation_error) */
  double hausdorff_rel;         /* max distance input vertex -> approximation (fan-triangulated) / input bbox diagonal */
  double hausdorff_sym_rel;     /* symmetric: also approximation samples -> input surface */
  double mean_rel;              /* mean input-vertex distance / diagonal */
} cagekit_approximation_error;

/* Distances between `input` and `approximation` (e.g. a simplified level or a cage's control
 * mesh), relative to the input's bounding-box diagonal, into *error. Long operation (progress,
 * cancel).
 * Errors: INVALID_HANDLE (input or approximation), INVALID_ARGUMENT (error NULL or bad
 *   struct_size), CANCELLED, OUT_OF_MEMORY.
 * Threading: reads both meshes; thread-safe. */
CAGEKIT_API cagekit_status cagekit_mesh_measure_error(cagekit_mesh input, cagekit_mesh approximation,
                                                      cagekit_approximation_error* error);

/* ------------------------------------------------------------------------------------------ */
/* Remeshing (thesis chapter 5: anisotropic; chapter 6: two-step quad-dominant)              */
/* ------------------------------------------------------------------------------------------ */

/* Two remeshers turn a triangle mesh into a quad-dominant cage, each with its own options and
 * report: cagekit_mesh_remesh_anisotropic (thesis ch. 5) samples the surface with lines of
 * principal curvature (plus feature and boundary lines) and meshes their intersections, so the
 * cage's edges follow the principal directions;
 * cagekit_mesh_remesh_quad (thesis ch. 6) segments the surface into nearly flat regions (VSA),
 * samples their boundaries (shared by both neighbours), lays out each region by an energy-driven
 * selection of curves in a conformal parameterisation (weights of Table 6.1), relaxes, maps back
 * to the surface and glues the regions. Both tag the cage edges on
 * feature lines / sharp region boundaries as infinitely sharp creases. */

/* Figures of a remeshed cage, the same for both remeshers. */
typedef struct cagekit_remesh_quality {
  uint64_t faces, vertices, quads;
  uint64_t interior_vertices;     /* vertices not on a boundary edge of the output */
  uint64_t valence4_vertices;     /* interior vertices with 4 edges */
  uint32_t max_face_valence, max_vertex_valence;
  uint64_t creases;               /* cage edges tagged infinitely sharp */
  double min_scaled_jacobian;     /* min over face corners of sin(corner angle) (the scaled Jacobian of a quad
                                     corner); T-joint vertices (within 10° of straight) are not corners;
                                     < 0 only at a concave corner */
  double seconds;                 /* whole call */
} cagekit_remesh_quality;

typedef struct cagekit_anisotropic_options {
  size_t struct_size;             /* sizeof(cagekit_anisotropic_options) */
  double tolerance;               /* approximation tolerance relative to the bbox diagonal, in (0, 1]; the line
                                     spacing follows the chord-height rule (5.10) (default 0.002) */
  double feature_angle_degrees;   /* edges whose faces' normals differ by more than this become feature lines
                                     and crease tags; < 0: none; <= 180 (default 40) */
  uint32_t max_face_valence;      /* faces with more corners are split, 3..1000000 (default 5) */
  uint32_t threads;               /* worker threads of the curvature field, 0..1024; 0 = all cores (default) */
  double curvature_radius;        /* curvature averaging radius relative to the bbox diagonal (thesis: 0.01),
                                     capped at 6 mean edge lengths (bounded cost on dense meshes); 0: three
                                     mean edge lengths; in [0, 1] (default 0.01) */
  /* The host's sharp edges (e.g. the edges a Blender user marked sharp): sharp_edge_count edges
   * of the input mesh as vertex pairs, 2 * sharp_edge_count indices. Feature lines (sampled as lines,
   * tagged as creases) whatever their angle, also with feature_angle_degrees < 0.
   * NULL with 0 (default). Read during the call; a pair that is not an edge of the mesh is
   * INVALID_ARGUMENT. */
  const uint32_t* sharp_edges;
  uint32_t sharp_edge_count;
} cagekit_anisotropic_options;

#define CAGEKIT_ANISOTROPIC_OPTIONS_INIT { sizeof(cagekit_anisotropic_options), 0.002, 40.0, 5, 0, 0.01, NULL, 0 }

typedef struct cagekit_anisotropic_report {
  size_t struct_size;             /* sizeof(cagekit_anisotropic_report) */
  cagekit_remesh_quality quality;
  uint64_t regions;               /* connected regions of confident input faces */
  uint64_t lines;                 /* sampled lines of all types */
  uint64_t holes;                 /* half-edges that could not be closed into faces (0 expected) */
  double mean_alignment_deg;      /* mean angle between the output edges along curvature lines and the nearer
                                     principal direction (mean of the two ends' directions, i.e. the tangent
                                     at the middle of a curved edge), over edges whose ends lie on confident
                                     faces (Λ >= cos π/6) */
} cagekit_anisotropic_report;

typedef struct cagekit_quad_remesh_options {
  size_t struct_size;             /* sizeof(cagekit_quad_remesh_options) */
  double edge_length;             /* δ, the spacing of the samples on the region boundaries relative to the
                                     bbox diagonal, in (0, 1] (thesis: 0.02-0.10; default 0.05) */
  uint32_t regions;               /* number of VSA regions |S|, 0..1000000; 0: the first count (up to 200)
                                     whose L2,1 error / area <= region_tolerance (default 30) */
  double region_tolerance;        /* used with regions = 0: a mean of |n_f - N|^2, finite and >= 0 (default
                                     0.01) */
  double crease_angle_degrees;    /* region boundaries whose input edges' length-weighted mean dihedral angle
                                     exceeds this become crease tags; < 0: none; <= 180 (default 40) */
  double triangle_weight;         /* w_tri of Table 6.1, the cost of a triangle, finite and > 0 (default 40) */
  double pentagon_weight;         /* w_PT, the cost of a pentagon, finite and > 0 (default 40) */
  double t_joint_weight;          /* w_T, the cost of a T-joint, finite and > 0 (default 100) */
  uint32_t refinement_passes;     /* sweeps of the sample-count refinement (not in the thesis): an arc next to
                                     an irregular region gets one sample more or fewer when re-selecting its
                                     regions makes the cage more regular there; 0..16. 0: off (faster; a few
                                     points fewer quads / valence-4 vertices) (default 1) */
  uint32_t threads;               /* workers over the regions of the curve selection, 0..1024; 0 = all cores
                                     (default) */
  /* The host's control of the segmentation. Face ids are the input mesh's (a polygon stands for
   * all of its triangles). The arrays are read during the call only (the caller keeps them). */
  const uint32_t* seed_faces;     /* faces that each start a VSA region (they then relax like the others);
                                     distinct, not pinned. NULL with seed_face_count 0 (default) */
  uint32_t seed_face_count;
  uint32_t pinned_region_count;   /* regions the host fixes: region k is the faces
                                     pinned_faces[pinned_region_offsets[k] .. pinned_region_offsets[k + 1]),
                                     edge-connected, disjoint, never changed by the segmentation and counted
                                     in `regions` (default 0) */
  const uint32_t* pinned_region_offsets; /* pinned_region_count + 1 non-decreasing offsets, first 0 */
  const uint32_t* pinned_faces;
  /* The host's sharp edges (e.g. the edges a Blender user marked sharp): sharp_edge_count edges
   * of the input mesh as vertex pairs, 2 * sharp_edge_count indices. Region borders: no VSA region grows
   * across one and each patch they enclose gets a region of its own (the count is raised to the
   * patches, as to the components); region boundaries along them are tagged as creases, also
   * with crease_angle_degrees < 0.
   * NULL with 0 (default). Read during the call; a pair that is not an edge of the mesh is
   * INVALID_ARGUMENT. */
  const uint32_t* sharp_edges;
  uint32_t sharp_edge_count;
} cagekit_quad_remesh_options;

#define CAGEKIT_QUAD_REMESH_OPTIONS_INIT                                                                   \
  { sizeof(cagekit_quad_remesh_options), 0.05, 30, 0.01, 40.0, 40.0, 40.0, 100.0, 1, 0, NULL, 0, 0, NULL, NULL, NULL, 0 }

typedef struct cagekit_quad_remesh_report {
  size_t struct_size;             /* sizeof(cagekit_quad_remesh_report) */
  cagekit_remesh_quality quality;
  uint64_t regions;               /* VSA regions used, after the splits below */
  uint64_t arcs;                  /* region-boundary arcs */
  uint64_t requested_regions;     /* the count asked for (`regions` of the options, or 200 by tolerance):
                                     raised to the mesh's connected components and capped at its triangles
                                     when no regions are pinned or seeded */
  uint64_t split_regions;         /* regions split: closed, with a handle, a folding map, or a failed layout */
  uint64_t merged_regions;        /* sliver regions (their sample loop has no area) merged into a neighbour */
  uint64_t layout_retries;        /* layouts redone after such splits or merges (at most 3) */
  uint64_t mended_faces;          /* faces of the final layout repaired in place: where two regions' faces
                                     coincided (thin parts one face wide per side) a vertex was added inside
                                     one of them; a face repeating a vertex was cut there */
  uint64_t partitioned_regions;   /* regions whose layout still failed after the retries, laid out instead by
                                     the quad-dominant partition of their polygon of boundary samples (no
                                     inner vertices); 0 in most results */
  uint64_t reseeded_regions;      /* 0 in most results; else no layout of the first segmentation came out
                                     valid (after every retry and the partition above), and the cage is the
                                     layout of a new segmentation with this many regions (10/3, then 20/3
                                     times the first count); the figures above are that layout's */
} cagekit_quad_remesh_report;

/* Remeshes `mesh` into a new cage: a valid oriented 2-manifold polygon mesh whose edges on
 * feature lines (anisotropic) or sharp region boundaries (quad) are tagged as infinitely sharp
 * creases. The mesh must be an oriented 2-manifold (boundary allowed) with finite positions;
 * faces with more than 3 vertices are fan-triangulated first. `options` NULL: the defaults;
 * `report` may be NULL. Long operations (progress stages anisotropic "curvature field",
 * "curvature lines", "meshing"; quad "vsa segmentation", "remesh constraints", "quad region
 * selection", "post-processing"; cancel).
 * Ownership: *out receives one reference (release it with cagekit_cage_release); the options'
 *   arrays are read during the call only.
 * Errors: INVALID_HANDLE; INVALID_ARGUMENT (out NULL, a bad struct_size, an option out of its
 *   range, naming it; quad: with pinned regions or seeds, more regions than triangles or fewer
 *   than the mesh's connected components — without them the count is adjusted and reported);
 *   INVALID_MESH (naming the problem: faces with < 3 or repeated vertices, bad indices,
 *   non-manifold or inconsistently oriented edges, non-finite positions, an empty or zero-extent
 *   mesh; anisotropic: no two lines intersect (too large a tolerance for the mesh's size); quad: a
 *   pinned region with a handle — other regions that are closed, have a handle or fold are
 *   split); CANCELLED; OUT_OF_MEMORY; INTERNAL (the result failed its validity check after the
 *   retries, naming the region).
 * Threading: reads `mesh`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_mesh_remesh_anisotropic(cagekit_mesh mesh, const cagekit_anisotropic_options* options,
                                                           cagekit_cage* out, cagekit_anisotropic_report* report);
CAGEKIT_API cagekit_status cagekit_mesh_remesh_quad(cagekit_mesh mesh, const cagekit_quad_remesh_options* options,
                                                    cagekit_cage* out, cagekit_quad_remesh_report* report);

/* ------------------------------------------------------------------------------------------ */
/* Fitting the limit surface to a scan (thesis chapter 7)                                     */
/* ------------------------------------------------------------------------------------------ */

/* Where the parameterisation step looks for the samples' foot points. */
typedef enum cagekit_projection_mode {
  /* Closest points on the exact limit surface (Newton/Brent search across ptex faces, thesis
   * §7.4). The default. */
  CAGEKIT_PROJECTION_EXACT = 0,
  /* Closest points on the piecewise-linear limit mesh of subdivision level 2 ([HDD+94]):
   * faster per pass, less accurate; a reference, not the default. */
  CAGEKIT_PROJECTION_PIECEWISE_LINEAR = 1,
  CAGEKIT_PROJECTION_MAX_ENUM = 0x7fffffff
} cagekit_projection_mode;

/* How the control-vertex step solves its linear least-squares problem. */
typedef enum cagekit_lsq_solver {
  CAGEKIT_LSQ_DIRECT = 0, /* sparse Cholesky (LDL^T) of the normal equations (the default) */
  CAGEKIT_LSQ_CGLS = 1,   /* conjugate gradients on the normal equations, warm-started */
  CAGEKIT_LSQ_MAX_ENUM = 0x7fffffff
} cagekit_lsq_solver;

typedef struct cagekit_fit_options {
  size_t struct_size;           /* sizeof(cagekit_fit_options) */
  uint32_t max_passes;          /* control-vertex steps at most, 0..100000 (default 5); 0 = only measure
                                   the initial cage */
  double tolerance;             /* stop when L2 drops by less than tolerance * L2 in a pass (thesis (7.2),
                                   relative), finite and >= 0 (default 1e-4); 0 = run max_passes steps */
  double fairing;               /* weight of an umbrella-Laplacian fairing term relative to the mean diagonal
                                   of A^T A, finite and >= 0 (default 0: none, as in the thesis) */
  double tangential_weight;     /* weight of the residuals' tangential part in the control-vertex step,
                                   in [0, 1] (default 1: point-distance least squares, the thesis's) */
  cagekit_bool32 keep_crease_vertices; /* 1: vertices on infinitely sharp crease edges and corner-tagged vertices
                                   keep their positions (cages built on the scan); 0 (default): all move */
  cagekit_projection_mode projection; /* default CAGEKIT_PROJECTION_EXACT */
  cagekit_lsq_solver solver;    /* default CAGEKIT_LSQ_DIRECT */
  uint32_t threads;             /* worker threads of the projection and assembly steps, 0..1024;
                                   0 (default) = the number of hardware threads */
  uint32_t max_projection_steps; /* update steps per closest-point search, 0..100000 (default 500) */
  double projection_epsilon;    /* a search stops when its gradient, in ptex parameter units, is below
                                   this; finite and > 0 (default 1e-6) */
  uint32_t projection_seed_resolution; /* grid quads per ptex face side of the piecewise-linear limit
                                          mesh that seeds the searches, 1..64 (default 4) */
  double weak_support_fraction; /* control vertices whose support holds little data (the sum of their
                                   squared basis values over the scan vertices is below this fraction
                                   of its mean over the free vertices; none at all included) get their
                                   own umbrella-Laplacian fairing row, so they stay near the average of
                                   their neighbours instead of flying off after a few distant samples;
                                   finite and >= 0 (default 0.05; 0 = off: such vertices are free, as in
                                   the thesis) */
  double weak_fairing;          /* weight of those rows relative to the mean diagonal of A^T A, finite and
                                   >= 0 (default 1) */
  cagekit_bool32 select_best_two_sided; /* 1 (default): return the state with the lowest two-sided RMS distance
                                    (scan -> surface and surface -> scan, cagekit_fit_two_sided), not the
                                    last one; 0: the last state kept (the thesis's rule alone) */
  double reverse_sample_factor; /* two-sided least squares (not in the thesis): each step also pulls the
                                   limit surface's grid points (projection_seed_resolution + 1)^2 per ptex
                                   face) that lie farther than this x the scan -> surface RMS from the
                                   scan towards their closest scan point, and steps are accepted and
                                   stopped by the two-sided RMS instead of L2. Needs the scan's faces
                                   (ignored for bare points). Finite, 0..100 (default 0: off, the thesis's
                                   one-sided fit; cagekit_scan_to_cage's last phase uses 3) */
  double crease_feature_reach;  /* crease-feature rows (not in the thesis): each step also pulls the points
                                   of the limit surface's crease curves (along the cage's infinitely sharp
                                   edges with two faces) that lie within this x the scan's bounding-box
                                   diagonal of one of the scan's sharp edges (the sharp input features of
                                   cagekit_scan_to_cage) onto their closest point of it, so that crease
                                   curves stay on the sharp edges instead of sliding along the surface.
                                   Finite, 0..1 (default 0.02; 0 = off, the thesis's fit) */
} cagekit_fit_options;

#define CAGEKIT_FIT_OPTIONS_INIT                                                                \
  { sizeof(cagekit_fit_options), 5, 1e-4, 0.0, 1.0, 0, CAGEKIT_PROJECTION_EXACT, CAGEKIT_LSQ_DIRECT, 0, \
    500, 1e-6, 4, 0.05, 1.0, 1, 0.0, 0.02 }

/* Figures of one state of the fit. Distances are |p_i - S(t_i)| from each scan vertex p_i to
 * its foot point on the limit surface, found by the exact projection (also in piecewise-linear
 * mode, where the statistics are measured outside `seconds`). "_rel" values are relative to the
 * scan's bounding-box diagonal. This struct has no struct_size: it is fixed for ABI version 1
 * (later figures go into a new struct). */
typedef struct cagekit_fit_pass {
  double l2;                    /* the thesis's L2 (7.1): sqrt(sum_i |p_i - S(t_i)|^2), model units */
  double rms_rel;               /* L2 / sqrt(N) / diagonal */
  double max_rel;               /* max_i |p_i - S(t_i)| / diagonal */
  double mean_rel;              /* mean_i |p_i - S(t_i)| / diagonal */
  double max_rel_interior;      /* max_rel over scan vertices not on or next to a scan boundary */
  double seconds;               /* time of this state: entry 0 the initial projection, entry k the k-th
                                   least-squares step and its re-projection */
  uint64_t unconverged_projections; /* searches that hit max_projection_steps first */
  double mean_projection_steps; /* update steps per search */
} cagekit_fit_pass;

/* Distances from the limit surface back to the scan for one state of the fit: from the limit
 * surface's grid points ((projection_seed_resolution + 1)^2 per ptex face) to the scan's triangles,
 * relative to the scan's bounding-box diagonal. NaN when the scan has no non-degenerate face. No
 * struct_size: fixed for ABI version 1. */
typedef struct cagekit_fit_two_sided {
  double surface_to_scan_max_rel;
  double surface_to_scan_rms_rel;
  double two_sided_rms_rel;     /* sqrt((rms_rel^2 + surface_to_scan_rms_rel^2) / 2) */
} cagekit_fit_two_sided;

typedef struct cagekit_fit_report {
  size_t struct_size;           /* sizeof(cagekit_fit_report) */
  uint32_t pass_count;          /* OUT: states measured, including the initial cage (entry 0): 1 + the
                                   control-vertex steps kept (the count of cagekit_cage_fit's passes) */
  cagekit_bool32 stopped_by_tolerance; /* OUT: 1 when (7.2) ended the fit before max_passes */
  cagekit_bool32 rejected_last_step; /* OUT: 1 when the last step would have increased L2 and was undone */
  cagekit_bool32 fairing_used;  /* OUT: 1 when the fairing term was active */
  uint64_t unsupported_control_vertices; /* OUT: control vertices with no scan vertex in their support in
                                            the last step (without fairing they keep their position) */
  double bbox_diagonal;         /* OUT: of the scan's vertices */
  double seconds;               /* OUT: the whole fit */
  cagekit_fit_pass initial;     /* OUT: the initial cage (= passes[0]) */
  cagekit_fit_pass final;       /* OUT: the returned cage (= passes[best_pass]) */
  uint32_t best_pass;           /* OUT: the state returned: with select_best_two_sided the one with the
                                   lowest two_sided_rms_rel, else pass_count - 1 */
  uint64_t weakly_supported_control_vertices; /* OUT: held by the weak-support fairing rows in the last
                                                 step (includes the unsupported ones) */
  cagekit_fit_two_sided initial_two_sided; /* OUT: surface -> scan figures of the initial cage */
  cagekit_fit_two_sided final_two_sided;   /* OUT: ... of the returned cage */
} cagekit_fit_report;

/* Fits the limit surface of `cage` to the vertices of `scan` (thesis ch. 7): alternates the
 * parameterisation step (foot points on the current limit surface) and the control-vertex
 * step (linear least squares with the exact basis functions) until the relative drop of L2
 * falls below options->tolerance or max_passes steps are done. L2 never increases: a step
 * that would increase it is undone and the fit stops (report->rejected_last_step). Every state
 * is also measured the other way (surface -> scan, cagekit_fit_two_sided); with
 * options->select_best_two_sided (default) the state with the lowest two-sided RMS is returned
 * (report->best_pass), so a step that lowers L2 while parts of the surface move away from the
 * scan is not what comes back. Control vertices with little or no data in their support are held
 * by fairing rows (options->weak_support_fraction).
 *
 * *out receives a NEW cage with the fitted control-vertex positions and the same connectivity,
 * tags (creases, corners, holes) and boundary rule as `cage`; `cage` itself is not changed.
 * Every scan vertex is a sample (faces are used to find the scan boundary and for the surface ->
 * scan distances), so the scan need not be a valid mesh, but its face indices must be in range
 * and its positions finite. options may be NULL (defaults); report may be NULL.
 *
 * `passes` receives the figures of every state measured (entry 0 the initial cage, then one per
 * control-vertex step kept; entry report->best_pass is the state returned). Two-call (Buffers)
 * over states, except that the fit is not repeated for a second call: max_passes + 1 entries
 * always suffice, and a nonzero pass_capacity below max_passes + 1 fails with SIZE_INSUFFICIENT
 * (*pass_count_out = max_passes + 1) before any work, so a short array never costs a fit. On
 * success *pass_count_out is the number of states measured (report->pass_count); with
 * pass_capacity 0 the fit runs and only that count is written.
 *
 * Long operation (progress, cancel), using up to options->threads worker threads internally;
 * callbacks still run on the calling thread.
 *
 * Ownership: *out receives one reference to the new cage (release it with cagekit_cage_release);
 *   `passes` is the caller's, written during the call only.
 * Errors: INVALID_HANDLE (cage or scan), INVALID_ARGUMENT (out or pass_count_out NULL, passes
 *   NULL with a nonzero pass_capacity, a bad struct_size, an option out of range or NaN, naming
 *   the field; a scan with no vertices, a face index out of range or a non-finite position),
 *   SIZE_INSUFFICIENT (pass_capacity, before any work), INVALID_MESH (a cage whose limit surface
 *   cannot be built), CANCELLED (stage "fit"; progress is reported at least once per pass),
 *   OUT_OF_MEMORY. On error *out is NULL and *report and `passes` are unspecified.
 * Threading: reads `cage` and `scan`: both may be used by other threads' read-only calls
 *   meanwhile, not modified; thread-safe. */
CAGEKIT_API cagekit_status cagekit_cage_fit(cagekit_cage cage, cagekit_mesh scan, const cagekit_fit_options* options,
                                            cagekit_cage* out, cagekit_fit_report* report, uint32_t pass_capacity,
                                            uint32_t* pass_count_out, cagekit_fit_pass* passes);

/* ------------------------------------------------------------------------------------------ */
/* Scan to cage: the whole journey in one call                                                 */
/* ------------------------------------------------------------------------------------------ */

/* How the initial cage is made. */
typedef enum cagekit_scan_method {
  CAGEKIT_SCAN_SIMPLIFY = 0,    /* structure-preserving simplification (thesis ch. 3) + quad-dominant cage */
  CAGEKIT_SCAN_QUAD = 1,        /* two-step quad-dominant remeshing (thesis ch. 6) */
  CAGEKIT_SCAN_ANISOTROPIC = 2, /* curvature-line remeshing (thesis ch. 5) */
  CAGEKIT_SCAN_METHOD_MAX_ENUM = 0x7fffffff
} cagekit_scan_method;

/* Which connected components of the scan are kept by the conditioning. */
typedef enum cagekit_component_mode {
  CAGEKIT_COMPONENTS_ALL = 0,     /* every component (the default) */
  CAGEKIT_COMPONENTS_LARGEST = 1, /* only the one with the most faces (scans with stray pieces) */
  CAGEKIT_COMPONENTS_MAX_ENUM = 0x7fffffff
} cagekit_component_mode;

typedef struct cagekit_scan_to_cage_options {
  size_t struct_size;               /* sizeof(cagekit_scan_to_cage_options) */
  cagekit_scan_method method;       /* default CAGEKIT_SCAN_SIMPLIFY */
  /* Conditioning (the first phase): cagekit_mesh_repair's steps without DROP_INVALID_FACES (bad
     indices and NaN/Inf stay INVALID_MESH) plus the removal of unreferenced vertices. */
  cagekit_bool32 repair;            /* 1 (default): condition the scan; 0: refuse an invalid scan */
  cagekit_component_mode components; /* default CAGEKIT_COMPONENTS_ALL */
  double weld_tolerance_rel;        /* vertices closer than this x the bounding-box diagonal are welded,
                                       finite and >= 0 (default 1e-7; 0: exact duplicates only) */
  /* SIMPLIFY: the coarsest level with at most `target` faces (CAGEKIT_LEVEL_BY_FACES, default) or
     vertices (CAGEKIT_LEVEL_BY_VERTICES); also the face count of the fallback. */
  cagekit_level_query target_query;
  double target;                    /* >= 1 (default 60) */
  const cagekit_cage_options* cage; /* SIMPLIFY's cage options; NULL = defaults. Read during the call. */
  const cagekit_quad_remesh_options* quad;          /* QUAD's options; NULL = defaults. Read during the call. */
  const cagekit_anisotropic_options* anisotropic;   /* ANISOTROPIC's options; NULL = defaults. Read during
                                                       the call. */
  const cagekit_fit_options* fit;   /* NULL = defaults. Read during the call. */
  uint32_t limit_levels;            /* the fitted cage is refined this often onto its limit for the error
                                       figures and *limit_out, 1..CAGEKIT_MAX_SUBDIVISION_LEVELS (default 3) */
  uint32_t self_intersection_level; /* the level of the limit mesh whose self-intersections are counted,
                                       0..CAGEKIT_MAX_SUBDIVISION_LEVELS (default 2; 0: not counted) */
  /* The good-result rule: the limit surface -> scan distance must be at most
     max(max_limit_to_scan_rel, limit_to_scan_factor x the scan -> limit distance) (relative to the
     diagonal), except for inputs with fewer than small_input_faces faces, whose smooth limit may
     bulge away from coarse facets; the cage must be valid and manifold with no holes the
     conditioned scan does not have. */
  double max_limit_to_scan_rel;     /* finite and > 0 (default 0.05) */
  double limit_to_scan_factor;      /* finite and > 0 (default 3) */
  uint64_t small_input_faces;       /* default 1000 */
  cagekit_bool32 fallback_to_simplify; /* 1 (default): a QUAD / ANISOTROPIC result that is not good (or that
                                       fails) is replaced by SIMPLIFY at `target` faces; the report says so
                                       and why. 0: it is an error. */
  uint32_t finer_simplify_attempts; /* a SIMPLIFY result whose limit surface strays from the scan is tried
                                       again at 2x, 4x, ... the target, at most this often, 0..8 (default 2;
                                       0: never); report->simplify_target_used says which was returned */
  double two_sided_refit_factor;    /* the last phase: the good result's cage is fitted again by two-sided
                                       least squares (cagekit_fit_options.reverse_sample_factor = this), and
                                       that fit is kept when the larger of the limit's two one-sided maxima
                                       drops by at least 5 %, with no more self-intersections and still good; the method,
                                       target and remedies are chosen by the one-sided fit. Finite, 0..100
                                       (default 3; 0: not tried) */
  /* The host's sharp edges, as vertex pairs of `scan` (2 * sharp_edge_count indices): after the
   * conditioning they are found again by their ends' positions and given to every method (as
   * the sharp_edges of the simplify, cage, quad and anisotropic options, including the
   * fallback); the report counts those found and those dropped (ends welded together, faces
   * dropped). The nested option structs' own sharp_edges must be empty here. NULL with 0
   * (default). Read during the call. */
  const uint32_t* sharp_edges;
  uint32_t sharp_edge_count;
} cagekit_scan_to_cage_options;

#define CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT                                                               \
  { sizeof(cagekit_scan_to_cage_options), CAGEKIT_SCAN_SIMPLIFY, 1, CAGEKIT_COMPONENTS_ALL, 1e-7,         \
    CAGEKIT_LEVEL_BY_FACES, 60.0, NULL, NULL, NULL, NULL, 3, 2, 0.05, 3.0, 1000, 1, 2, 3.0, NULL, 0 }

/* Every figure of one scan-to-cage run. Distances are relative to the conditioned scan's
 * bounding-box diagonal. */
typedef struct cagekit_scan_to_cage_report {
  size_t struct_size;               /* sizeof(cagekit_scan_to_cage_report) */
  /* 1. conditioning */
  uint64_t input_vertices, input_faces;
  uint64_t conditioned_vertices, conditioned_faces;
  uint64_t welded_vertices, dropped_degenerate_faces, dropped_duplicate_faces;
  uint64_t split_vertices;          /* added to split non-manifold edges / vertices and non-orientable parts */
  uint64_t flipped_faces, non_orientable_components, removed_unreferenced_vertices;
  uint64_t components;              /* connected components kept */
  uint64_t dropped_components, dropped_component_faces; /* CAGEKIT_COMPONENTS_LARGEST */
  /* 2. the method */
  cagekit_scan_method requested_method;
  cagekit_scan_method used_method;  /* differs after a fallback */
  cagekit_bool32 fallback;          /* 1 when the requested method's result was replaced */
  cagekit_bool32 input_is_cage;     /* 1 when the conditioned scan had no more faces than the method would
                                       make and is its own cage (edges sharper than 40 degrees creased) */
  char fallback_reason[256];        /* why the fallback happened (NUL-terminated, "" when none) */
  uint32_t level, level_count;      /* SIMPLIFY: the level chosen and the hierarchy's level count */
  uint64_t level_faces, level_faces_with_holes; /* SIMPLIFY: polygons of that level */
  uint64_t cage_vertices, cage_faces, cage_quads, cage_triangles; /* the fitted cage */
  uint64_t creases;                 /* crease edges of the cage */
  uint64_t remesh_regions, remesh_lines, remesh_holes; /* regions; lines (anisotropic) or arcs (quad); holes (anisotropic) */
  uint64_t interior_vertices, valence4_vertices; /* of the cage */
  uint32_t max_face_valence, max_vertex_valence;
  double mean_alignment_deg;        /* ANISOTROPIC, as in cagekit_anisotropic_report */
  double method_scan_to_cage_max_rel, method_cage_to_scan_max_rel, method_mean_rel; /* the initial cage's
                                       control mesh against the scan */
  /* 3. the cage */
  uint64_t input_boundary_loops, cage_boundary_loops;
  uint64_t holes_added;             /* always 0 on success */
  /* 4. the fit (all figures as cagekit_fit_report's) */
  uint32_t fit_pass_count, fit_best_pass;
  cagekit_fit_pass fit_initial, fit_final;
  cagekit_fit_two_sided fit_initial_two_sided, fit_final_two_sided;
  uint64_t unsupported_control_vertices, weakly_supported_control_vertices;
  /* 5. the limit surface */
  uint32_t limit_levels;
  uint64_t limit_faces;
  double scan_to_limit_max_rel;     /* max over scan vertices of the distance to the limit mesh */
  double limit_to_scan_max_rel;     /* max over limit-mesh samples of the distance to the scan's surface */
  double limit_mean_rel;            /* mean scan-vertex distance */
  uint64_t self_intersections;      /* intersecting triangle pairs of the level-`self_intersection_level`
                                       limit mesh (quads split along the diagonal that folds least) */
  uint64_t self_intersection_triangles; /* triangles tested */
  double method_seconds, fit_seconds, seconds;
  double simplify_target_used;      /* SIMPLIFY (also as the fallback): the target of the returned level */
  /* Counted only when self_intersections > 0 (else 0): the conditioned scan's own intersecting
     pairs (a faithful surface inherits them) and the initial cage's limit mesh's before the fit
     (whether the method or the fit made them). While the limit has more than the scan, the
     journey remedies them, keeping the good result with the fewest: the fit is run again with more fairing
     (fit_fairing_used), a tiny input is creased more, SIMPLIFY tries the finer targets too. */
  uint64_t scan_self_intersections, unfitted_self_intersections;
  cagekit_bool32 scan_self_intersections_counted; /* 1 when scan_self_intersections was counted */
  double own_cage_crease_angle_deg; /* input_is_cage: the crease angle used (40 by default, 20 or 0 =
                                       every edge creased after a self-intersection remedy) */
  double fit_fairing_used;          /* the fit's fairing weight of the result (the option's, or 0.01 / 0.1
                                       after a remedy: for self-intersections, or for a limit that strayed
                                       from the scan, which is fitted again with more fairing before any
                                       finer target or fallback is tried) */
  /* The last phase (cagekit_scan_to_cage_options.two_sided_refit_factor). */
  cagekit_bool32 two_sided_refit;   /* 1 when the returned fit is the two-sided refit */
  double one_sided_fit_max_rel;     /* then: max(scan -> limit, limit -> scan) of the one-sided fit it
                                       replaced (0 when two_sided_refit is 0) */
  uint64_t sharp_edges;             /* the options' sharp edges found on the conditioned scan ... */
  uint64_t sharp_edges_dropped;     /* ... and not found (their ends welded together or dropped) */
  uint64_t remesh_reseeded_regions; /* quad: cagekit_quad_remesh_report.reseeded_regions (0: the first
                                       segmentation's layout was used) */
} cagekit_scan_to_cage_report;

/* The whole journey from a scan to a fitted cage, in named phases: conditioning (repair as
 * above, one info log line naming every change) -> the method (an input that already has fewer
 * faces than the method would make is its own cage) -> a valid manifold cage without new holes
 * -> fit of its limit surface (cagekit_cage_fit) -> the limit surface measured against the scan
 * both ways and its self-intersections counted -> the good-result rule (options above) -> a
 * two-sided refit of the good result, kept only when closer to the scan (two_sided_refit_factor). Status
 * SUCCESS means a good result: *cage_out is the fitted cage with crease tags, *limit_out (may be
 * NULL) the fitted cage refined limit_levels times onto its limit, and *report (may be NULL)
 * holds every figure. The returned cage's fit is reported as cagekit_cage_fit reports it:
 * `fit_report` (may be NULL) and its states in `fit_passes` (fit_pass_capacity,
 * fit_pass_count_out: two-call (Buffers) as cagekit_cage_fit's passes, with max_passes the
 * options->fit one: max_passes + 1 entries always suffice, and a shorter nonzero capacity fails
 * with SIZE_INSUFFICIENT before any work). Hosts keep the individual steps (cagekit_mesh_repair,
 * cagekit_hierarchy_*, cagekit_mesh_remesh_*, cagekit_cage_fit) for finer control.
 *
 * Long operation (progress: the stages of each phase, "conditioning", the method's, "fit",
 * "error"; cancel), using the threads its options give.
 *
 * Ownership: *cage_out and *limit_out each receive one reference (release them with
 *   cagekit_cage_release); the options and the structs and arrays they point to are read during
 *   the call only; `fit_passes` is the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (NULL cage_out or fit_pass_count_out, fit_passes NULL
 *   with a nonzero fit_pass_capacity, bad struct_size, an option out of range, naming it; nested
 *   option structs with sharp_edges of their own), SIZE_INSUFFICIENT (fit_pass_capacity, before
 *   any work), INVALID_MESH (out-of-range indices or non-finite positions, naming the first; an
 *   invalid scan with repair 0; no faces, or nothing left after conditioning), QUALITY (no good
 *   result: the message names the method and the figure, e.g. "the limit surface strays 7.2 % of
 *   the diagonal from the scan"), CANCELLED, OUT_OF_MEMORY (also the context's memory budget). On
 *   error the outputs are NULL and *report, *fit_report and `fit_passes` are unspecified.
 * Threading: reads `scan`; thread-safe for distinct outputs. */
CAGEKIT_API cagekit_status cagekit_scan_to_cage(cagekit_mesh scan, const cagekit_scan_to_cage_options* options,
                                                cagekit_cage* cage_out, cagekit_cage* limit_out,
                                                cagekit_scan_to_cage_report* report, cagekit_fit_report* fit_report,
                                                uint32_t fit_pass_capacity, uint32_t* fit_pass_count_out,
                                                cagekit_fit_pass* fit_passes);

/* ------------------------------------------------------------------------------------------ */
/* Multiresolution editing (thesis ch. 8): bind a scan to a cage, deform it on the CPU          */
/* ------------------------------------------------------------------------------------------ */

/* A scan bound to a cage's limit surface: per scan vertex its foot point, displacement, basis
 * functions and normal-reconstruction coefficients (thesis §8.3, §8.5). Immutable once made;
 * any number of threads may read it and deformers may share it. */
typedef struct cagekit_binding_t* cagekit_binding;
/* Deforms a bound scan for moved control points on the CPU. One thread at a time (it keeps the
 * last control points and per-vertex surface frames for incremental updates). */
typedef struct cagekit_cpu_deformer_t* cagekit_cpu_deformer;

typedef enum cagekit_displacement_mode {
  CAGEKIT_DISPLACEMENT_NORMAL = 0,      /* the thesis: D along the surface normal (8.1) */
  CAGEKIT_DISPLACEMENT_LOCAL_FRAME = 1, /* the whole offset in the surface's orthonormal frame:
                                           exact also where the foot point is on a border */
  CAGEKIT_DISPLACEMENT_MAX_ENUM = 0x7fffffff
} cagekit_displacement_mode;

typedef struct cagekit_bind_options {
  size_t struct_size;                  /* sizeof(cagekit_bind_options) */
  cagekit_displacement_mode mode;      /* default CAGEKIT_DISPLACEMENT_NORMAL */
  cagekit_bool32 exact_normals;        /* 1: also store the data of the exact normals (8.4)-(8.7) */
  uint32_t threads;                    /* 0 = all cores */
  double sharp_angle_degrees;          /* sharp features (thesis §8.5.2): >= 0 binds every scan
                                          vertex once per smooth sector (sectors split by edges
                                          whose faces' normals differ by more than this angle, and
                                          by boundary / non-manifold edges), so each copy keeps its
                                          sector's normal; the bound vertices are then the copies
                                          (cagekit_binding_get_vertex_sources, _get_faces).
                                          Default -1: one bound vertex per scan vertex. */
} cagekit_bind_options;

#define CAGEKIT_BIND_OPTIONS_INIT { sizeof(cagekit_bind_options), CAGEKIT_DISPLACEMENT_NORMAL, 0, 0, -1.0 }

typedef struct cagekit_binding_info {
  size_t struct_size;                  /* sizeof(cagekit_binding_info) */
  uint32_t vertex_count;               /* bound vertices (the scan's, plus copies per smooth sector) */
  uint32_t control_count;              /* cage vertices */
  uint64_t basis_entries;              /* stored non-zero basis functions, all vertices */
  double max_sideways_residual;        /* normal mode: largest offset part not along the normal,
                                          relative to the scan's bbox diagonal (0 in local-frame mode) */
  uint64_t vertices_with_sideways_residual; /* normal mode: vertices above 1e-6 of the diagonal */
  double bbox_diagonal;
  cagekit_bool32 has_exact_normals;
  /* The CPU deformer's compact table. */
  double deform_bytes_per_vertex;      /* bytes read + written per vertex in one full CPU frame of
                                          positions + approximate normals (table, outputs, control) */
  uint32_t compact_cells;              /* bicubic cells of the table (0: no table, sparse rows used) */
  uint32_t irregular_vertices;         /* vertices the table evaluates from their sparse rows */
  /* Sector split (cagekit_bind_options.sharp_angle_degrees >= 0). */
  uint32_t scan_vertex_count;          /* the scan's vertices; vertex_count - scan_vertex_count
                                          are copies made at sharp features (equal without split) */
  cagekit_bool32 has_sector_split;     /* 1: bound vertices are per smooth sector (see below) */
} cagekit_binding_info;

/* Binds every vertex of `scan` to the limit surface of `cage` (exact closest points, §7.4).
 * Usually the cage was fitted to the scan first (cagekit_cage_fit), so that displacements are
 * small. options may be NULL. Long operation (progress, cancel).
 * Ownership: *out receives one reference (release it with cagekit_binding_release); the binding
 *   keeps its own copy of the cage (cagekit_binding_get_cage).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL, bad struct_size or option, a scan without
 *   vertices, with a face index out of range or with a non-finite position), INVALID_MESH (no
 *   limit surface), CANCELLED (stage "bind"), OUT_OF_MEMORY.
 * Threading: reads `cage` and `scan`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_multires_bind(cagekit_cage cage, cagekit_mesh scan,
                                                 const cagekit_bind_options* options, cagekit_binding* out);
/* Adds a reference (retain) or drops one (release; the binding is destroyed when no reference is
 * left, including those its deformers hold). NULL is ignored.
 * Errors: none.
 * Threading: any thread (the reference count is atomic). */
CAGEKIT_API void cagekit_binding_retain(cagekit_binding binding);
CAGEKIT_API void cagekit_binding_release(cagekit_binding binding);
/* Fills *info with the binding's counts and figures.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (info NULL or bad struct_size).
 * Threading: reads `binding`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_binding_get_info(cagekit_binding binding, cagekit_binding_info* info);

/* Saved bindings (`.ckb`): binding is the slow part (one exact closest-point search per scan
 * vertex); a saved binding keeps the cage it was made from, the options and per vertex the foot
 * point, displacement and normal coefficients, and reading it rebuilds the limit surface, the
 * basis rows and the deformer's compact table from them: the result equals the binding that was
 * saved, bit for bit. Format: little-endian sections, versioned; about 118 bytes per scan vertex
 * (normal mode), 134 (local frame or exact normals).
 * Writing: to a file atomically (a failed write never leaves a partial file) or into a new blob.
 * Ownership: `path` is read during the call only; write_memory's *out receives a new blob (one
 *   reference: release it with cagekit_blob_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (path or out NULL), IO (files), OUT_OF_MEMORY.
 * Threading: reads the binding; thread-safe. */
CAGEKIT_API cagekit_status cagekit_binding_write_file(cagekit_binding binding, const char* path);
CAGEKIT_API cagekit_status cagekit_binding_write_memory(cagekit_binding binding, cagekit_blob* out);
/* Reading: `threads` (0 = all cores) for the rebuild. The bytes are treated as hostile. Long
 * operation (progress, cancel).
 * Ownership: *out receives one reference (release it with cagekit_binding_release); `path` and
 *   `data` are only read during the call.
 * Errors: INVALID_HANDLE (context), INVALID_ARGUMENT (out or path NULL, data NULL with a nonzero
 *   size, threads above 1024), IO, PARSE (the message names the source and the byte offset or the
 *   field: truncation, bad magic, non-finite numbers, a foot point off the limit surface, a cage
 *   the OBJ reader refuses), UNSUPPORTED_FORMAT (another format version), LIMIT_EXCEEDED (hostile
 *   counts), INVALID_MESH (the saved cage has no limit surface), OUT_OF_MEMORY, CANCELLED (stage
 *   "bind").
 * Threading: any thread (thread-safe). */
CAGEKIT_API cagekit_status cagekit_binding_read_file(cagekit_context context, const char* path, uint32_t threads,
                                                     cagekit_binding* out);
CAGEKIT_API cagekit_status cagekit_binding_read_memory(cagekit_context context, const void* data, size_t size,
                                                       uint32_t threads, cagekit_binding* out);
/* With a sector split: bound vertex i copies scan vertex sources[i] (the first
 * info.scan_vertex_count are the scan's own, in order; copies follow), and the scan's faces
 * over the bound vertices (same faces, same order; draw these, and give a mesh made of them to
 * cagekit_gl_deformer_create). Without a split, sources[i] = i and *face_count_out = 0 (the
 * scan's own faces apply). Two-call (Buffers): sources over bound vertices; the faces as
 * cagekit_mesh_get_faces's.
 * Ownership: the arrays are the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (a count pointer NULL, an array NULL with a nonzero
 *   capacity), SIZE_INSUFFICIENT.
 * Threading: reads `binding`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_binding_get_vertex_sources(cagekit_binding binding, uint32_t vertex_capacity,
                                                              uint32_t* vertex_count_out, uint32_t* sources);
CAGEKIT_API cagekit_status cagekit_binding_get_faces(cagekit_binding binding, uint32_t face_capacity,
                                                     uint32_t* face_count_out, uint32_t* face_sizes,
                                                     uint64_t index_capacity, uint64_t* index_count_out,
                                                     uint32_t* face_indices);
/* A renumbering of the scan's vertices in the order the CPU deformer writes them (cells in table
 * order, then the irregular vertices; with a sector split a copy counts for its scan vertex):
 * order[k] is the scan vertex that becomes vertex k, each scan vertex once (the count is the
 * scan's vertex count). The deformer writes positions and normals into the caller's arrays in
 * the scan's vertex order; where that order does not follow the cells, the stores are scattered
 * and cost most of a full frame. A host that may renumber its scan (e.g. on import) applies this
 * order once (new index of order[k] = k, faces remapped) and binds again: the writes become
 * sequential streaming stores, which makes full frames faster.
 * Optional; the deformer gives the same positions either way. Two-call (Buffers) over scan
 * vertices.
 * Ownership: `order` is the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (vertex_count_out NULL, order NULL with a nonzero
 *   capacity), SIZE_INSUFFICIENT, OUT_OF_MEMORY.
 * Threading: reads `binding`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_binding_get_deformer_vertex_order(cagekit_binding binding, uint32_t vertex_capacity,
                                                                     uint32_t* vertex_count_out, uint32_t* order);
/* The cage the binding was made on, as a new cage handle: a copy the caller may edit and pass
 * its positions to a deformer.
 * Ownership: *out receives one reference (release it with cagekit_cage_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL), OUT_OF_MEMORY.
 * Threading: reads `binding`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_binding_get_cage(cagekit_binding binding, cagekit_cage* out);

typedef enum cagekit_normal_mode {
  CAGEKIT_NORMALS_APPROXIMATE = 0, /* (8.11)-(8.12): from S_u, S_v only */
  CAGEKIT_NORMALS_EXACT = 1,       /* (8.4)-(8.7): needs a binding made with exact_normals */
  CAGEKIT_NORMALS_MAX_ENUM = 0x7fffffff
} cagekit_normal_mode;

/* A CPU deformer of `binding`. threads: 0 = all cores.
 * Ownership: *out receives one reference (release it with cagekit_cpu_deformer_release); the
 *   deformer keeps `binding` alive.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL, threads above 1024), OUT_OF_MEMORY.
 * Threading: reads `binding`; thread-safe (deformers may share a binding). */
CAGEKIT_API cagekit_status cagekit_cpu_deformer_create(cagekit_binding binding, uint32_t threads,
                                                       cagekit_cpu_deformer* out);
/* Adds a reference (retain) or drops one (release; the last one destroys the deformer and drops
 * its reference to the binding). NULL is ignored.
 * Errors: none.
 * Threading: any thread (the reference count is atomic). */
CAGEKIT_API void cagekit_cpu_deformer_retain(cagekit_cpu_deformer deformer);
CAGEKIT_API void cagekit_cpu_deformer_release(cagekit_cpu_deformer deformer);

/* Full recompute: `control` holds control_count xyz triples (the cage's vertices, moved);
 * positions and normals receive an xyz triple per bound vertex (unit normals). Two-call
 * (Buffers) over the bound vertices (cagekit_binding_info.vertex_count), shared by positions and
 * normals (either may be NULL; both NULL with a nonzero capacity deforms without output).
 * vertex_capacity 0 makes the call a query: only *vertex_count_out is written, nothing is
 * deformed and the other arguments are not read. Hosts that know the count pass it every frame.
 * Ownership: `control` is read during the call only; positions and normals are the caller's,
 *   written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (vertex_count_out NULL, control NULL, control_count
 *   not the binding's, a non-finite control point, normals_mode out of range), INVALID_OPERATION
 *   (exact normals from a binding made without their data), SIZE_INSUFFICIENT, OUT_OF_MEMORY.
 * Threading: modifies `deformer`: one thread at a time (not thread-safe on the same deformer). */
CAGEKIT_API cagekit_status cagekit_cpu_deformer_deform(cagekit_cpu_deformer deformer, const double* control,
                                                       uint32_t control_count, cagekit_normal_mode normals_mode,
                                                       uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                       double* positions, double* normals);

/* Incremental: only the control points listed in `moved` (moved_count indices) changed since the
 * last deform/update call of this deformer (which must have had the same normals_mode); the
 * other entries of `control` are not read (they must equal the previous call's). Only the
 * vertices in their support are recomputed and written — the rest of `positions` / `normals` is
 * left as the caller had it from the earlier calls. *updated_count (may be NULL) receives the
 * number of vertices recomputed. The outputs as cagekit_cpu_deformer_deform's (vertex_capacity 0:
 * a query that updates nothing).
 * Ownership: `control` and `moved` are read during the call only; positions and normals are the
 *   caller's, written during the call only.
 * Errors: as cagekit_cpu_deformer_deform, plus INVALID_ARGUMENT for moved NULL with a nonzero
 *   moved_count or a moved index out of range, and INVALID_OPERATION for a call before the first
 *   deform or with another normals_mode than the last deform's.
 * Threading: modifies `deformer`: one thread at a time (not thread-safe on the same deformer). */
CAGEKIT_API cagekit_status cagekit_cpu_deformer_update(cagekit_cpu_deformer deformer, const double* control,
                                                       uint32_t control_count, const uint32_t* moved,
                                                       uint32_t moved_count, cagekit_normal_mode normals_mode,
                                                       uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                       double* positions, double* normals, uint32_t* updated_count);

/* The same two calls writing float32 positions and normals (xyz triples, 3 floats per bound
 * vertex; two-call over the bound vertices as there), for hosts that draw float32 vertex arrays
 * (half the bytes written per frame; the full recompute is faster). `control` stays double.
 * Every value written is the double call's value rounded to float (the deformer's compact path
 * evaluates in float32 anyway; positions are formed in double, then rounded). A deformer may mix
 * the double and float32 calls: an update_f32 after a deform (or the reverse) recomputes the
 * moved points' support only, into whichever arrays that call is given.
 * Ownership: as cagekit_cpu_deformer_deform / cagekit_cpu_deformer_update: the arrays are the
 *   caller's, only read or written during the call, never kept.
 * Errors: as cagekit_cpu_deformer_deform / cagekit_cpu_deformer_update (INVALID_HANDLE,
 *   INVALID_ARGUMENT, INVALID_OPERATION, SIZE_INSUFFICIENT, OUT_OF_MEMORY).
 * Threading: modifies `deformer`: one thread at a time (not thread-safe on the same deformer). */
CAGEKIT_API cagekit_status cagekit_cpu_deformer_deform_f32(cagekit_cpu_deformer deformer, const double* control,
                                                           uint32_t control_count, cagekit_normal_mode normals_mode,
                                                           uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                           float* positions, float* normals);
CAGEKIT_API cagekit_status cagekit_cpu_deformer_update_f32(cagekit_cpu_deformer deformer, const double* control,
                                                           uint32_t control_count, const uint32_t* moved,
                                                           uint32_t moved_count, cagekit_normal_mode normals_mode,
                                                           uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                           float* positions, float* normals, uint32_t* updated_count);

/* ------------------------------------------------------------------------------------------ */
/* Limit surface as bicubic Bezier patches (for CAD kernels: STEP, B-spline faces)            */
/* ------------------------------------------------------------------------------------------ */

/* The limit surface of a cage (as cagekit_surface_create with default options evaluates it) as
 * bicubic Bezier patches, each on a dyadic square of one ptex face; the squares tile every ptex
 * face with a limit surface. Where the limit surface is one polynomial (regular B-spline patches,
 * also at infinitely sharp creases and boundaries) the patch IS the limit surface ("exact", to
 * rounding). Around extraordinary vertices it is not polynomial: there a patch approximates it
 * (border curves fitted to limit points along each border with the corners on the surface, inner
 * points by least squares), and a square is split into 4 while its measured error exceeds the
 * tolerance and max_depth allows. Crease edges and ptex face borders are always patch borders, so
 * sharp features are kept. The error of a patch is measured as the largest distance between patch
 * and limit surface at equal parameters on a 33 x 33 grid (not a bound between the samples).
 * Neighbouring patches meet exactly when both are exact or both approximated on equal squares, and
 * within the sum of their errors otherwise (sew with a tolerance of 2 x max_error). */
typedef struct cagekit_limit_patches_t* cagekit_limit_patches;

typedef struct cagekit_limit_patch_options {
  size_t struct_size; /* sizeof(cagekit_limit_patch_options) */
  double tolerance;   /* largest distance allowed between an approximated patch and the limit surface,
                         as a fraction of the bounding-box diagonal of the cage's control points;
                         finite and > 0 (default 1e-4) */
  uint32_t max_depth; /* how often a square that is not one polynomial may be split into 4, 0..12
                         (default 8); patches still above the tolerance at that depth are kept and
                         counted in over_tolerance_count */
  uint32_t threads;   /* worker threads, 0..1024; 0 (default) = the number of hardware threads.
                         The patches do not depend on it. */
} cagekit_limit_patch_options;

#define CAGEKIT_LIMIT_PATCH_OPTIONS_INIT { sizeof(cagekit_limit_patch_options), 1e-4, 8, 0 }

typedef struct cagekit_limit_patch_info {
  size_t struct_size;            /* set by the caller: sizeof(cagekit_limit_patch_info) */
  uint32_t patch_count;          /* exact_count + approximated_count */
  uint32_t exact_count;          /* patches equal to the limit surface */
  uint32_t approximated_count;
  uint32_t over_tolerance_count; /* approximated patches above the tolerance (max_depth reached) */
  double max_error;              /* largest measured error of an approximated patch, model units */
  double max_error_rel;          /* max_error / bbox_diagonal */
  double bbox_diagonal;          /* of the cage's control points */
  double tolerance;              /* the absolute tolerance: options.tolerance * bbox_diagonal */
} cagekit_limit_patch_info;

/* One patch. Not versioned: its layout is fixed for this ABI version. */
typedef struct cagekit_limit_patch {
  uint32_t ptex_face;    /* ptex face (numbering of cagekit_surface_get_ptex_face) */
  uint32_t cage_face;    /* the cage face it belongs to */
  double u0, v0, u1, v1; /* its square in the ptex face: Bezier parameters (s, t) in [0,1]^2 are the
                            ptex location (u0 + s (u1 - u0), v0 + t (v1 - v0)) */
  cagekit_bool32 exact;  /* 1: the polynomial is the limit surface; 0: an approximation */
  uint32_t reserved;     /* 0 */
  double error;          /* measured largest distance to the limit surface, model units (rounding
                            level for exact patches) */
  double control_points[48]; /* bicubic Bezier control net: point (i, j), i along s, j along t, is
                                control_points[3 * (4 * j + i) + 0..2], with weight B_i(s) B_j(t) */
} cagekit_limit_patch;

/* Builds the patches of `cage`'s limit surface. options may be NULL (defaults). Long operation
 * (progress stage "limit patches", cancel).
 * Ownership: *out receives one reference (release it with cagekit_limit_patches_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL, bad struct_size or options), INVALID_MESH
 *   (a cage that cannot be subdivided), LIMIT_EXCEEDED (more than 2^20 patches would be needed:
 *   raise the tolerance or lower max_depth), CANCELLED, OUT_OF_MEMORY (also against the context's
 *   memory budget).
 * Threading: reads `cage`; thread-safe. The result is immutable and may be read from several
 *   threads at once. */
CAGEKIT_API cagekit_status cagekit_limit_patches_create(cagekit_cage cage, const cagekit_limit_patch_options* options,
                                                        cagekit_limit_patches* out);
/* Adds a reference (retain) or drops one (release; the last one destroys the patches). NULL is
 * ignored.
 * Errors: none.
 * Threading: any thread (the reference count is atomic). */
CAGEKIT_API void cagekit_limit_patches_retain(cagekit_limit_patches patches);
CAGEKIT_API void cagekit_limit_patches_release(cagekit_limit_patches patches);
/* Counts and errors of the patches, into *info.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (info NULL or bad struct_size).
 * Threading: reads `patches`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_limit_patches_get_info(cagekit_limit_patches patches, cagekit_limit_patch_info* info);
/* Copies every patch into `patch_array`, ordered by ptex face, then by quadtree order. Two-call
 * (Buffers) over patches (the count is cagekit_limit_patch_info.patch_count).
 * Ownership: `patch_array` is the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (patch_count_out NULL, patch_array NULL with a nonzero
 *   capacity), SIZE_INSUFFICIENT.
 * Threading: reads `patches`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_limit_patches_get(cagekit_limit_patches patches, uint32_t patch_capacity,
                                                     uint32_t* patch_count_out, cagekit_limit_patch* patch_array);

/* ------------------------------------------------------------------------------------------ */
/* Limit surface as B-spline surfaces, one per ptex face (for CAD kernels: STEP, NURBS faces)   */
/* ------------------------------------------------------------------------------------------ */

/* The limit surface of a cage (as cagekit_surface_create with default options evaluates it) as
 * one non-rational B-spline surface per ptex face (a cage quad has one, an n-gon n; ptex faces of
 * hole faces have none): what a CAD kernel takes as a NURBS face directly. Each surface has its
 * degrees (3 x 3 today), clamped ("open") knot vectors in [0, 1] with the end knots repeated
 * degree + 1 times and uniform simple interior knots, and num_u x num_v control points. The knot
 * vectors differ between surfaces (the number of knots is chosen per surface and direction);
 * read each surface's own.
 * Where the limit surface of a ptex face is piecewise bicubic on the knot grid (regular faces,
 * also at infinitely sharp creases and boundaries) the surface IS the limit surface ("exact",
 * measured below 1e-12 of the diagonal). Next to an extraordinary vertex it approximates it: a
 * surface over the tolerance, folded, or with a normal jump above max_normal_jump_deg across a
 * smooth border gets more knots (with its borders), up to max_level. Shared borders are the same
 * curve on both surfaces (identical border control points where the two have the same knots on
 * it), and across smooth (non-crease) borders the cross-boundary derivatives are constrained so
 * that the normals agree (G1); crease edges are C0 borders, boundaries stay boundaries.
 * Measured per surface on a grid of at least 33 x 33 samples: the parametric error (largest
 * distance to the limit surface at equal parameters), the error (two-sided: where the parametric
 * error exceeds the tolerance, each far sample is projected onto the other surface within the ptex
 * face, both ways; never above the parametric error) and the largest angle between the surface's
 * normal and the limit's at equal parameters (above 90 degrees: folded). Normal jumps: the angle
 * between the two surfaces' normals at points along every shared border. */
typedef struct cagekit_limit_surfaces_t* cagekit_limit_surfaces;

typedef struct cagekit_limit_surface_options {
  size_t struct_size; /* sizeof(cagekit_limit_surface_options) */
  double tolerance;   /* largest distance allowed between an approximated surface and the limit
                         surface, as a fraction of the bounding-box diagonal of the cage's control
                         points; finite and > 0 (default 1e-4) */
  uint32_t max_level; /* largest knot level tried, 1..7 (default 5): at level l a quad ptex face
                         has up to 2^l knot spans per direction; surfaces still above the
                         tolerance at max_level are kept and counted in over_tolerance_count */
  uint32_t min_level; /* smallest knot level tried, 1..max_level (default 1) */
  double max_normal_jump_deg; /* a surface whose normal jumps by more than this many degrees across a
                                 smooth border gets more knots, as one over the tolerance; finite
                                 and > 0 (default 0.5) */
  uint32_t threads;   /* worker threads for the surface fits, 0..1024; 0 (default) = the number of
                         hardware threads. The surfaces do not depend on it. */
} cagekit_limit_surface_options;

#define CAGEKIT_LIMIT_SURFACE_OPTIONS_INIT { sizeof(cagekit_limit_surface_options), 1e-4, 5, 1, 0.5, 0 }

typedef struct cagekit_limit_surface_info {
  size_t struct_size;              /* set by the caller: sizeof(cagekit_limit_surface_info) */
  uint32_t surface_count;          /* exact_count + approximated_count */
  uint32_t exact_count;            /* surfaces equal to the limit surface */
  uint32_t approximated_count;
  uint32_t over_tolerance_count;   /* approximated surfaces above the tolerance or folded (max_level
                                      reached) */
  uint32_t folded_count;           /* surfaces whose normal deviates from the limit's by more than
                                      90 degrees somewhere */
  uint32_t level;                  /* the largest knot level used (2^level spans per quad side) */
  uint32_t ptex_face_count;        /* ptex faces of the cage, holes included */
  uint32_t limit_fold_points;      /* border samples left out of max_normal_jump_deg because the
                                      limit surface itself folds or is degenerate there (its own
                                      normals on the two sides > 30 degrees apart, or its
                                      derivatives nearly parallel): a fault of the cage */
  double max_error;                /* largest two-sided error of a surface, model units */
  double max_error_rel;            /* max_error / bbox_diagonal */
  double max_parametric_error;     /* largest parametric error of a surface, model units */
  double max_normal_deviation_deg; /* largest angle between a surface's normal and the limit's */
  double max_normal_jump_deg;      /* largest normal jump across smooth shared borders, degrees */
  double max_crease_angle_deg;     /* largest normal jump across crease / non-manifold borders, degrees */
  double bbox_diagonal;            /* of the cage's control points */
  double tolerance;                /* the absolute tolerance: options.tolerance * bbox_diagonal */
} cagekit_limit_surface_info;

/* What lies across one side of a surface. */
typedef enum cagekit_surface_border_kind {
  CAGEKIT_SURFACE_BORDER_BOUNDARY = 0,     /* a boundary edge (or next to a hole): no neighbour */
  CAGEKIT_SURFACE_BORDER_SMOOTH = 1,       /* shared with one neighbour, tangent-continuous (G1) */
  CAGEKIT_SURFACE_BORDER_CREASE = 2,       /* shared along an infinitely sharp crease (C0) */
  CAGEKIT_SURFACE_BORDER_NON_MANIFOLD = 3, /* a cage edge in more than two faces (sharp, C0): the
                                              border curve is shared by all of them */
  CAGEKIT_SURFACE_BORDER_KIND_MAX_ENUM = 0x7fffffff
} cagekit_surface_border_kind;

/* A parameter direction of a surface. */
typedef enum cagekit_surface_direction {
  CAGEKIT_SURFACE_DIRECTION_U = 0,
  CAGEKIT_SURFACE_DIRECTION_V = 1,
  CAGEKIT_SURFACE_DIRECTION_MAX_ENUM = 0x7fffffff
} cagekit_surface_direction;

/* One side of a surface. Sides: 0 is v = 0 (parameter u), 1 is u = 1 (parameter v), 2 is v = 1
 * (parameter u), 3 is u = 0 (parameter v). Not versioned: its layout is fixed for this ABI
 * version. */
typedef struct cagekit_limit_surface_side {
  cagekit_surface_border_kind kind;
  uint32_t neighbour_count;   /* 0 for boundaries; 1, or 2 where a quad side meets two n-gon
                                 sub-faces (each on half of it); more at non-manifold edges */
  double max_normal_jump_deg; /* measured along this side (0 for boundaries) */
} cagekit_limit_surface_side;

/* One surface, without its knots and control points (cagekit_limit_surfaces_get_knots,
 * cagekit_limit_surfaces_get_control_points). Not versioned: its layout is fixed for this ABI
 * version. */
typedef struct cagekit_limit_surface {
  uint32_t ptex_face;     /* ptex face (numbering of cagekit_surface_get_ptex_face); the surface's
                             (u, v) in [0,1]^2 is that ptex face's location (u, v) */
  uint32_t cage_face;     /* the cage face it belongs to */
  uint32_t degree_u, degree_v;
  uint32_t knot_count_u;  /* = num_u + degree_u + 1 */
  uint32_t knot_count_v;  /* = num_v + degree_v + 1 */
  uint32_t num_u, num_v;  /* control points per direction */
  cagekit_bool32 exact;   /* 1: the surface is the limit surface; 0: an approximation */
  uint32_t reserved;      /* 0 */
  double error;           /* two-sided distance to the limit surface, model units */
  double parametric_error; /* largest distance to the limit surface at equal parameters (>= error) */
  double max_normal_deviation_deg; /* largest angle between its normal and the limit's (> 90: folded) */
  cagekit_limit_surface_side sides[4];
} cagekit_limit_surface;

/* One neighbour along a side: the side's parameter range [t0, t1] and where it lies on the
 * neighbour's side: neighbour parameter = n0 + (t - t0) / (t1 - t0) * (n1 - n0) (n1 < n0: the
 * two run in opposite directions). Not versioned: its layout is fixed for this ABI version. */
typedef struct cagekit_limit_surface_neighbour {
  uint32_t surface; /* the neighbour's index (as for cagekit_limit_surfaces_get_surface) */
  uint32_t side;    /* the neighbour's side, 0..3 */
  double t0, t1;    /* the range on this side */
  double n0, n1;    /* the same range on the neighbour's side */
} cagekit_limit_surface_neighbour;

/* Builds the B-spline surfaces of `cage`'s limit surface. options may be NULL (defaults). Long
 * operation (progress stage "limit B-spline surfaces", cancel).
 * Ownership: *out receives one reference (release it with cagekit_limit_surfaces_release).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (out NULL, bad struct_size or options, min_level above
 *   max_level), INVALID_MESH (a cage that cannot be subdivided), CANCELLED, OUT_OF_MEMORY (also
 *   against the context's memory budget).
 * Threading: reads `cage`; thread-safe. The result is immutable and may be read from several
 *   threads at once. */
CAGEKIT_API cagekit_status cagekit_limit_surfaces_create(cagekit_cage cage,
                                                         const cagekit_limit_surface_options* options,
                                                         cagekit_limit_surfaces* out);
/* Adds a reference (retain) or drops one (release; the last one destroys the surfaces). NULL is
 * ignored.
 * Errors: none.
 * Threading: any thread (the reference count is atomic). */
CAGEKIT_API void cagekit_limit_surfaces_retain(cagekit_limit_surfaces surfaces);
CAGEKIT_API void cagekit_limit_surfaces_release(cagekit_limit_surfaces surfaces);
/* Counts, errors and normal jumps of the surfaces, into *info.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (info NULL or bad struct_size).
 * Threading: reads `surfaces`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_limit_surfaces_get_info(cagekit_limit_surfaces surfaces,
                                                           cagekit_limit_surface_info* info);
/* Surface `index` (0 .. surface_count - 1, ordered by ptex face) into *surface.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (surface NULL, index out of range).
 * Threading: reads `surfaces`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_limit_surfaces_get_surface(cagekit_limit_surfaces surfaces, uint32_t index,
                                                              cagekit_limit_surface* surface);
/* The knot vector of surface `index` in `direction`: knot_count_u (or _v) values, nondecreasing,
 * from 0 to 1, the end knots repeated degree + 1 times. Two-call (Buffers) over knots.
 * Ownership: `knots` is the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (index out of range, direction not a
 *   cagekit_surface_direction, knot_count_out NULL, knots NULL with a nonzero capacity),
 *   SIZE_INSUFFICIENT.
 * Threading: reads `surfaces`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_limit_surfaces_get_knots(cagekit_limit_surfaces surfaces, uint32_t index,
                                                            cagekit_surface_direction direction,
                                                            uint32_t knot_capacity, uint32_t* knot_count_out,
                                                            double* knots);
/* The control points of surface `index` as xyz triples, row-major with u inner: point (i, j)
 * (i along u, 0 .. num_u - 1; j along v) is points[3 * (j * num_u + i) + 0..2], with weight
 * N_i(u) N_j(v) (the B-spline basis functions of the knot vectors). Two-call (Buffers) over
 * points (num_u * num_v of them).
 * Ownership: `points` is the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (index out of range, point_count_out NULL, points NULL
 *   with a nonzero capacity), SIZE_INSUFFICIENT.
 * Threading: reads `surfaces`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_limit_surfaces_get_control_points(cagekit_limit_surfaces surfaces, uint32_t index,
                                                                     uint32_t point_capacity,
                                                                     uint32_t* point_count_out, double* points);
/* The neighbours of surface `index` across its side `side` (0..3, see cagekit_limit_surface_side),
 * each with the part of the side it covers. Two-call (Buffers) over neighbours (the side's neighbour_count).
 * Ownership: `neighbours` is the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (index out of range, side above 3, neighbour_count_out
 *   NULL, neighbours NULL with a nonzero capacity), SIZE_INSUFFICIENT.
 * Threading: reads `surfaces`; thread-safe. */
CAGEKIT_API cagekit_status cagekit_limit_surfaces_get_neighbours(cagekit_limit_surfaces surfaces, uint32_t index,
                                                                 uint32_t side, uint32_t neighbour_capacity,
                                                                 uint32_t* neighbour_count_out,
                                                                 cagekit_limit_surface_neighbour* neighbours);

/* ------------------------------------------------------------------------------------------ */
/* Rendering: pictures of meshes, cages (their limit surfaces) and error maps                 */
/* ------------------------------------------------------------------------------------------ */

/* A scene of items drawn into one RGBA8 image: a mesh (its polygons, shaded), a cage (drawn as
 * its Catmull-Clark limit surface, tessellated by uniform refinement with limit positions, with
 * optional wireframe of the control edges and crease-tagged edges in their own colour) or a
 * deformed scan (a mesh with another default colour). Items are laid out in columns (an item
 * with `overlay` set shares its predecessor's column), views in rows; a scene whose items fill a
 * single column lays several views out row-major in a near-square grid instead (as many grid
 * columns as make the tiles closest to square; ties: fewer empty tiles, then fewer columns).
 * Every view is framed automatically on the bounding box of all items, so all columns share one
 * scale. Per item a
 * per-vertex scalar can colour the surface through a colour map, with a legend (a bar and its
 * min / max labels); text is drawn with a 5x7 bitmap font compiled into the library.
 *
 * Drawing needs OpenGL 3.3 (core or compatibility) or OpenGL ES 3.0. cagekit_render_scene_draw
 * makes its own headless context: libEGL is loaded at run time (libcagekit has no link-time
 * dependency on EGL or GL), the display is the first EGL device that is not a software renderer
 * (EGL_EXT_platform_device) or else Mesa's surfaceless platform (llvmpipe when there is no GPU);
 * desktop GL 3.3 core is tried first, then GLES 3.0. The drawing goes to a framebuffer object of
 * the library (RGBA8 + 24-bit depth, no multisampling): the same scene gives the same bytes on
 * the same driver. cagekit_gl_render_scene_draw (cagekit_gl.h) draws in the host's current GL
 * context instead.
 *
 * Builds made without the render module (CMake CAGEKIT_WITH_RENDER=OFF) keep every function
 * below; each returns CAGEKIT_ERROR_UNSUPPORTED_FEATURE ("built without the render module"),
 * except retain / release, which ignore their argument. */
typedef struct cagekit_render_scene_t* cagekit_render_scene;

typedef enum cagekit_render_item_kind {
  CAGEKIT_RENDER_ITEM_MESH = 0,          /* added with cagekit_render_scene_add_mesh */
  CAGEKIT_RENDER_ITEM_CAGE = 1,          /* added with cagekit_render_scene_add_cage */
  CAGEKIT_RENDER_ITEM_DEFORMED_SCAN = 2, /* a mesh drawn in the deformed-scan colour */
  CAGEKIT_RENDER_ITEM_KIND_MAX_ENUM = 0x7fffffff
} cagekit_render_item_kind;

/* Colour maps of per-vertex scalars: the value range_min maps to the first colour, range_max to
 * the last, linearly. VIRIDIS: matplotlib's viridis (dark purple -> blue -> green -> yellow),
 * for magnitudes such as distances. BLUE_WHITE_RED: diverging blue -> white -> red, for signed
 * values centred on zero (give a symmetric range). */
typedef enum cagekit_render_colormap {
  CAGEKIT_RENDER_COLORMAP_VIRIDIS = 0,
  CAGEKIT_RENDER_COLORMAP_BLUE_WHITE_RED = 1,
  CAGEKIT_RENDER_COLORMAP_MAX_ENUM = 0x7fffffff
} cagekit_render_colormap;

/* Views. FRONT looks along -z (up +y), SIDE along -x (up +y), TOP along -y (up -z), ISO from
 * the (+x, +y, +z) octant (up +y); each is framed on the scene's bounding box. CUSTOM uses the
 * camera's eye, target and up as given. All views are perspective with the camera's fov. */
typedef enum cagekit_render_view {
  CAGEKIT_RENDER_VIEW_FRONT = 0,
  CAGEKIT_RENDER_VIEW_SIDE = 1,
  CAGEKIT_RENDER_VIEW_TOP = 2,
  CAGEKIT_RENDER_VIEW_ISO = 3,
  CAGEKIT_RENDER_VIEW_CUSTOM = 4,
  CAGEKIT_RENDER_VIEW_MAX_ENUM = 0x7fffffff
} cagekit_render_view;

/* Which EGL display the headless draw uses: AUTO (the first EGL device that is not a software
 * renderer, else Mesa's surfaceless platform), SURFACELESS (Mesa's surfaceless platform only),
 * DEVICE (the first EGL device of any kind, software included). */
typedef enum cagekit_render_display {
  CAGEKIT_RENDER_DISPLAY_AUTO = 0,
  CAGEKIT_RENDER_DISPLAY_SURFACELESS = 1,
  CAGEKIT_RENDER_DISPLAY_DEVICE = 2,
  CAGEKIT_RENDER_DISPLAY_MAX_ENUM = 0x7fffffff
} cagekit_render_display;

/* Colours are RGBA with components in [0, 1]; an alpha of 0 in an item colour means "the
 * default" (surface: light grey for meshes, light blue for cages, tan for deformed scans;
 * wireframe: near black; creases: magenta-red (0.90, 0.15, 0.55), a colour no shaded surface
 * or colour map produces). */
typedef struct cagekit_render_item_options {
  size_t struct_size;             /* sizeof(cagekit_render_item_options) */
  cagekit_bool32 surface;         /* draw the shaded surface (default 1) */
  cagekit_bool32 wireframe;       /* mesh: its edges; cage: the control mesh's edges (default 0) */
  cagekit_bool32 creases;         /* cage: the crease-tagged control edges and the crease curves on the
                                     limit surface, in crease_color (default 0; ignored for meshes) */
  cagekit_bool32 overlay;         /* 1: drawn in the previous item's column, over it (default 0) */
  uint32_t tessellation_level;    /* cage: uniform refinement levels of the limit surface, 1..6;
                                     0 (default) = automatic: the largest level <= 4 that keeps
                                     <= 262144 faces, at least 1 */
  float color[4];                 /* surface colour (alpha 0: default) */
  float wire_color[4];            /* wireframe colour (alpha 0: default) */
  float crease_color[4];          /* crease colour (alpha 0: default) */
  const char* title;              /* drawn above the item's column in the first row; NULL = none.
                                     Copied. */
} cagekit_render_item_options;

#define CAGEKIT_RENDER_ITEM_OPTIONS_INIT \
  { sizeof(cagekit_render_item_options), 1, 0, 0, 0, 0, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, NULL }

typedef struct cagekit_render_scalar_options {
  size_t struct_size;               /* sizeof(cagekit_render_scalar_options) */
  cagekit_render_colormap colormap; /* default VIRIDIS */
  cagekit_bool32 auto_range;        /* 1 (default): the range is [min, max] of the values */
  double range_min, range_max;      /* the range when auto_range is 0 (range_min < range_max) */
  cagekit_bool32 legend;            /* 1 (default): a colour bar with the range's min / max labels */
  const char* label;                /* the quantity's name above the legend; NULL = none
                                       ("distance to scan" for cagekit_render_scene_set_distance_to_scan).
                                       Copied. */
} cagekit_render_scalar_options;

#define CAGEKIT_RENDER_SCALAR_OPTIONS_INIT \
  { sizeof(cagekit_render_scalar_options), CAGEKIT_RENDER_COLORMAP_VIRIDIS, 1, 0.0, 0.0, 1, NULL }

typedef struct cagekit_render_camera {
  size_t struct_size;       /* sizeof(cagekit_render_camera) */
  cagekit_render_view view; /* default ISO */
  double eye[3];            /* CUSTOM only: camera position, the point it looks at and its up */
  double target[3];         /*   direction (not along eye - target) */
  double up[3];
  double fov_degrees;       /* vertical field of view, (1, 170) (default 30) */
} cagekit_render_camera;

#define CAGEKIT_RENDER_CAMERA_INIT \
  { sizeof(cagekit_render_camera), CAGEKIT_RENDER_VIEW_ISO, {0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 30.0 }

typedef struct cagekit_render_options {
  size_t struct_size;             /* sizeof(cagekit_render_options) */
  uint32_t width, height;         /* the whole image in pixels, 1..16384 each (default 800 x 600) */
  float background[4];            /* RGBA (default opaque white) */
  cagekit_bool32 labels;          /* 1 (default): titles, view names (with several views) and legends */
  cagekit_render_display display; /* headless draw only (default AUTO) */
  const char* egl_library;        /* headless draw only: the libEGL to load; NULL (default) = the
                                     environment variable CAGEKIT_EGL_LIBRARY if set, else
                                     "libEGL.so.1". A path that cannot be loaded makes the draw fail
                                     with UNSUPPORTED_FEATURE (tests use this). Copied. */
} cagekit_render_options;

#define CAGEKIT_RENDER_OPTIONS_INIT \
  { sizeof(cagekit_render_options), 800, 600, {1, 1, 1, 1}, 1, CAGEKIT_RENDER_DISPLAY_AUTO, NULL }

typedef struct cagekit_render_item_info {
  size_t struct_size;             /* sizeof(cagekit_render_item_info) */
  cagekit_render_item_kind kind;
  uint32_t column;                /* the item's column in the image */
  uint32_t vertex_count;          /* vertices of the drawn surface (the scalars' count) */
  uint32_t triangle_count;
  uint32_t tessellation_level;    /* cage: the level used; 0 for meshes */
  cagekit_bool32 has_scalars;
  double scalar_min, scalar_max;  /* the range the colour map and the legend show (0 without scalars) */
  double bounds_min[3], bounds_max[3]; /* bounding box of everything the item draws */
} cagekit_render_item_info;

/* Creates an empty scene (800 x 600, white background, one ISO view).
 * Ownership: *out receives one reference (release it with cagekit_render_scene_release); the
 *   scene keeps `context` alive.
 * Errors: INVALID_HANDLE (context), INVALID_ARGUMENT (out NULL), UNSUPPORTED_FEATURE (built
 *   without the render module), OUT_OF_MEMORY.
 * Threading: any thread (thread-safe). */
CAGEKIT_API cagekit_status cagekit_render_scene_create(cagekit_context context, cagekit_render_scene* out);
/* Adds a reference (retain) or drops one (release; the last one frees the scene). NULL is
 * ignored.
 * Errors: none.
 * Threading: any thread (the reference count is atomic). */
CAGEKIT_API void cagekit_render_scene_retain(cagekit_render_scene scene);
CAGEKIT_API void cagekit_render_scene_release(cagekit_render_scene scene);

/* Replaces the image settings. options may be NULL (the defaults).
 * Ownership: options and the string it points to are read during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (bad struct_size, a colour component outside [0, 1],
 *   labels not 0/1, display out of range), LIMIT_EXCEEDED (a side of 0 or above 16384).
 * Threading: modifies `scene` (no other call on it meanwhile). */
CAGEKIT_API cagekit_status cagekit_render_scene_set_options(cagekit_render_scene scene,
                                                            const cagekit_render_options* options);

/* The scene's current image settings, into *options (egl_library is NULL when none was set).
 * Ownership: options->egl_library points into the scene: valid until its next set_options or
 *   last release.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (options NULL or bad struct_size).
 * Threading: reads `scene`. */
CAGEKIT_API cagekit_status cagekit_render_scene_get_options(cagekit_render_scene scene, cagekit_render_options* options);

/* Replaces the views (rows of the image, or a grid for a single item column: see above):
 * view_count cameras, 1..64. The default is one ISO view.
 * Ownership: `cameras` is read during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (cameras NULL, view_count 0, bad struct_size, a view
 *   out of range, fov outside (1, 170), a CUSTOM camera with non-finite or degenerate eye /
 *   target / up: the message names the view), LIMIT_EXCEEDED (more than 64 views).
 * Threading: modifies `scene`. */
CAGEKIT_API cagekit_status cagekit_render_scene_set_views(cagekit_render_scene scene, uint32_t view_count,
                                                          const cagekit_render_camera* cameras);

/* Adds a mesh item (polygons fan-triangulated, smooth-shaded with area-weighted vertex normals)
 * of kind MESH or DEFORMED_SCAN; its index (0, 1, ... in the order added) goes to *item_out
 * (may be NULL). options may be NULL (defaults).
 * Ownership: the scene copies what it draws; `mesh` and options are read during the call only.
 * Errors: INVALID_HANDLE (scene, mesh), INVALID_ARGUMENT (bad struct_size, a boolean not 0/1, a
 *   colour outside [0, 1], kind CAGE or out of range), INVALID_MESH (an index out of range or a
 *   non-finite position, named), OUT_OF_MEMORY.
 * Threading: modifies `scene`; reads `mesh`. */
CAGEKIT_API cagekit_status cagekit_render_scene_add_mesh(cagekit_render_scene scene, cagekit_mesh mesh,
                                                         cagekit_render_item_kind kind,
                                                         const cagekit_render_item_options* options,
                                                         uint32_t* item_out);

/* Adds a cage item: its limit surface, tessellated at options->tessellation_level (the refined
 * vertices moved to their limit positions; hole faces left out), plus the control edges
 * (wireframe) and crease edges (creases) when asked. Long operation (progress, cancel).
 * Ownership: as cagekit_render_scene_add_mesh.
 * Errors: INVALID_HANDLE (scene, cage), INVALID_ARGUMENT (as add_mesh; a tessellation_level
 *   above 6), INVALID_MESH (a cage that cannot be subdivided), LIMIT_EXCEEDED (the refined
 *   surface would exceed 2^31 indices), CANCELLED, OUT_OF_MEMORY.
 * Threading: modifies `scene`; reads `cage`. */
CAGEKIT_API cagekit_status cagekit_render_scene_add_cage(cagekit_render_scene scene, cagekit_cage cage,
                                                         const cagekit_render_item_options* options,
                                                         uint32_t* item_out);

/* Colours item `item` by a per-vertex scalar: `values` holds one value per vertex of the drawn
 * surface (cagekit_render_item_info.vertex_count: the mesh's vertices, or the tessellated limit
 * surface's, in the order of cagekit_render_scene_get_item_geometry). Replaces earlier scalars.
 * options may be NULL (defaults).
 * Ownership: values and options (and its label) are read during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (item out of range, values NULL with a nonzero count,
 *   value_count not the vertex count, a non-finite value, bad struct_size, colormap out of range,
 *   a boolean not 0/1, range_min >= range_max without auto_range), OUT_OF_MEMORY.
 * Threading: modifies `scene`. */
CAGEKIT_API cagekit_status cagekit_render_scene_set_scalars(cagekit_render_scene scene, uint32_t item,
                                                            uint32_t value_count, const double* values,
                                                            const cagekit_render_scalar_options* options);

/* Colours item `item` by its two-sided distance to `scan` (absolute, in the scan's units): each
 * vertex v of the drawn surface gets max(distance from v to the scan's surface, the distances to
 * the drawn surface of the scan vertices whose nearest drawn triangle has v as a corner). The
 * largest value is thus the symmetric vertex-to-surface Hausdorff distance between the drawn
 * surface and the scan, and a spike of either one shows where it is. Exact point-to-triangle
 * distances. The values are then set as by cagekit_render_scene_set_scalars (read them back with
 * cagekit_render_scene_get_scalars). Long operation (progress, cancel).
 * Ownership: `scan` and options are read during the call only.
 * Errors: INVALID_HANDLE (scene, scan), INVALID_ARGUMENT (item out of range, options as
 *   set_scalars), INVALID_MESH (a scan with bad indices or no non-degenerate triangle), CANCELLED,
 *   OUT_OF_MEMORY.
 * Threading: modifies `scene`; reads `scan`. */
CAGEKIT_API cagekit_status cagekit_render_scene_set_distance_to_scan(cagekit_render_scene scene, uint32_t item,
                                                                     cagekit_mesh scan,
                                                                     const cagekit_render_scalar_options* options);

/* The item's scalars (one per drawn vertex; 0 values without scalars). Two-call (Buffers) over
 * the values.
 * Ownership: `values` is the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (item out of range, value_count_out NULL, values NULL
 *   with a nonzero capacity), SIZE_INSUFFICIENT.
 * Threading: reads `scene`. */
CAGEKIT_API cagekit_status cagekit_render_scene_get_scalars(cagekit_render_scene scene, uint32_t item,
                                                            uint32_t value_capacity, uint32_t* value_count_out,
                                                            double* values);

/* The drawn surface of an item: positions (xyz per vertex, as drawn: single precision widened to
 * double) and triangles (three vertex indices each). Two-call (Buffers) on each array, over
 * vertices and over triangles; both counts are written before either capacity is checked.
 * Ownership: the arrays are the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (item out of range, a count pointer NULL, an array
 *   NULL with a nonzero capacity), SIZE_INSUFFICIENT.
 * Threading: reads `scene`. */
CAGEKIT_API cagekit_status cagekit_render_scene_get_item_geometry(cagekit_render_scene scene, uint32_t item,
                                                                  uint32_t vertex_capacity, uint32_t* vertex_count_out,
                                                                  double* positions, uint32_t triangle_capacity,
                                                                  uint32_t* triangle_count_out, uint32_t* triangles);

/* The number of items, into *count.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (count NULL).
 * Threading: reads `scene`. */
CAGEKIT_API cagekit_status cagekit_render_scene_get_item_count(cagekit_render_scene scene, uint32_t* count);

/* Facts about item `item` (kind, column, counts, level, the scalar range shown, bounds).
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (item out of range, info NULL or bad struct_size).
 * Threading: reads `scene`. */
CAGEKIT_API cagekit_status cagekit_render_scene_get_item_info(cagekit_render_scene scene, uint32_t item,
                                                              cagekit_render_item_info* info);

/* Draws the scene in a headless GL context of the library's own (above) and copies the image
 * into `rgba`: width x height pixels of 4 bytes (R, G, B, A), rows top first, tightly packed.
 * Two-call (Buffers) over pixels (capacity in pixels, 4 bytes each; the count is width * height).
 * With pixel_capacity 0 nothing is drawn. The EGL context that was current on the calling thread
 * (if any, made by the same libEGL) is current again when the call returns; a host whose GL
 * context is not an EGL one (GLX, WGL) should call this on a thread without a current context,
 * or use cagekit_gl_render_scene_draw.
 * Ownership: `rgba` is the caller's, written during the call only.
 * Errors: INVALID_HANDLE, INVALID_ARGUMENT (pixel_count_out NULL, rgba NULL with a nonzero
 *   capacity), SIZE_INSUFFICIENT, UNSUPPORTED_FEATURE (no EGL library, display or context could be
 *   made: the message names the library, platform, extension or version missing; a shader that
 *   does not compile), LIMIT_EXCEEDED (an image above the context's framebuffer limits),
 *   OUT_OF_MEMORY.
 * Threading: reads `scene`; several threads may draw different scenes (or the same one) at once,
 *   each in its own context. */
CAGEKIT_API cagekit_status cagekit_render_scene_draw(cagekit_render_scene scene, uint32_t pixel_capacity,
                                                     uint32_t* pixel_count_out, uint8_t* rgba);

/* Draws as cagekit_render_scene_draw and writes the image as a PNG file (8-bit RGBA, libpng).
 * Ownership: `path` is read during the call only.
 * Errors: those of cagekit_render_scene_draw (SIZE_INSUFFICIENT excepted), INVALID_ARGUMENT (path
 *   NULL), IO (the file cannot be written: the message names it).
 * Threading: as cagekit_render_scene_draw. */
CAGEKIT_API cagekit_status cagekit_render_scene_write_png(cagekit_render_scene scene, const char* path);

/* Draws as cagekit_render_scene_draw and encodes the image as PNG bytes in a new blob.
 * Ownership: *out receives one reference (release it with cagekit_blob_release).
 * Errors: those of cagekit_render_scene_draw (SIZE_INSUFFICIENT excepted), INVALID_ARGUMENT (out
 *   NULL).
 * Threading: as cagekit_render_scene_draw. */
CAGEKIT_API cagekit_status cagekit_render_scene_encode_png(cagekit_render_scene scene, cagekit_blob* out);

/* Encodes a caller's RGBA8 image (width x height pixels, rows top first, tightly packed; e.g. one
 * drawn by cagekit_gl_render_scene_draw) as a PNG file (`path` not NULL) or, when path is NULL,
 * as PNG bytes in a new blob (*out).
 * Ownership: rgba and path are read during the call only; *out (path NULL) receives one reference.
 * Errors: INVALID_HANDLE (context), INVALID_ARGUMENT (rgba NULL, out NULL with a NULL path),
 *   LIMIT_EXCEEDED (a side of 0 or above 16384), IO (the file cannot be written),
 *   UNSUPPORTED_FEATURE (built without the render module), OUT_OF_MEMORY.
 * Threading: any thread (thread-safe). */
CAGEKIT_API cagekit_status cagekit_render_encode_png(cagekit_context context, const uint8_t* rgba, uint32_t width,
                                                     uint32_t height, const char* path, cagekit_blob* out);

#ifdef __cplusplus
}
#endif

#endif /* CAGEKIT_CAGEKIT_H */
