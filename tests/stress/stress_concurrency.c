/* SPDX-License-Identifier: GPL-3.0-or-later
 * Concurrency stress test of libcagekit through the public C API only (C99 + pthreads).
 *
 * It checks exactly the thread-safety guarantees that <cagekit/cagekit.h> documents:
 *  - every function may run concurrently on DIFFERENT objects (each thread makes its own meshes,
 *    cages, hierarchies, blobs);
 *  - one object may be used by several threads at once through calls documented as "Reads"
 *    (shared mesh: validate/get_info/repair/get_*; shared cage: write_memory/subdivide/limit
 *    points/surface_create/get_*; shared surface: everything; shared hierarchy: level info, current
 *    info, faces, clusters, build_cage, polygon mesh);
 *  - set_level ("Modifies") is only called on a thread's own hierarchy;
 *  - retain/release of one handle from many threads;
 *  - a context is shared by all threads and keeps the last error per thread: a thread's own
 *    failure message must not be replaced by other threads' failures, and a thread that never
 *    failed sees "";
 *  - cagekit_context_cancel() from another thread stops the long operations of that context
 *    (and only of that context).
 * Every result is compared with a single-threaded reference computed first (bitwise for
 * positions, reports and encoded bytes). Built with -fsanitize=thread in packaging/test-all.sh.
 *
 * Usage: stress_concurrency [iterations per thread] [threads]   (defaults 4 and 6) */
#include <cagekit/cagekit.h>

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------------------------------ */
/* Thread-safe checks                                                                          */
/* ------------------------------------------------------------------------------------------ */

static pthread_mutex_t g_fail_mutex = PTHREAD_MUTEX_INITIALIZER;
static int g_failures = 0;

static void record_failure(const char* file, int line, int tid, const char* what) {
  pthread_mutex_lock(&g_fail_mutex);
  ++g_failures;
  if (g_failures <= 50) fprintf(stderr, "%s:%d: [thread %d] CHECK failed: %s\n", file, line, tid, what);
  pthread_mutex_unlock(&g_fail_mutex);
}

