/* SPDX-License-Identifier: GPL-3.0-or-later
 * Hostile sizes through the public C API: files whose headers claim huge element counts and API
 * calls with huge counts must fail with the documented status, without crashing and without
 * allocating much.
 *
 * Each case runs in a forked child. Outside sanitizer builds the child's address space is
 * limited (RLIMIT_AS = its current size + 100 MiB, malloc arenas limited to 1), so an attempt to
 * allocate what the header claims fails and shows up as a wrong status (OUT_OF_MEMORY) or a
 * crash. In every build the child's peak-RSS growth during the call (ru_maxrss delta) must stay
 * below 100 MiB. The status is asserted; the time of each call is only printed.
 *
 * Usage: hostile_sizes [-v] */
#include <cagekit/cagekit.h>

#include <malloc.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "../sanitizer/sanitized_build.h"

#if CAGEKIT_ASAN_BUILD
/* ASan keeps freed blocks in a quarantine (256 MiB by default) whose pages stay resident, so
 * the thousands of reads of the Draco sweeps would raise the peak RSS by ~190 MiB without any
 * large allocation. Without the quarantine the RSS figure measures the reads again (options
 * given in ASAN_OPTIONS still take precedence). */
const char* __asan_default_options(void);
__attribute__((visibility("default"))) const char* __asan_default_options(void) { return "quarantine_size_mb=0"; }
#endif

#define RSS_BOUND_KIB (100L * 1024L)
#ifndef AS_HEADROOM_BYTES
#define AS_HEADROOM_BYTES (100ull << 20)
#endif

static int g_failures = 0;
static int g_verbose = 0;
static cagekit_context g_context;

static double now_seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static long max_rss_kib(void) {
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

static unsigned long long address_space_bytes(void) {
  unsigned long long pages = 0;
  FILE* f = fopen("/proc/self/statm", "r");
  if (f) {
    if (fscanf(f, "%llu", &pages) != 1) pages = 0;
    fclose(f);
  }
  return pages * (unsigned long long)sysconf(_SC_PAGESIZE);
}

/* A case: runs some calls, returns 0 when every status was the expected one (and prints why
 * not otherwise). */
typedef int (*case_fn)(void);

static void run_case(const char* name, case_fn fn) {
  pid_t pid;
  int status = 0;
  fflush(stdout);
  fflush(stderr);
  pid = fork();
  if (pid < 0) {
    perror("fork");
    ++g_failures;
    return;
  }
  if (pid == 0) {
    long rss_before, rss_after;
    double t0, seconds;
    int result;
    if (!CAGEKIT_SANITIZED_BUILD) {
      struct rlimit limit;
      mallopt(M_ARENA_MAX, 1);
      limit.rlim_cur = limit.rlim_max = (rlim_t)(address_space_bytes() + AS_HEADROOM_BYTES);
      if (setrlimit(RLIMIT_AS, &limit) != 0) perror("setrlimit");
    }
    rss_before = max_rss_kib();
    t0 = now_seconds();
    result = fn();
    seconds = now_seconds() - t0;
    rss_after = max_rss_kib();
    printf("%-58s %8.2f ms  peak RSS +%ld KiB%s\n", name, 1e3 * seconds, rss_after - rss_before,
           seconds > 0.1 ? "  (case total > 100 ms)" : "");
    if (rss_after - rss_before > RSS_BOUND_KIB) {
      fprintf(stderr, "%s: peak RSS grew by %ld KiB, more than %ld KiB\n", name, rss_after - rss_before,
              RSS_BOUND_KIB);
      result = 1;
    }
    fflush(stdout);
    fflush(stderr);
    _exit(result == 0 ? 0 : 1);
  }
  if (waitpid(pid, &status, 0) != pid) {
    perror("waitpid");
    ++g_failures;
    return;
  }
  if (WIFSIGNALED(status)) {
    fprintf(stderr, "FAIL %s: killed by signal %d\n", name, WTERMSIG(status));
    ++g_failures;
  } else if (WEXITSTATUS(status) != 0) {
    fprintf(stderr, "FAIL %s\n", name);
    ++g_failures;
  }
}

/* Checks a status; on mismatch prints the status and the message. Returns 0 when as expected. */
static int expect(const char* what, cagekit_status got, cagekit_status expected) {
  if (got == expected) {
    if (g_verbose) printf("  %s: %s: %s\n", what, cagekit_status_string(got), cagekit_last_error_message(g_context));
    return 0;
  }
  fprintf(stderr, "  %s: got %d (%s: %s), expected %d (%s)\n", what, (int)got, cagekit_status_string(got),
          cagekit_last_error_message(g_context), (int)expected, cagekit_status_string(expected));
  return 1;
}

static int read_text(const char* what, const char* text, cagekit_file_format format, cagekit_status expected) {
  cagekit_mesh mesh = (cagekit_mesh)&g_context;
  cagekit_cage cage = (cagekit_cage)&g_context;
  int bad = expect(what, cagekit_mesh_read_memory(g_context, text, strlen(text), format, &mesh), expected);
  bad |= expect(what, cagekit_cage_read_memory(g_context, text, strlen(text), format, &cage), expected);
  if (expected != CAGEKIT_SUCCESS && (mesh != NULL || cage != NULL)) {
    fprintf(stderr, "  %s: output handle not NULL after a failure\n", what);
    bad = 1;
  }
  return bad;
}

/* --- file headers --- */

static int obj_huge_face_index(void) {
  return read_text("OBJ face index 4e9", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4000000000\n", CAGEKIT_FORMAT_OBJ,
                   CAGEKIT_ERROR_PARSE) |
         read_text("OBJ face index 2^28", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 268435456\n", CAGEKIT_FORMAT_OBJ,
                   CAGEKIT_ERROR_PARSE) |
         read_text("OBJ relative index -4e9", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4000000000\n",
                   CAGEKIT_FORMAT_OBJ, CAGEKIT_ERROR_PARSE) |
         read_text("OBJ index 2^64", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 18446744073709551616\n", CAGEKIT_FORMAT_OBJ,
                   CAGEKIT_ERROR_PARSE);
}

static int obj_huge_tag_counts(void) {
  /* `t crease 4000000000/1 ...`: counts far beyond what the line holds */
  return read_text("OBJ tag counts 4e9",
                   "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\nt crease 4000000000/1/0 0 1 10\n",
                   CAGEKIT_FORMAT_OBJ, CAGEKIT_ERROR_PARSE);
}

static int obj_face_beyond_max_face_size(void) {
  /* one face with 70000 corners (> the 2^16 corners a reader accepts) */
  const int corners = 70000;
  size_t size = 64 + (size_t)corners * 2, used;
  char* text = (char*)malloc(size);
  int i, bad;
  used = (size_t)sprintf(text, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
  for (i = 0; i < corners; ++i) used += (size_t)sprintf(text + used, " %d", 1 + i % 3);
  sprintf(text + used, "\n");
  bad = read_text("OBJ face of 70000 corners", text, CAGEKIT_FORMAT_OBJ, CAGEKIT_ERROR_LIMIT_EXCEEDED);
  free(text);
  return bad;
}

static int ply_huge_vertex_count(void) {
  static const char* ascii =
      "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  static const char* binary_head =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  static const char* faces =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4000000000\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  static const char* list =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n";
  char binary[512];
  size_t head = strlen(binary_head);
  int bad = read_text("PLY ascii element vertex 4e9", ascii, CAGEKIT_FORMAT_PLY, CAGEKIT_ERROR_PARSE);
  cagekit_mesh mesh = NULL;
  memcpy(binary, binary_head, head);
  memset(binary + head, 0, 64); /* a few zero bytes of "data" */
  bad |= expect("PLY binary element vertex 4e9",
                cagekit_mesh_read_memory(g_context, binary, head + 64, CAGEKIT_FORMAT_PLY, &mesh),
                CAGEKIT_ERROR_PARSE);
  bad |= read_text("PLY ascii element face 4e9", faces, CAGEKIT_FORMAT_PLY, CAGEKIT_ERROR_PARSE);
  bad |= read_text("PLY face list of 4e9 indices", list, CAGEKIT_FORMAT_PLY, CAGEKIT_ERROR_LIMIT_EXCEEDED);
  return bad;
}

static int off_huge_counts(void) {
  return read_text("OFF 2000000000 1 0", "OFF\n2000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", CAGEKIT_FORMAT_OFF,
                   CAGEKIT_ERROR_PARSE) |
         read_text("OFF 200000000 1 0 (below the vertex limit)", "OFF\n200000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                   CAGEKIT_FORMAT_OFF, CAGEKIT_ERROR_PARSE) |
         read_text("OFF 3 2000000000 0", "OFF\n3 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", CAGEKIT_FORMAT_OFF,
                   CAGEKIT_ERROR_PARSE) |
         read_text("OFF face of 4e9 corners", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n", CAGEKIT_FORMAT_OFF,
                   CAGEKIT_ERROR_LIMIT_EXCEEDED);
}

/* A small cage (a 4 x 4 quad grid with two creases) encoded as Draco. */
static cagekit_blob draco_blob(int speed) {
  double positions[25 * 3];
  uint32_t quads[16 * 4], creases[4] = {0, 1, 1, 2};
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  cagekit_mesh mesh = NULL;
  cagekit_cage cage = NULL;
  cagekit_blob blob = NULL;
  cagekit_write_options options = CAGEKIT_WRITE_OPTIONS_INIT;
  int i, j;
  for (i = 0; i < 5; ++i)
    for (j = 0; j < 5; ++j) {
      positions[3 * (5 * i + j)] = j;
      positions[3 * (5 * i + j) + 1] = i;
      positions[3 * (5 * i + j) + 2] = 0.1 * ((i * j) % 3);
    }
  for (i = 0; i < 4; ++i)
    for (j = 0; j < 4; ++j) {
      uint32_t* q = quads + 4 * (4 * i + j);
      q[0] = (uint32_t)(5 * i + j), q[1] = (uint32_t)(5 * i + j + 1), q[2] = (uint32_t)(5 * i + j + 6),
      q[3] = (uint32_t)(5 * i + j + 5);
    }
  desc.vertex_count = 25;
  desc.positions = positions;
  desc.face_count = 16;
  desc.uniform_face_size = 4;
  desc.face_indices = quads;
  options.format = CAGEKIT_FORMAT_DRACO;
  options.draco_speed = speed;
  if (cagekit_mesh_create(g_context, &desc, &mesh) == CAGEKIT_SUCCESS &&
      cagekit_cage_create(mesh, &cage) == CAGEKIT_SUCCESS &&
      cagekit_cage_set_creases(cage, 2, creases, NULL) == CAGEKIT_SUCCESS)
    cagekit_cage_write_memory(cage, &options, &blob, NULL);
  cagekit_cage_release(cage);
  cagekit_mesh_release(mesh);
  return blob;
}

/* Overwrites each of the first bytes (the header, the counts and the connectivity start) with
 * values that make varints and counts huge; every read must succeed or fail cleanly. */
static int draco_sweep(int speed) {
  static const unsigned char values[] = {0xff, 0x7f, 0x80, 0xfe, 0x00};
  cagekit_blob blob = draco_blob(speed);
  unsigned char* bytes;
  size_t size, i, v, reads = 0, failures = 0;
  int bad = 0;
  double slowest = 0;
  cagekit_cage check = NULL;
  if (!blob) {
    fprintf(stderr, "  cannot encode the Draco test cage\n");
    return 1;
  }
  size = cagekit_blob_size(blob);
  bytes = (unsigned char*)malloc(size);
  memcpy(bytes, cagekit_blob_data(blob), size);
  bad |= expect("Draco intact", cagekit_cage_read_memory(g_context, bytes, size, CAGEKIT_FORMAT_DRACO, &check),
                CAGEKIT_SUCCESS);
  cagekit_cage_release(check);
  for (i = 0; i < size && i < 160; ++i)
    for (v = 0; v < sizeof values; ++v) {
      const unsigned char saved = bytes[i];
      cagekit_cage cage = NULL;
      cagekit_status s;
      double t0;
      if (saved == values[v]) continue;
      bytes[i] = values[v];
      t0 = now_seconds();
      s = cagekit_cage_read_memory(g_context, bytes, size, CAGEKIT_FORMAT_DRACO, &cage);
      t0 = now_seconds() - t0;
      if (t0 > slowest) slowest = t0;
      ++reads;
      if (s != CAGEKIT_SUCCESS) ++failures;
      /* INVALID_MESH: tags that do not fit the decoded mesh (a cage must be valid, as for
       * cagekit_cage_create); a mesh read ignores the tags, so it never sees that status. */
      if (s != CAGEKIT_SUCCESS && s != CAGEKIT_ERROR_PARSE && s != CAGEKIT_ERROR_LIMIT_EXCEEDED &&
          s != CAGEKIT_ERROR_UNSUPPORTED_FORMAT && s != CAGEKIT_ERROR_INVALID_MESH) {
        fprintf(stderr, "  Draco speed %d, byte %zu = 0x%02x: %d (%s: %s)\n", speed, i, values[v], (int)s,
                cagekit_status_string(s), cagekit_last_error_message(g_context));
        bad = 1;
      }
      if ((s == CAGEKIT_SUCCESS) != (cage != NULL)) bad = 1;
      cagekit_cage_release(cage);
      {
        cagekit_mesh mesh = NULL;
        s = cagekit_mesh_read_memory(g_context, bytes, size, CAGEKIT_FORMAT_DRACO, &mesh);
        ++reads;
        if (s != CAGEKIT_SUCCESS && s != CAGEKIT_ERROR_PARSE && s != CAGEKIT_ERROR_LIMIT_EXCEEDED &&
            s != CAGEKIT_ERROR_UNSUPPORTED_FORMAT) {
          fprintf(stderr, "  Draco speed %d, byte %zu = 0x%02x, as a mesh: %d (%s: %s)\n", speed, i, values[v],
                  (int)s, cagekit_status_string(s), cagekit_last_error_message(g_context));
          bad = 1;
        }
        if ((s == CAGEKIT_SUCCESS) != (mesh != NULL)) bad = 1;
        cagekit_mesh_release(mesh);
      }
      bytes[i] = saved;
    }
  printf("  Draco speed %d: %zu bytes, %zu corrupted reads, %zu cage reads rejected, slowest cage read %.2f ms\n", speed, size, reads,
         failures, 1e3 * slowest);
  free(bytes);
  cagekit_blob_release(blob);
  return bad;
}

static int draco_corrupt_counts_edgebreaker(void) { return draco_sweep(5); }
static int draco_corrupt_counts_sequential(void) { return draco_sweep(10); }

/* --- API calls --- */

static int mesh_create_huge_counts(void) {
  double tiny[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  uint32_t tri[3] = {0, 1, 2}, huge_size = UINT32_MAX;
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  cagekit_mesh mesh = (cagekit_mesh)&desc;
  int bad = 0;
  desc.positions = tiny;
  desc.face_indices = tri;

  desc.vertex_count = UINT32_MAX;
  desc.face_count = 1;
  bad |= expect("mesh_create vertex_count UINT32_MAX", cagekit_mesh_create(g_context, &desc, &mesh),
                CAGEKIT_ERROR_LIMIT_EXCEEDED);
  desc.vertex_count = 1u << 31;
  bad |= expect("mesh_create vertex_count 2^31", cagekit_mesh_create(g_context, &desc, &mesh),
                CAGEKIT_ERROR_LIMIT_EXCEEDED);
  desc.vertex_count = 3;
  desc.face_count = UINT32_MAX - 1;
  bad |= expect("mesh_create face_count UINT32_MAX-1", cagekit_mesh_create(g_context, &desc, &mesh),
                CAGEKIT_ERROR_LIMIT_EXCEEDED);
  desc.face_count = 1u << 30; /* 3 * 2^30 indices */
  bad |= expect("mesh_create 3 * 2^30 indices", cagekit_mesh_create(g_context, &desc, &mesh),
                CAGEKIT_ERROR_LIMIT_EXCEEDED);
  desc.face_count = 1;
  desc.uniform_face_size = UINT32_MAX;
  bad |= expect("mesh_create uniform_face_size UINT32_MAX", cagekit_mesh_create(g_context, &desc, &mesh),
                CAGEKIT_ERROR_LIMIT_EXCEEDED);
  desc.uniform_face_size = 3;
  desc.face_sizes = &huge_size;
  bad |= expect("mesh_create face_sizes[0] UINT32_MAX", cagekit_mesh_create(g_context, &desc, &mesh),
                CAGEKIT_ERROR_LIMIT_EXCEEDED);
  desc.face_sizes = NULL;
  desc.vertex_count = 1u << 30;
  desc.face_count = 0;
  desc.position_stride = 24;
  desc.positions = NULL;
  bad |= expect("mesh_create 2^30 vertices, positions NULL", cagekit_mesh_create(g_context, &desc, &mesh),
                CAGEKIT_ERROR_INVALID_ARGUMENT);
  if (mesh != NULL) {
    fprintf(stderr, "  mesh_create: output handle not NULL after a failure\n");
    bad = 1;
  }
  return bad;
}

/* A w x h quad grid cage. */
static cagekit_cage grid_cage(uint32_t w, uint32_t h) {
  double* positions = (double*)malloc(sizeof(double) * 3 * (w + 1) * (h + 1));
  uint32_t* quads = (uint32_t*)malloc(sizeof(uint32_t) * 4 * w * h);
  uint32_t i, j;
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  cagekit_mesh mesh = NULL;
  cagekit_cage cage = NULL;
  for (i = 0; i <= h; ++i)
    for (j = 0; j <= w; ++j) {
      double* p = positions + 3 * (i * (w + 1) + j);
      p[0] = j, p[1] = i, p[2] = 0.01 * ((i + j) % 5);
    }
  for (i = 0; i < h; ++i)
    for (j = 0; j < w; ++j) {
      uint32_t* q = quads + 4 * (i * w + j);
      q[0] = i * (w + 1) + j, q[1] = q[0] + 1, q[2] = q[1] + w + 1, q[3] = q[0] + w + 1;
    }
  desc.vertex_count = (w + 1) * (h + 1);
  desc.positions = positions;
  desc.face_count = w * h;
  desc.uniform_face_size = 4;
  desc.face_indices = quads;
  if (cagekit_mesh_create(g_context, &desc, &mesh) == CAGEKIT_SUCCESS) cagekit_cage_create(mesh, &cage);
  cagekit_mesh_release(mesh);
  free(positions);
  free(quads);
  return cage;
}

/* One subdivide call, timed on its own (the case's total includes building the cages). */
static int timed_subdivide(const char* what, cagekit_cage cage, uint32_t levels, cagekit_status expected) {
  cagekit_subdivide_options options = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  cagekit_cage out = (cagekit_cage)&options;
  cagekit_status s;
  double t0 = now_seconds();
  int bad;
  options.levels = levels;
  s = cagekit_cage_subdivide(cage, &options, &out);
  t0 = now_seconds() - t0;
  printf("  %-40s %8.2f ms\n", what, 1e3 * t0);
  bad = expect(what, s, expected);
  if (out != NULL) bad = 1;
  return bad;
}

static int subdivide_huge_levels(void) {
  cagekit_cage small = grid_cage(2, 2), big = grid_cage(200, 200);
  int bad = 0;
  bad |= timed_subdivide("subdivide levels 30", small, 30, CAGEKIT_ERROR_INVALID_ARGUMENT);
  bad |= timed_subdivide("subdivide levels UINT32_MAX", small, UINT32_MAX, CAGEKIT_ERROR_INVALID_ARGUMENT);
  /* 40000 quads * 4^8 = 2.6e9 faces, 1e10 face-vertices: refused before allocating */
  bad |= timed_subdivide("subdivide 40000 quads 8 levels", big, CAGEKIT_MAX_SUBDIVISION_LEVELS,
                         CAGEKIT_ERROR_LIMIT_EXCEEDED);
  /* 6.5e8 faces, 2.6e9 face-vertices */
  bad |= timed_subdivide("subdivide 40000 quads 7 levels", big, 7, CAGEKIT_ERROR_LIMIT_EXCEEDED);
  cagekit_cage_release(small);
  cagekit_cage_release(big);
  return bad;
}

/* Within the 2^31-index limit but far beyond memory: 40000 quads x 6 levels = 6.5e8 face
 * corners (tens of GiB). With a context memory budget of 64 MiB the call must refuse before
 * allocating (OUT_OF_MEMORY naming the budget). */
static int subdivide_beyond_budget(void) {
  cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
  cagekit_context saved = g_context, budget = NULL;
  cagekit_cage big;
  int bad;
  desc.memory_budget_bytes = 64ull << 20;
  if (cagekit_context_create(&desc, &budget) != CAGEKIT_SUCCESS) return 1;
  g_context = budget; /* grid_cage and expect() use g_context */
  big = grid_cage(200, 200);
  bad = timed_subdivide("subdivide 40000 quads 6 levels, budget 64 MiB", big, 6, CAGEKIT_ERROR_OUT_OF_MEMORY);
  if (strstr(cagekit_last_error_message(budget), "budget") == NULL) {
    fprintf(stderr, "  message does not name the budget: %s\n", cagekit_last_error_message(budget));
    bad = 1;
  }
  cagekit_cage_release(big);
  cagekit_context_release(budget);
  g_context = saved;
  return bad;
}

static int surface_huge_counts(void) {
  cagekit_cage cage = grid_cage(3, 3);
  cagekit_surface surface = NULL;
  cagekit_surface_options options = CAGEKIT_SURFACE_OPTIONS_INIT;
  cagekit_surface_location bad_location = {UINT32_MAX, 0.5, 0.5}, good_location = {0, 0.5, 0.5};
  cagekit_surface_point point;
  uint32_t n = 0;
  int bad = 0;
  options.isolation_level = 30;
  bad |= expect("surface_create isolation 30", cagekit_surface_create(cage, &options, &surface),
                CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.isolation_level = 2;
  options.sharp_isolation_level = UINT32_MAX;
  bad |= expect("surface_create sharp isolation UINT32_MAX", cagekit_surface_create(cage, &options, &surface),
                CAGEKIT_ERROR_INVALID_ARGUMENT);
  bad |= expect("surface_create", cagekit_surface_create(cage, NULL, &surface), CAGEKIT_SUCCESS);
  /* count UINT32_MAX: NULL buffers are refused; a bad first location is refused before any
   * further location is read or anything is allocated per location */
  bad |= expect("surface_evaluate count UINT32_MAX, locations NULL",
                cagekit_surface_evaluate(surface, NULL, UINT32_MAX, NULL, &point), CAGEKIT_ERROR_INVALID_ARGUMENT);
  bad |= expect("surface_evaluate count UINT32_MAX, points NULL",
                cagekit_surface_evaluate(surface, NULL, UINT32_MAX, &good_location, NULL),
                CAGEKIT_ERROR_INVALID_ARGUMENT);
  bad |= expect("surface_evaluate count UINT32_MAX, location 0 bad",
                cagekit_surface_evaluate(surface, NULL, UINT32_MAX, &bad_location, &point),
                CAGEKIT_ERROR_INVALID_ARGUMENT);
  if (strstr(cagekit_last_error_message(g_context), "location 0") == NULL) {
    fprintf(stderr, "  surface_evaluate: message does not name location 0: %s\n", cagekit_last_error_message(g_context));
    bad = 1;
  }
  bad |= expect("surface_evaluate_basis face UINT32_MAX",
                cagekit_surface_evaluate_basis(surface, &bad_location, 0, &n, NULL, NULL, NULL, NULL, NULL, NULL, NULL),
                CAGEKIT_ERROR_INVALID_ARGUMENT);
  bad |= expect("surface_get_ptex_face face UINT32_MAX", cagekit_surface_get_ptex_face(surface, UINT32_MAX, 0, &n),
                CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_surface_release(surface);
  cagekit_cage_release(cage);
  return bad;
}

static int tags_huge_indices(void) {
  cagekit_cage cage = grid_cage(2, 2);
  uint32_t pairs[2] = {0, UINT32_MAX}, vertex = UINT32_MAX, face = UINT32_MAX;
  int bad = 0;
  bad |= expect("set_creases vertex UINT32_MAX", cagekit_cage_set_creases(cage, 1, pairs, NULL),
                CAGEKIT_ERROR_INVALID_ARGUMENT);
  bad |= expect("set_corners vertex UINT32_MAX", cagekit_cage_set_corners(cage, 1, &vertex, NULL),
                CAGEKIT_ERROR_INVALID_ARGUMENT);
  bad |= expect("set_holes face UINT32_MAX", cagekit_cage_set_holes(cage, 1, &face), CAGEKIT_ERROR_INVALID_ARGUMENT);
  bad |= expect("set_creases count UINT32_MAX, NULL pairs", cagekit_cage_set_creases(cage, UINT32_MAX, NULL, NULL),
                CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_cage_release(cage);
  return bad;
}

/* The address-space limit itself works: a 512 MiB allocation fails in the child. */
static int limit_self_check(void) {
  void* p = malloc((size_t)512 << 20);
  if (p != NULL) {
    fprintf(stderr, "  a 512 MiB allocation succeeded under the address-space limit\n");
    free(p);
    return 1;
  }
  return 0;
}

int main(int argc, char** argv) {
  if (argc > 1 && strcmp(argv[1], "-v") == 0) g_verbose = 1;
  if (cagekit_context_create(NULL, &g_context) != CAGEKIT_SUCCESS) {
    fprintf(stderr, "cannot create a context\n");
    return 1;
  }
  if (CAGEKIT_SANITIZED_BUILD)
    printf("hostile sizes (sanitizer build: no address-space limit; peak RSS growth must stay below %ld MiB)\n",
           RSS_BOUND_KIB / 1024);
  else
    printf("hostile sizes (each case under RLIMIT_AS = current + %llu MiB; peak RSS growth must stay below %ld MiB)\n",
           (unsigned long long)(AS_HEADROOM_BYTES >> 20), RSS_BOUND_KIB / 1024);
  if (!CAGEKIT_SANITIZED_BUILD) run_case("self-check: 512 MiB malloc fails under the limit", limit_self_check);
  run_case("OBJ: face index 4e9 / 2^28 / -4e9 / 2^64", obj_huge_face_index);
  run_case("OBJ: crease tag counts 4e9", obj_huge_tag_counts);
  run_case("OBJ: one face of 70000 corners", obj_face_beyond_max_face_size);
  run_case("PLY: element vertex/face 4e9, list of 4e9", ply_huge_vertex_count);
  run_case("OFF: 2e9 / 2e8 vertices, 2e9 faces, 4e9 corners", off_huge_counts);
  run_case("Draco: corrupted header/counts (edgebreaker)", draco_corrupt_counts_edgebreaker);
  run_case("Draco: corrupted header/counts (sequential)", draco_corrupt_counts_sequential);
  run_case("mesh_create: counts near UINT32_MAX, tiny buffers", mesh_create_huge_counts);
  run_case("cage_subdivide: levels 30, 2^32-1; 40000 quads x 7/8 levels", subdivide_huge_levels);
  run_case("cage_subdivide: 40000 quads x 6 levels, 64 MiB budget", subdivide_beyond_budget);
  run_case("surface: isolation 30, evaluate count UINT32_MAX", surface_huge_counts);
  run_case("cage tags: indices UINT32_MAX", tags_huge_indices);
  cagekit_context_release(g_context);
  printf("%s: %d failed case(s)\n", g_failures ? "FAIL" : "PASS", g_failures);
  return g_failures ? 1 : 0;
}