#define CHECK_T(tid, cond)                                               \
  do {                                                                   \
    if (!(cond)) record_failure(__FILE__, __LINE__, (tid), #cond);       \
  } while (0)

#define CHECK_ST(tid, expr, expected)                                                      \
  do {                                                                                     \
    cagekit_status s_ = (expr);                                                            \
    if (s_ != (expected)) {                                                                \
      char b_[512];                                                                        \
      snprintf(b_, sizeof b_, "%s returned %d (%s), expected %d", #expr, (int)s_,          \
               cagekit_status_string(s_), (int)(expected));                                \
      record_failure(__FILE__, __LINE__, (tid), b_);                                       \
    }                                                                                      \
  } while (0)

#define CHECK_OK_T(tid, expr) CHECK_ST(tid, expr, CAGEKIT_SUCCESS)

/* FNV-1a over bytes: a compact fingerprint of an array compared with the reference's. */
static uint64_t fnv(uint64_t h, const void* data, size_t size) {
  const unsigned char* p = (const unsigned char*)data;
  size_t i;
  for (i = 0; i < size; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}
#define FNV_SEED 1469598103934665603ull

/* ------------------------------------------------------------------------------------------ */
/* Test geometry: a torus (quads for the cage, triangles for meshes and hierarchies)          */
/* ------------------------------------------------------------------------------------------ */

typedef struct geometry {
  uint32_t nv, nf;
  double* positions;
  uint32_t* indices;
  uint32_t face_size;
} geometry;

static void make_torus(uint32_t nu, uint32_t nv, int triangles, geometry* g) {
  uint32_t i, j, f = 0;
  g->nv = nu * nv;
  g->face_size = triangles ? 3 : 4;
  g->nf = nu * nv * (triangles ? 2 : 1);
  g->positions = (double*)malloc(sizeof(double) * 3 * g->nv);
  g->indices = (uint32_t*)malloc(sizeof(uint32_t) * g->face_size * g->nf);
  for (i = 0; i < nu; ++i)
    for (j = 0; j < nv; ++j) {
      const double a = 6.283185307179586 * i / nu, b = 6.283185307179586 * j / nv;
      /* a slightly bumpy torus, so that simplification has real decisions to make */
      const double r = 0.35 + 0.03 * sin(3.0 * a) * cos(2.0 * b);
      double* p = g->positions + 3 * (i * nv + j);
      p[0] = (1.0 + r * cos(b)) * cos(a);
      p[1] = (1.0 + r * cos(b)) * sin(a);
      p[2] = r * sin(b);
    }
  for (i = 0; i < nu; ++i)
    for (j = 0; j < nv; ++j) {
      const uint32_t v00 = i * nv + j, v10 = ((i + 1) % nu) * nv + j;
      const uint32_t v01 = i * nv + (j + 1) % nv, v11 = ((i + 1) % nu) * nv + (j + 1) % nv;
      if (triangles) {
        uint32_t* t = g->indices + 3 * f;
        t[0] = v00, t[1] = v10, t[2] = v11, t[3] = v00, t[4] = v11, t[5] = v01;
        f += 2;
      } else {
        uint32_t* q = g->indices + 4 * f;
        q[0] = v00, q[1] = v10, q[2] = v11, q[3] = v01;
        f += 1;
      }
    }
}

static cagekit_status create_mesh(cagekit_context context, const geometry* g, uint32_t face_count,
                                  const uint32_t* indices, cagekit_mesh* out) {
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  desc.vertex_count = g->nv;
  desc.positions = g->positions;
  desc.face_count = face_count;
  desc.uniform_face_size = g->face_size;
  desc.face_indices = indices;
  return cagekit_mesh_create(context, &desc, out);
}

/* ------------------------------------------------------------------------------------------ */
/* Fingerprints of results                                                                    */
/* ------------------------------------------------------------------------------------------ */

/* Positions + faces of a mesh. */
static uint64_t mesh_fingerprint(cagekit_mesh mesh) {
  uint32_t nv = 0, nf = 0;
  uint64_t ni = 0, h = FNV_SEED;
  double* p;
  uint32_t *sizes, *indices;
  if (cagekit_mesh_get_counts(mesh, &nv, &nf, &ni) != CAGEKIT_SUCCESS) return 0;
  p = (double*)malloc(sizeof(double) * 3 * (nv + 1));
  sizes = (uint32_t*)malloc(sizeof(uint32_t) * (nf + 1));
  indices = (uint32_t*)malloc(sizeof(uint32_t) * (size_t)(ni + 1));
  if (cagekit_mesh_get_positions(mesh, CAGEKIT_SCALAR_FLOAT64, nv, &nv, p) != CAGEKIT_SUCCESS ||
      cagekit_mesh_get_faces(mesh, nf, &nf, sizes, ni, &ni, indices) != CAGEKIT_SUCCESS)
    h = 0;
  else {
    h = fnv(h, &nv, sizeof nv);
    h = fnv(h, &nf, sizeof nf);
    h = fnv(h, p, sizeof(double) * 3 * nv);
    h = fnv(h, sizes, sizeof(uint32_t) * nf);
    h = fnv(h, indices, sizeof(uint32_t) * (size_t)ni);
  }
  free(p);
  free(sizes);
  free(indices);
  return h;
}

/* Control mesh + creases + corners + holes + boundary rule of a cage. */
static uint64_t cage_fingerprint(cagekit_cage cage) {
  cagekit_mesh mesh = NULL;
  uint64_t h;
  uint32_t n = 0, pairs[2 * 4096], corners[4096], holes[4096];
  float sharp[4096];
  cagekit_boundary_rule rule = CAGEKIT_BOUNDARY_EDGES_ONLY;
  if (cagekit_cage_get_mesh(cage, &mesh) != CAGEKIT_SUCCESS) return 0;
  h = mesh_fingerprint(mesh);
  cagekit_mesh_release(mesh);
  if (cagekit_cage_get_creases(cage, 4096, &n, pairs, sharp) != CAGEKIT_SUCCESS) return 0;
  h = fnv(h, &n, sizeof n);
  h = fnv(h, pairs, sizeof(uint32_t) * 2 * n);
  h = fnv(h, sharp, sizeof(float) * n);
  if (cagekit_cage_get_corners(cage, 4096, &n, corners, sharp) != CAGEKIT_SUCCESS) return 0;
  h = fnv(h, &n, sizeof n);
  h = fnv(h, corners, sizeof(uint32_t) * n);
  h = fnv(h, sharp, sizeof(float) * n);
  if (cagekit_cage_get_holes(cage, 4096, &n, holes) != CAGEKIT_SUCCESS) return 0;
  h = fnv(h, &n, sizeof n);
  h = fnv(h, holes, sizeof(uint32_t) * n);
  if (cagekit_cage_get_boundary_rule(cage, &rule) != CAGEKIT_SUCCESS) return 0;
  return fnv(h, &rule, sizeof rule);
}

static uint64_t info_fingerprint(const cagekit_mesh_info* info) {
  /* field by field (no padding bytes involved) */
  uint64_t h = FNV_SEED;
  h = fnv(h, &info->vertices, sizeof(uint64_t) * 10);
  h = fnv(h, &info->genus, sizeof info->genus);
  h = fnv(h, &info->manifold, sizeof info->manifold);
  h = fnv(h, info->bbox_min, sizeof info->bbox_min);
  h = fnv(h, info->bbox_max, sizeof info->bbox_max);
  h = fnv(h, &info->bbox_diagonal, sizeof info->bbox_diagonal);
  h = fnv(h, &info->creases, sizeof(uint64_t) * 4);
  return h;
}

static uint64_t current_level_fingerprint(cagekit_hierarchy hierarchy) {
  cagekit_polygonal_level_info info;
  uint32_t nf = 0, nl = 0, nc = 0, *loops, *sizes, *verts, *clusters;
  uint64_t ni = 0, h = FNV_SEED;
  memset(&info, 0, sizeof info);
  info.struct_size = sizeof info;
  if (cagekit_hierarchy_get_current_info(hierarchy, &info) != CAGEKIT_SUCCESS) return 0;
  h = fnv(h, &info.level, sizeof info.level);
  h = fnv(h, &info.faces, sizeof(uint64_t) * 4);
  h = fnv(h, &info.l2_error, sizeof(double) * 2);
  if (cagekit_hierarchy_get_faces(hierarchy, 0, &nf, NULL, 0, &nl, NULL, 0, &ni, NULL) != CAGEKIT_SUCCESS) return 0;
  loops = (uint32_t*)malloc(sizeof(uint32_t) * (nf + 1));
  sizes = (uint32_t*)malloc(sizeof(uint32_t) * (nl + 1));
  verts = (uint32_t*)malloc(sizeof(uint32_t) * (size_t)(ni + 1));
  if (cagekit_hierarchy_get_faces(hierarchy, nf, &nf, loops, nl, &nl, sizes, ni, &ni, verts) != CAGEKIT_SUCCESS ||
      cagekit_hierarchy_get_clusters(hierarchy, 0, &nc, NULL) != CAGEKIT_SUCCESS)
    h = 0;
  else {
    h = fnv(h, loops, sizeof(uint32_t) * nf);
    h = fnv(h, sizes, sizeof(uint32_t) * nl);
    h = fnv(h, verts, sizeof(uint32_t) * (size_t)ni);
    clusters = (uint32_t*)malloc(sizeof(uint32_t) * (nc + 1));
    if (cagekit_hierarchy_get_clusters(hierarchy, nc, &nc, clusters) != CAGEKIT_SUCCESS) h = 0;
    else h = fnv(h, clusters, sizeof(uint32_t) * nc);
    free(clusters);
  }
  free(loops);
  free(sizes);
  free(verts);
  return h;
}

/* ------------------------------------------------------------------------------------------ */
/* Shared state and the single-threaded reference                                             */
/* ------------------------------------------------------------------------------------------ */

#define MAX_LEVELS 4096
#define EVAL_COUNT 64
#define CHURN 200

typedef struct reference {
  uint64_t tri_mesh_info, tri_mesh_fp;
  cagekit_validation_report broken_report;
  uint64_t repaired_fp;
  cagekit_repair_report repair_report;
  unsigned char obj_bytes_fp_and_size[16];
  uint64_t obj_fp, drc_fp;          /* encoded bytes */
  size_t obj_size, drc_size;
  uint64_t obj_read_fp, drc_read_fp; /* cages read back */
  uint64_t subdiv_fp, limit_fp, cage_info_fp;
  cagekit_surface_point points[EVAL_COUNT];
  uint64_t basis_fp;
  uint32_t level_count;
  uint64_t level_info_fp;           /* get_level_info of every level */
  uint32_t probe_levels[3];
  uint64_t probe_fp[3];             /* current level fingerprint after set_level(probe) */
  uint64_t shared_level_fp;         /* of the shared hierarchy at its (fixed) level */
  uint64_t built_cage_fp, polygon_mesh_fp;
  uint64_t cancel_subdiv_fp;
  uint64_t fit_fp;                  /* the shared cage fitted to the shared mesh (threads = 1) */
  uint64_t bind_info_fp, deform_fp; /* binding info; positions + normals for moved control points */
} reference;

static geometry g_tri, g_quad, g_big;
static uint32_t* g_broken_indices; /* g_tri's faces + a duplicate face + an out-of-range face */
static uint32_t g_broken_face_count;
static cagekit_surface_location g_locations[EVAL_COUNT];
static reference g_ref;

static cagekit_context g_context;    /* shared by every worker */
static cagekit_context g_cancel_ctx; /* the cancellation scenario's own context */
static cagekit_mesh g_shared_mesh;
static cagekit_cage g_shared_cage, g_cancel_cage;
static cagekit_surface g_shared_surface;
static cagekit_hierarchy g_shared_hierarchy;
static cagekit_binding g_shared_binding; /* immutable: read by every worker's own deformer */
static int g_iterations = 4;

static uint64_t blob_fp(cagekit_blob blob) { return fnv(FNV_SEED, cagekit_blob_data(blob), cagekit_blob_size(blob)); }

static uint64_t level_info_fp(int tid, cagekit_hierarchy h, uint32_t count) {
  uint64_t fp = FNV_SEED;
  uint32_t l;
  for (l = 0; l < count; ++l) {
    cagekit_level_info info;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    CHECK_OK_T(tid, cagekit_hierarchy_get_level_info(h, l, &info));
    fp = fnv(fp, &info.faces, sizeof(uint64_t) * 2);
    fp = fnv(fp, &info.error, sizeof(double));
  }
  return fp;
}

static uint64_t built_cage_fp(int tid, cagekit_hierarchy h) {
  cagekit_cage cage = NULL;
  uint64_t fp = 0;
  CHECK_OK_T(tid, cagekit_hierarchy_build_cage(h, NULL, &cage, NULL));
  if (cage) fp = cage_fingerprint(cage);
  cagekit_cage_release(cage);
  return fp;
}

static uint64_t polygon_mesh_fp(int tid, cagekit_hierarchy h) {
  cagekit_mesh mesh = NULL;
  uint64_t fp = 0;
  CHECK_OK_T(tid, cagekit_hierarchy_get_polygon_mesh(h, &mesh));
  if (mesh) fp = mesh_fingerprint(mesh);
  cagekit_mesh_release(mesh);
  return fp;
}

/* Encodes the shared cage, reads it back; fingerprints of bytes and read-back cage. */
static void encode_and_read(int tid, cagekit_file_format format, uint64_t* bytes_fp, size_t* size, uint64_t* read_fp) {
  cagekit_write_options options = CAGEKIT_WRITE_OPTIONS_INIT;
  cagekit_blob blob = NULL;
  cagekit_cage back = NULL;
  options.format = format;
  *bytes_fp = 0, *size = 0, *read_fp = 0;
  CHECK_OK_T(tid, cagekit_cage_write_memory(g_shared_cage, &options, &blob, NULL));
  if (!blob) return;
  *bytes_fp = blob_fp(blob);
  *size = cagekit_blob_size(blob);
  CHECK_OK_T(tid, cagekit_cage_read_memory(g_context, cagekit_blob_data(blob), cagekit_blob_size(blob),
                                           CAGEKIT_FORMAT_AUTO, &back));
  cagekit_blob_release(blob);
  if (back) *read_fp = cage_fingerprint(back);
  cagekit_cage_release(back);
}

static uint64_t subdivide_fp(int tid, cagekit_cage cage, uint32_t levels, cagekit_status expected) {
  cagekit_subdivide_options options = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  cagekit_cage refined = NULL;
  uint64_t fp = 0;
  options.levels = levels;
  options.limit_positions = 1;
  CHECK_ST(tid, cagekit_cage_subdivide(cage, &options, &refined), expected);
  if (refined) fp = cage_fingerprint(refined);
  cagekit_cage_release(refined);
  return fp;
}

static uint64_t limit_fp(int tid, cagekit_cage cage) {
  uint32_t n = 0;
  double *p, *nrm;
  uint64_t fp = FNV_SEED;
  CHECK_OK_T(tid, cagekit_cage_get_limit_points(cage, 0, &n, NULL, NULL));
  p = (double*)malloc(sizeof(double) * 3 * (n + 1));
  nrm = (double*)malloc(sizeof(double) * 3 * (n + 1));
  CHECK_OK_T(tid, cagekit_cage_get_limit_points(cage, n, &n, p, nrm));
  fp = fnv(fp, p, sizeof(double) * 3 * n);
  fp = fnv(fp, nrm, sizeof(double) * 3 * n);
  free(p);
  free(nrm);
  return fp;
}

static uint64_t basis_fp(int tid, cagekit_surface surface) {
  uint32_t n = 0, idx[256];
  double w[256], wu[256], wv[256];
  CHECK_OK_T(tid, cagekit_surface_evaluate_basis(surface, &g_locations[5], 256, &n, idx, w, wu, wv, NULL, NULL, NULL));
  if (n > 256) return 0;
  return fnv(fnv(fnv(fnv(FNV_SEED, idx, 4 * n), w, 8 * n), wu, 8 * n), wv, 8 * n);
}

static uint64_t mesh_info_fp(int tid, cagekit_mesh mesh) {
  cagekit_mesh_info info;
  memset(&info, 0, sizeof info);
  info.struct_size = sizeof info;
  CHECK_OK_T(tid, cagekit_mesh_get_info(mesh, &info));
  return info_fingerprint(&info);
}

static uint64_t cage_info_fp(int tid, cagekit_cage cage) {
  cagekit_mesh_info info;
  memset(&info, 0, sizeof info);
  info.struct_size = sizeof info;
  CHECK_OK_T(tid, cagekit_cage_get_info(cage, &info));
  return info_fingerprint(&info);
}

static void validate_broken(int tid, cagekit_mesh mesh, cagekit_validation_report* report) {
  memset(report, 0, sizeof *report);
  report->struct_size = sizeof *report;
  CHECK_ST(tid, cagekit_mesh_validate(mesh, report), CAGEKIT_ERROR_INVALID_MESH);
}

static uint64_t repair_fp(int tid, cagekit_mesh mesh, cagekit_repair_report* report) {
  cagekit_mesh repaired = NULL;
  uint64_t fp = 0;
  memset(report, 0, sizeof *report);
  report->struct_size = sizeof *report;
  CHECK_OK_T(tid, cagekit_mesh_repair(mesh, NULL, &repaired, report));
  if (repaired) {
    CHECK_OK_T(tid, cagekit_mesh_validate(repaired, NULL));
    fp = mesh_fingerprint(repaired);
  }
  cagekit_mesh_release(repaired);
  return fp;
}

static uint64_t fit_fp(int tid) {
  cagekit_fit_options options = CAGEKIT_FIT_OPTIONS_INIT;
  cagekit_cage fitted = NULL;
  uint64_t fp = 0;
  uint32_t pass_count = 0;
  options.max_passes = 2;
  options.threads = 1;
  CHECK_OK_T(tid, cagekit_cage_fit(g_shared_cage, g_shared_mesh, &options, &fitted, NULL, 0, &pass_count, NULL));
  if (fitted) fp = cage_fingerprint(fitted);
  cagekit_cage_release(fitted);
  return fp;
}

static uint64_t bind_info_fp(int tid, cagekit_binding binding) {
  cagekit_binding_info info;
  memset(&info, 0, sizeof info);
  info.struct_size = sizeof info;
  CHECK_OK_T(tid, cagekit_binding_get_info(binding, &info));
  return fnv(fnv(fnv(FNV_SEED, &info.vertex_count, sizeof info.vertex_count), &info.basis_entries,
                 sizeof info.basis_entries),
             &info.max_sideways_residual, sizeof info.max_sideways_residual);
}

/* A deformer of the shared binding: the cage's control points, every third moved, then positions
 * and normals fingerprinted (full recompute, then an incremental update of two points). */
static uint64_t deform_fp(int tid) {
  cagekit_cpu_deformer deformer = NULL;
  cagekit_mesh cage_mesh = NULL;
  uint32_t m = 0, n = 0, k, moved[2] = {0, 3}, written = 0;
  double* control;
  double *positions, *normals;
  uint64_t fp = FNV_SEED;
  cagekit_binding_info info;
  memset(&info, 0, sizeof info);
  info.struct_size = sizeof info;
  CHECK_OK_T(tid, cagekit_binding_get_info(g_shared_binding, &info));
  n = info.vertex_count;
  CHECK_OK_T(tid, cagekit_cage_get_mesh(g_shared_cage, &cage_mesh));
  CHECK_OK_T(tid, cagekit_mesh_get_positions(cage_mesh, CAGEKIT_SCALAR_FLOAT64, 0, &m, NULL));
  control = (double*)malloc(3 * (size_t)m * sizeof(double));
  positions = (double*)malloc(3 * (size_t)n * sizeof(double));
  normals = (double*)malloc(3 * (size_t)n * sizeof(double));
  if (!control || !positions || !normals) {
    record_failure(__FILE__, __LINE__, tid, "out of memory");
  } else {
    CHECK_OK_T(tid, cagekit_mesh_get_positions(cage_mesh, CAGEKIT_SCALAR_FLOAT64, m, &m, control));
    for (k = 0; k < m; k += 3) control[3 * k + 2] += 0.05;
    CHECK_OK_T(tid, cagekit_cpu_deformer_create(g_shared_binding, 1, &deformer));
    CHECK_OK_T(tid, cagekit_cpu_deformer_deform(deformer, control, m, CAGEKIT_NORMALS_APPROXIMATE, n, &written,
                                                positions, normals));
    control[0] -= 0.03;
    control[3 * 3 + 1] += 0.02;
    CHECK_OK_T(tid, cagekit_cpu_deformer_update(deformer, control, m, moved, 2, CAGEKIT_NORMALS_APPROXIMATE, n,
                                                &written, positions, normals, NULL));
    fp = fnv(fnv(fp, positions, 3 * (size_t)n * sizeof(double)), normals, 3 * (size_t)n * sizeof(double));
  }
  cagekit_cpu_deformer_release(deformer);
  cagekit_mesh_release(cage_mesh);
  free(control);
  free(positions);
  free(normals);
  return fp;
}

static void compute_reference(void) {
  const int tid = -1;
  cagekit_mesh broken = NULL;
  cagekit_hierarchy h = NULL;
  int k;

  g_ref.tri_mesh_info = mesh_info_fp(tid, g_shared_mesh);
  g_ref.tri_mesh_fp = mesh_fingerprint(g_shared_mesh);
  CHECK_OK_T(tid, cagekit_mesh_validate(g_shared_mesh, NULL));
  CHECK_OK_T(tid, create_mesh(g_context, &g_tri, g_broken_face_count, g_broken_indices, &broken));
  validate_broken(tid, broken, &g_ref.broken_report);
  CHECK_T(tid, g_ref.broken_report.valid == 0 && g_ref.broken_report.issue_counts[CAGEKIT_ISSUE_INDEX_OUT_OF_RANGE] == 1);
  g_ref.repaired_fp = repair_fp(tid, broken, &g_ref.repair_report);
  CHECK_T(tid, g_ref.repair_report.dropped_invalid_faces == 1 && g_ref.repair_report.dropped_duplicate_faces == 1);
  cagekit_mesh_release(broken);

  encode_and_read(tid, CAGEKIT_FORMAT_OBJ, &g_ref.obj_fp, &g_ref.obj_size, &g_ref.obj_read_fp);
  encode_and_read(tid, CAGEKIT_FORMAT_DRACO, &g_ref.drc_fp, &g_ref.drc_size, &g_ref.drc_read_fp);
  /* OBJ keeps positions to 9 digits and the tags: the read-back cage has the creases. */
  CHECK_T(tid, g_ref.obj_size > 1000 && g_ref.drc_size > 100);
  g_ref.subdiv_fp = subdivide_fp(tid, g_shared_cage, 2, CAGEKIT_SUCCESS);
  g_ref.limit_fp = limit_fp(tid, g_shared_cage);
  g_ref.cage_info_fp = cage_info_fp(tid, g_shared_cage);
  CHECK_OK_T(tid, cagekit_surface_evaluate(g_shared_surface, NULL, EVAL_COUNT, g_locations, g_ref.points));
  g_ref.basis_fp = basis_fp(tid, g_shared_surface);

  CHECK_OK_T(tid, cagekit_hierarchy_create(g_shared_mesh, NULL, &h));
  CHECK_OK_T(tid, cagekit_hierarchy_get_level_count(h, &g_ref.level_count));
  CHECK_T(tid, g_ref.level_count > 10 && g_ref.level_count < MAX_LEVELS);
  g_ref.level_info_fp = level_info_fp(tid, h, g_ref.level_count);
  g_ref.probe_levels[0] = 0;
  g_ref.probe_levels[1] = g_ref.level_count / 2;
  g_ref.probe_levels[2] = g_ref.level_count - 1;
  for (k = 0; k < 3; ++k) {
    CHECK_OK_T(tid, cagekit_hierarchy_set_level(h, g_ref.probe_levels[k]));
    g_ref.probe_fp[k] = current_level_fingerprint(h);
  }
  cagekit_hierarchy_release(h);
  /* the shared hierarchy sits at the middle probe level for the whole run */
  CHECK_OK_T(tid, cagekit_hierarchy_create(g_shared_mesh, NULL, &g_shared_hierarchy));
  CHECK_OK_T(tid, cagekit_hierarchy_set_level(g_shared_hierarchy, g_ref.probe_levels[1]));
  g_ref.shared_level_fp = current_level_fingerprint(g_shared_hierarchy);
  CHECK_T(tid, g_ref.shared_level_fp == g_ref.probe_fp[1]);
  g_ref.built_cage_fp = built_cage_fp(tid, g_shared_hierarchy);
  g_ref.polygon_mesh_fp = polygon_mesh_fp(tid, g_shared_hierarchy);

  g_ref.cancel_subdiv_fp = subdivide_fp(tid, g_cancel_cage, 2, CAGEKIT_SUCCESS);

  g_ref.fit_fp = fit_fp(tid);
  {
    cagekit_bind_options options = CAGEKIT_BIND_OPTIONS_INIT;
    options.threads = 1;
    CHECK_OK_T(tid, cagekit_multires_bind(g_shared_cage, g_shared_mesh, &options, &g_shared_binding));
  }
  g_ref.bind_info_fp = bind_info_fp(tid, g_shared_binding);
  g_ref.deform_fp = deform_fp(tid);
}

/* ------------------------------------------------------------------------------------------ */
/* Workers                                                                                    */
/* ------------------------------------------------------------------------------------------ */

typedef struct worker {
  pthread_t thread;
  int tid;
  int fails_on_purpose; /* 0: this thread never fails a call and must always see "" */
} worker;

static void expect_own_error(int tid, const char* when) {
  char expected[64];
  const char* message = cagekit_last_error_message(g_context);
  snprintf(expected, sizeof expected, "not %d", 100 + tid);
  if (strstr(message, expected) == NULL) {
    char b[512];
    snprintf(b, sizeof b, "%s: last error is \"%.300s\", expected this thread's (\"%s\")", when, message, expected);
    record_failure(__FILE__, __LINE__, tid, b);
  }
}

static void* worker_main(void* arg) {
  const worker* w = (const worker*)arg;
  const int tid = w->tid;
  int it, k;
  for (it = 0; it < g_iterations; ++it) {
    cagekit_mesh mesh = NULL, broken = NULL;
    cagekit_hierarchy own = NULL;
    cagekit_surface surface = NULL;
    cagekit_validation_report vr;
    cagekit_repair_report rr;
    cagekit_surface_point points[EVAL_COUNT];
    uint64_t fp;
    size_t size;
    uint64_t read_fp;
    uint32_t count = 0, level = 0;

    if (w->fails_on_purpose && it > 0) expect_own_error(tid, "start of iteration");

    /* retain/release churn on the shared handles (other threads hold and use them) */
    for (k = 0; k < CHURN; ++k) {
      cagekit_mesh_retain(g_shared_mesh);
      cagekit_cage_retain(g_shared_cage);
      cagekit_surface_retain(g_shared_surface);
      cagekit_hierarchy_retain(g_shared_hierarchy);
      cagekit_context_retain(g_context);
      cagekit_context_release(g_context);
      cagekit_hierarchy_release(g_shared_hierarchy);
      cagekit_surface_release(g_shared_surface);
      cagekit_cage_release(g_shared_cage);
      cagekit_mesh_release(g_shared_mesh);
    }

    /* own meshes: create / validate / info / repair */
    CHECK_OK_T(tid, create_mesh(g_context, &g_tri, g_tri.nf, g_tri.indices, &mesh));
    CHECK_OK_T(tid, cagekit_mesh_validate(mesh, NULL));
    CHECK_T(tid, mesh_info_fp(tid, mesh) == g_ref.tri_mesh_info);
    CHECK_T(tid, mesh_fingerprint(mesh) == g_ref.tri_mesh_fp);
    if (w->fails_on_purpose) {
      CHECK_OK_T(tid, create_mesh(g_context, &g_tri, g_broken_face_count, g_broken_indices, &broken));
      validate_broken(tid, broken, &vr);
      CHECK_T(tid, vr.valid == g_ref.broken_report.valid && vr.issue_flags == g_ref.broken_report.issue_flags &&
                       memcmp(vr.issue_counts, g_ref.broken_report.issue_counts, sizeof vr.issue_counts) == 0);
      CHECK_T(tid, strstr(cagekit_last_error_message(g_context), "vertex") != NULL);
      fp = repair_fp(tid, broken, &rr);
      CHECK_T(tid, fp == g_ref.repaired_fp && memcmp(&rr, &g_ref.repair_report, sizeof rr) == 0);
      cagekit_mesh_release(broken);
    }

    /* shared mesh: reads */
    CHECK_OK_T(tid, cagekit_mesh_validate(g_shared_mesh, NULL));
    CHECK_T(tid, mesh_info_fp(tid, g_shared_mesh) == g_ref.tri_mesh_info);
    CHECK_T(tid, mesh_fingerprint(g_shared_mesh) == g_ref.tri_mesh_fp);

    /* shared cage: encode (OBJ, Draco) and read back into own cages */
    encode_and_read(tid, CAGEKIT_FORMAT_OBJ, &fp, &size, &read_fp);
    CHECK_T(tid, fp == g_ref.obj_fp && size == g_ref.obj_size && read_fp == g_ref.obj_read_fp);
    encode_and_read(tid, CAGEKIT_FORMAT_DRACO, &fp, &size, &read_fp);
    CHECK_T(tid, fp == g_ref.drc_fp && size == g_ref.drc_size && read_fp == g_ref.drc_read_fp);

    /* shared cage: subdivide, limit points, info, a new surface */
    CHECK_T(tid, subdivide_fp(tid, g_shared_cage, 2, CAGEKIT_SUCCESS) == g_ref.subdiv_fp);
    CHECK_T(tid, limit_fp(tid, g_shared_cage) == g_ref.limit_fp);
    CHECK_T(tid, cage_info_fp(tid, g_shared_cage) == g_ref.cage_info_fp);
    if (it == 0) {
      CHECK_OK_T(tid, cagekit_surface_create(g_shared_cage, NULL, &surface));
      if (surface) {
        memset(points, 0, sizeof points);
        CHECK_OK_T(tid, cagekit_surface_evaluate(surface, NULL, EVAL_COUNT, g_locations, points));
        CHECK_T(tid, memcmp(points, g_ref.points, sizeof points) == 0);
      }
      cagekit_surface_release(surface);
    }

    /* shared surface: evaluate, basis */
    memset(points, 0, sizeof points);
    CHECK_OK_T(tid, cagekit_surface_evaluate(g_shared_surface, NULL, EVAL_COUNT, g_locations, points));
    CHECK_T(tid, memcmp(points, g_ref.points, sizeof points) == 0);
    CHECK_T(tid, basis_fp(tid, g_shared_surface) == g_ref.basis_fp);

    /* shared hierarchy: reads only, at its fixed level */
    CHECK_OK_T(tid, cagekit_hierarchy_get_level_count(g_shared_hierarchy, &count));
    CHECK_T(tid, count == g_ref.level_count);
    CHECK_T(tid, level_info_fp(tid, g_shared_hierarchy, count) == g_ref.level_info_fp);
    CHECK_OK_T(tid, cagekit_hierarchy_get_current_level(g_shared_hierarchy, &level));
    CHECK_T(tid, level == g_ref.probe_levels[1]);
    CHECK_T(tid, current_level_fingerprint(g_shared_hierarchy) == g_ref.shared_level_fp);
    if (it % 2 == 0) {
      CHECK_T(tid, built_cage_fp(tid, g_shared_hierarchy) == g_ref.built_cage_fp);
      CHECK_T(tid, polygon_mesh_fp(tid, g_shared_hierarchy) == g_ref.polygon_mesh_fp);
    }

    /* fitting and multiresolution: fit and bind read the shared cage and mesh; each thread's own
     * deformer reads the shared (immutable) binding; results equal the single-threaded ones */
    if (it % 2 == 1) {
      cagekit_binding own_binding = NULL;
      cagekit_bind_options bind = CAGEKIT_BIND_OPTIONS_INIT;
      CHECK_T(tid, fit_fp(tid) == g_ref.fit_fp);
      bind.threads = 1;
      CHECK_OK_T(tid, cagekit_multires_bind(g_shared_cage, g_shared_mesh, &bind, &own_binding));
      if (own_binding) CHECK_T(tid, bind_info_fp(tid, own_binding) == g_ref.bind_info_fp);
      cagekit_binding_release(own_binding);
    }
    CHECK_T(tid, deform_fp(tid) == g_ref.deform_fp);
    cagekit_binding_retain(g_shared_binding);
    cagekit_binding_release(g_shared_binding);

    /* own hierarchy (from the thread's own mesh): navigate up and down */
    if (it % 2 == 0) {
      CHECK_OK_T(tid, cagekit_hierarchy_create(mesh, NULL, &own));
      if (own) {
        CHECK_OK_T(tid, cagekit_hierarchy_get_level_count(own, &count));
        CHECK_T(tid, count == g_ref.level_count);
        for (k = 0; k < 4; ++k) {
          const int probe = (k + tid) % 3;
          CHECK_OK_T(tid, cagekit_hierarchy_set_level(own, g_ref.probe_levels[probe]));
          CHECK_T(tid, current_level_fingerprint(own) == g_ref.probe_fp[probe]);
        }
      }
      cagekit_hierarchy_release(own);
    }
    cagekit_mesh_release(mesh);

    /* this thread's own failure, with a message no other thread produces */
    if (w->fails_on_purpose) {
      cagekit_subdivide_options options = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
      cagekit_cage refined = (cagekit_cage)&options;
      options.levels = (uint32_t)(100 + tid);
      CHECK_ST(tid, cagekit_cage_subdivide(g_shared_cage, &options, &refined), CAGEKIT_ERROR_INVALID_ARGUMENT);
      CHECK_T(tid, refined == NULL);
      expect_own_error(tid, "right after the failure");
    } else {
      CHECK_T(tid, strcmp(cagekit_last_error_message(g_context), "") == 0);
    }
  }
  if (w->fails_on_purpose) expect_own_error(tid, "end of the thread");
  else CHECK_T(tid, strcmp(cagekit_last_error_message(g_context), "") == 0);
  return NULL;
}

/* --- cancellation from another thread --- */

static pthread_mutex_t g_cancel_mutex = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t g_cancel_cond = PTHREAD_COND_INITIALIZER;
static int g_cancel_successes = 0;

static void* cancel_worker_main(void* arg) {
  const int tid = 100;
  int rounds, cancelled = 0;
  (void)arg;
  for (rounds = 0; rounds < 100000 && !cancelled; ++rounds) {
    cagekit_subdivide_options options = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
    cagekit_cage refined = NULL;
    cagekit_status s;
    options.levels = 2;
    options.limit_positions = 1;
    s = cagekit_cage_subdivide(g_cancel_cage, &options, &refined);
    if (s == CAGEKIT_SUCCESS) {
      CHECK_T(tid, refined != NULL && cage_fingerprint(refined) == g_ref.cancel_subdiv_fp);
      pthread_mutex_lock(&g_cancel_mutex);
      ++g_cancel_successes;
      pthread_cond_broadcast(&g_cancel_cond);
      pthread_mutex_unlock(&g_cancel_mutex);
    } else {
      CHECK_ST(tid, s, CAGEKIT_ERROR_CANCELLED);
      CHECK_T(tid, refined == NULL);
      CHECK_T(tid, strstr(cagekit_last_error_message(g_cancel_ctx), "cancel") != NULL);
      cancelled = 1;
    }
    cagekit_cage_release(refined);
  }
  CHECK_T(tid, cancelled); /* the request stays until reset: every later operation is cancelled */
  return NULL;
}

static void* canceller_main(void* arg) {
  (void)arg;
  pthread_mutex_lock(&g_cancel_mutex);
  while (g_cancel_successes < 2) pthread_cond_wait(&g_cancel_cond, &g_cancel_mutex);
  pthread_mutex_unlock(&g_cancel_mutex);
  cagekit_context_cancel(g_cancel_ctx);
  return NULL;
}

int main(int argc, char** argv) {
  int threads = 6, t, k;
  worker workers[64];
  pthread_t cancel_worker, canceller;
  cagekit_mesh quad_mesh = NULL, big_mesh = NULL;
  uint32_t creases[2 * 64];

  if (argc > 1) g_iterations = atoi(argv[1]);
  if (argc > 2) threads = atoi(argv[2]);
  if (g_iterations < 1) g_iterations = 1;
  if (threads < 2) threads = 2;
  if (threads > 64) threads = 64;

  make_torus(24, 12, 1, &g_tri);
  make_torus(16, 8, 0, &g_quad);
  make_torus(48, 24, 0, &g_big);
  /* g_tri + a duplicate of face 0 + a face with an out-of-range index */
  g_broken_face_count = g_tri.nf + 2;
  g_broken_indices = (uint32_t*)malloc(sizeof(uint32_t) * 3 * g_broken_face_count);
  memcpy(g_broken_indices, g_tri.indices, sizeof(uint32_t) * 3 * g_tri.nf);
  memcpy(g_broken_indices + 3 * g_tri.nf, g_tri.indices, sizeof(uint32_t) * 3);
  g_broken_indices[3 * g_tri.nf + 3] = 0;
  g_broken_indices[3 * g_tri.nf + 4] = 1;
  g_broken_indices[3 * g_tri.nf + 5] = g_tri.nv + 7;
  for (k = 0; k < EVAL_COUNT; ++k) {
    g_locations[k].face = (uint32_t)(k * 37) % g_quad.nf;
    g_locations[k].u = (k % 7) / 6.0;
    g_locations[k].v = ((k * 3) % 11) / 10.0;
  }

  if (cagekit_context_create(NULL, &g_context) != CAGEKIT_SUCCESS ||
      cagekit_context_create(NULL, &g_cancel_ctx) != CAGEKIT_SUCCESS) {
    fprintf(stderr, "cannot create contexts\n");
    return 1;
  }
  CHECK_OK_T(-1, create_mesh(g_context, &g_tri, g_tri.nf, g_tri.indices, &g_shared_mesh));
  CHECK_OK_T(-1, create_mesh(g_context, &g_quad, g_quad.nf, g_quad.indices, &quad_mesh));
  CHECK_OK_T(-1, cagekit_cage_create(quad_mesh, &g_shared_cage));
  /* a crease ring around the tube (u = 0) and a corner */
  for (k = 0; k < 8; ++k) {
    creases[2 * k] = (uint32_t)k;
    creases[2 * k + 1] = (uint32_t)((k + 1) % 8);
  }
  CHECK_OK_T(-1, cagekit_cage_set_creases(g_shared_cage, 8, creases, NULL));
  CHECK_OK_T(-1, cagekit_surface_create(g_shared_cage, NULL, &g_shared_surface));
  CHECK_OK_T(-1, create_mesh(g_cancel_ctx, &g_big, g_big.nf, g_big.indices, &big_mesh));
  CHECK_OK_T(-1, cagekit_cage_create(big_mesh, &g_cancel_cage));
  cagekit_mesh_release(quad_mesh);
  cagekit_mesh_release(big_mesh);
  if (g_failures) return 1;

  compute_reference();
  if (g_failures) {
    fprintf(stderr, "the single-threaded reference failed\n");
    return 1;
  }
  /* the reference run's failures (broken mesh) must not be seen by the workers */
  printf("reference: %u hierarchy levels, OBJ %zu bytes, Draco %zu bytes; %d threads x %d iterations\n",
         g_ref.level_count, g_ref.obj_size, g_ref.drc_size, threads, g_iterations);

  for (t = 0; t < threads; ++t) {
    workers[t].tid = t;
    workers[t].fails_on_purpose = t != 1;
    if (pthread_create(&workers[t].thread, NULL, worker_main, &workers[t]) != 0) {
      fprintf(stderr, "pthread_create failed\n");
      return 1;
    }
  }
  if (pthread_create(&cancel_worker, NULL, cancel_worker_main, NULL) != 0 ||
      pthread_create(&canceller, NULL, canceller_main, NULL) != 0) {
    fprintf(stderr, "pthread_create failed\n");
    return 1;
  }
  for (t = 0; t < threads; ++t) pthread_join(workers[t].thread, NULL);
  pthread_join(cancel_worker, NULL);
  pthread_join(canceller, NULL);

  /* the main context was never cancelled; the cancel context works again after a reset */
  CHECK_T(-1, subdivide_fp(-1, g_shared_cage, 2, CAGEKIT_SUCCESS) == g_ref.subdiv_fp);
  subdivide_fp(-1, g_cancel_cage, 1, CAGEKIT_ERROR_CANCELLED);
  cagekit_context_reset_cancel(g_cancel_ctx);
  CHECK_T(-1, subdivide_fp(-1, g_cancel_cage, 2, CAGEKIT_SUCCESS) == g_ref.cancel_subdiv_fp);

  /* every shared handle is still alive with one reference; release in an order that leaves
   * the contexts to be freed by their last objects */
  cagekit_context_release(g_context);
  cagekit_context_release(g_cancel_ctx);
  CHECK_T(-1, mesh_fingerprint(g_shared_mesh) == g_ref.tri_mesh_fp);
  cagekit_hierarchy_release(g_shared_hierarchy);
  cagekit_binding_release(g_shared_binding);
  cagekit_surface_release(g_shared_surface);
  cagekit_cage_release(g_shared_cage);
  cagekit_cage_release(g_cancel_cage);
  cagekit_mesh_release(g_shared_mesh);
  free(g_tri.positions), free(g_tri.indices), free(g_quad.positions), free(g_quad.indices);
  free(g_big.positions), free(g_big.indices), free(g_broken_indices);

  printf("cancel scenario: %d successful subdivisions before the cancellation\n", g_cancel_successes);
  printf("%s: %d failed checks\n", g_failures ? "FAIL" : "PASS", g_failures);
  return g_failures ? 1 : 0;
}
