/* SPDX-License-Identifier: GPL-3.0-or-later
 * ABI tests of libcagekit written in C99 against the public header only. */
#include <cagekit/cagekit.h>

#include <math.h>
#include <stddef.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>

#include "c_test.h"

static cagekit_context new_context(void) {
  cagekit_context context = NULL;
  CHECK_OK(cagekit_context_create(NULL, &context));
  return context;
}

/* A unit cube of 6 outward quads, positions as float or double. */
static const double kCubeD[24] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1};
static const uint32_t kCubeQuads[24] = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
static const uint32_t kCubeEdges[24] = {0, 1, 2, 3, 4, 5, 6, 7, 0, 2, 1, 3, 4, 6, 5, 7, 0, 4, 1, 5, 2, 6, 3, 7};

/* A mesh of `face_count` faces of `face_size` vertices each from double xyz positions. */
static cagekit_mesh new_uniform_mesh(cagekit_context context, uint32_t vertex_count, const double* positions,
                                     uint32_t face_count, uint32_t face_size, const uint32_t* indices) {
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  cagekit_mesh mesh = NULL;
  desc.vertex_count = vertex_count;
  desc.positions = positions;
  desc.face_count = face_count;
  desc.uniform_face_size = face_size;
  desc.face_indices = indices;
  CHECK_OK(cagekit_mesh_create(context, &desc, &mesh));
  return mesh;
}

static cagekit_mesh new_cube(cagekit_context context) { return new_uniform_mesh(context, 8, kCubeD, 6, 4, kCubeQuads); }

static cagekit_cage new_creased_cube(cagekit_context context) {
  cagekit_mesh mesh = new_cube(context);
  cagekit_cage cage = NULL;
  CHECK_OK(cagekit_cage_create(mesh, &cage));
  CHECK_OK(cagekit_cage_set_creases(cage, 12, kCubeEdges, NULL));
  cagekit_mesh_release(mesh);
  return cage;
}

/* cagekit_cage_fit and cagekit_scan_to_cage for the tests that do not look at the fit's states:
 * pass capacity 0, so only their count is written. */
static cagekit_status fit_without_passes(cagekit_cage cage, cagekit_mesh scan, const cagekit_fit_options* options,
                                         cagekit_cage* out, cagekit_fit_report* report) {
  uint32_t pass_count = 0;
  return cagekit_cage_fit(cage, scan, options, out, report, 0, &pass_count, NULL);
}

static cagekit_status scan_to_cage_without_passes(cagekit_mesh scan, const cagekit_scan_to_cage_options* options,
                                                  cagekit_cage* cage_out, cagekit_cage* limit_out,
                                                  cagekit_scan_to_cage_report* report) {
  uint32_t pass_count = 0;
  return cagekit_scan_to_cage(scan, options, cage_out, limit_out, report, NULL, 0, &pass_count, NULL);
}

static void version_is_consistent(void) {
  CHECK(cagekit_version() == CAGEKIT_VERSION);
  CHECK(cagekit_abi_version() == CAGEKIT_ABI_VERSION);
  CHECK(strlen(cagekit_version_string()) >= 5);
  CHECK(CAGEKIT_MAKE_VERSION(1, 2, 3) > CAGEKIT_MAKE_VERSION(1, 1, 999));
  CHECK(strcmp(cagekit_status_string(CAGEKIT_ERROR_PARSE), "parse error") == 0);
  CHECK(strcmp(cagekit_status_string((cagekit_status)-999), "unknown status") == 0);
  CHECK(strcmp(cagekit_status_string(CAGEKIT_ERROR_UNSUPPORTED_FEATURE), "unsupported feature") == 0);
  CHECK(strcmp(cagekit_status_string(CAGEKIT_ERROR_INVALID_OPERATION), "invalid operation") == 0);
  CHECK(strcmp(cagekit_status_string((cagekit_status)(CAGEKIT_ERROR_INVALID_OPERATION - 1)), "unknown status") == 0);
}

static void context_rejects_other_abi_and_bad_struct_size(void) {
  cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
  cagekit_context context = (cagekit_context)1;
  desc.abi_version = CAGEKIT_ABI_VERSION + 1;
  CHECK_STATUS(cagekit_context_create(&desc, &context), CAGEKIT_ERROR_VERSION_MISMATCH);
  CHECK(context == NULL);
  CHECK(strstr(cagekit_last_error_message(NULL), "ABI") != NULL);
  /* A host built against 0.1 (ABI 1, other struct layouts) is refused, not read. */
  desc.abi_version = 1;
  CHECK_STATUS(cagekit_context_create(&desc, &context), CAGEKIT_ERROR_VERSION_MISMATCH);
  CHECK(context == NULL);
  CHECK(strstr(cagekit_last_error_message(NULL), "ABI 1") != NULL);
  desc.abi_version = CAGEKIT_ABI_VERSION;
  desc.struct_size = 3;
  CHECK_STATUS(cagekit_context_create(&desc, &context), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_context_create(NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
}

static void older_smaller_struct_is_accepted(void) {
  /* A host built against an older header passes a shorter struct: only the fields it has. */
  cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
  cagekit_context context = NULL;
  desc.struct_size = offsetof(cagekit_context_desc, log);
  CHECK_OK(cagekit_context_create(&desc, &context));
  cagekit_context_release(context);
}

static void mesh_round_trips_through_buffers(void) {
  cagekit_context context = new_context();
  float positions[8 * 4]; /* stride of 4 floats */
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  cagekit_mesh mesh = NULL;
  uint32_t sizes[6] = {4, 4, 4, 4, 4, 4};
  uint32_t vertex_count = 0, face_count = 0, read_sizes[6], read_indices[24];
  uint64_t index_count = 0;
  double back[24];
  int i;
  for (i = 0; i < 8; ++i) {
    positions[4 * i] = (float)kCubeD[3 * i];
    positions[4 * i + 1] = (float)kCubeD[3 * i + 1];
    positions[4 * i + 2] = (float)kCubeD[3 * i + 2];
    positions[4 * i + 3] = -1.0f;
  }
  desc.vertex_count = 8;
  desc.positions = positions;
  desc.position_type = CAGEKIT_SCALAR_FLOAT32;
  desc.position_stride = 4 * sizeof(float);
  desc.face_count = 6;
  desc.face_sizes = sizes;
  desc.face_indices = kCubeQuads;
  CHECK_OK(cagekit_mesh_create(context, &desc, &mesh));

  /* two-call idiom: size query, too small, right size */
  CHECK_OK(cagekit_mesh_get_positions(mesh, CAGEKIT_SCALAR_FLOAT64, 0, &vertex_count, NULL));
  CHECK(vertex_count == 8);
  CHECK_STATUS(cagekit_mesh_get_positions(mesh, CAGEKIT_SCALAR_FLOAT64, 7, &vertex_count, back),
               CAGEKIT_ERROR_SIZE_INSUFFICIENT);
  CHECK(vertex_count == 8);
  CHECK(strstr(cagekit_last_error_message(context), "capacity") != NULL);
  CHECK_OK(cagekit_mesh_get_positions(mesh, CAGEKIT_SCALAR_FLOAT64, 8, &vertex_count, back));
  for (i = 0; i < 24; ++i) CHECK(back[i] == kCubeD[i]);

  CHECK_OK(cagekit_mesh_get_faces(mesh, 0, &face_count, NULL, 0, &index_count, NULL));
  CHECK(face_count == 6 && index_count == 24);
  CHECK_OK(cagekit_mesh_get_faces(mesh, 6, &face_count, read_sizes, 24, &index_count, read_indices));
  for (i = 0; i < 6; ++i) CHECK(read_sizes[i] == 4);
  CHECK(memcmp(read_indices, kCubeQuads, sizeof(kCubeQuads)) == 0);
  CHECK_OK(cagekit_mesh_get_counts(mesh, &vertex_count, &face_count, &index_count));
  CHECK(vertex_count == 8 && face_count == 6 && index_count == 24);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

static void bad_descriptions_are_rejected(void) {
  cagekit_context context = new_context();
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  cagekit_mesh mesh = (cagekit_mesh)1;
  uint32_t zero_size[1] = {0};
  desc.vertex_count = 8;
  desc.positions = NULL;
  CHECK_STATUS(cagekit_mesh_create(context, &desc, &mesh), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(mesh == NULL);
  CHECK(strstr(cagekit_last_error_message(context), "positions") != NULL);
  desc.positions = kCubeD;
  desc.face_count = 1;
  desc.face_sizes = zero_size;
  desc.face_indices = kCubeQuads;
  CHECK_STATUS(cagekit_mesh_create(context, &desc, &mesh), CAGEKIT_ERROR_INVALID_ARGUMENT);
  desc.face_sizes = NULL;
  desc.uniform_face_size = 0x80000000u;
  CHECK_STATUS(cagekit_mesh_create(context, &desc, &mesh), CAGEKIT_ERROR_LIMIT_EXCEEDED);
  CHECK_STATUS(cagekit_mesh_create(NULL, &desc, &mesh), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK_STATUS(cagekit_mesh_create(context, NULL, &mesh), CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_context_release(context);
}

static void wrong_handle_types_are_detected(void) {
  cagekit_context context = new_context();
  cagekit_cage cage = new_creased_cube(context);
  uint32_t count = 0;
  /* a cage passed where a mesh is expected */
  CHECK_STATUS(cagekit_mesh_get_counts((cagekit_mesh)(void*)cage, &count, NULL, NULL), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK_STATUS(cagekit_mesh_get_counts(NULL, &count, NULL, NULL), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK(strstr(cagekit_last_error_message(NULL), "not a valid handle") != NULL);
  cagekit_cage_release(cage);
  cagekit_context_release(context);
}

static void validation_names_the_problem_and_repair_fixes_it(void) {
  cagekit_context context = new_context();
  /* two triangles sharing an edge with the same direction (inconsistent), one bad index,
     and one NaN position */
  double positions[5 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 0};
  uint32_t triangles[9] = {0, 1, 2, 1, 2, 3, 0, 1, 99};
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  cagekit_mesh mesh = NULL, repaired = NULL;
  cagekit_validation_report report;
  cagekit_repair_report repair_report;
  cagekit_repair_options repair_options = CAGEKIT_REPAIR_OPTIONS_INIT;
  cagekit_cage cage = NULL;
  positions[14] = NAN;
  desc.vertex_count = 5;
  desc.positions = positions;
  desc.face_count = 3;
  desc.face_indices = triangles;
  CHECK_OK(cagekit_mesh_create(context, &desc, &mesh));
  report.struct_size = sizeof(report);
  CHECK_STATUS(cagekit_mesh_validate(mesh, &report), CAGEKIT_ERROR_INVALID_MESH);
  CHECK(report.valid == 0);
  CHECK(report.issue_flags & (1u << CAGEKIT_ISSUE_INDEX_OUT_OF_RANGE));
  CHECK(report.issue_flags & (1u << CAGEKIT_ISSUE_NON_FINITE_POSITION));
  CHECK(report.issue_flags & (1u << CAGEKIT_ISSUE_INCONSISTENT_ORIENTATION));
  CHECK(report.issue_counts[CAGEKIT_ISSUE_INDEX_OUT_OF_RANGE] == 1);
  CHECK(strstr(cagekit_last_error_message(context), "99") != NULL);
  CHECK_STATUS(cagekit_cage_create(mesh, &cage), CAGEKIT_ERROR_INVALID_MESH);
  CHECK(cage == NULL);

  repair_report.struct_size = sizeof(repair_report);
  repair_options.steps |= CAGEKIT_REPAIR_REMOVE_UNREFERENCED; /* also drops the NaN vertex */
  CHECK_OK(cagekit_mesh_repair(mesh, &repair_options, &repaired, &repair_report));
  CHECK(repair_report.dropped_invalid_faces == 1);
  CHECK(repair_report.flipped_faces == 1);
  CHECK_OK(cagekit_mesh_validate(repaired, &report));
  CHECK(report.valid == 1);
  cagekit_mesh_release(repaired);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

static void cage_tags_round_trip_and_bad_tags_fail(void) {
  cagekit_context context = new_context();
  cagekit_cage cage = new_creased_cube(context);
  uint32_t count = 0, pairs[24], corner = 0, bad_pair[2] = {0, 7}, hole = 2, holes[1];
  float sharpness[12], corner_sharpness = 2.5f, negative = -1.0f;
  cagekit_boundary_rule rule;
  cagekit_mesh_info info;
  int i;
  CHECK_OK(cagekit_cage_get_creases(cage, 0, &count, NULL, NULL));
  CHECK(count == 12);
  CHECK_OK(cagekit_cage_get_creases(cage, 12, &count, pairs, sharpness));
  for (i = 0; i < 12; ++i) CHECK(sharpness[i] == CAGEKIT_SHARP);
  CHECK(memcmp(pairs, kCubeEdges, sizeof(pairs)) == 0);
  /* (0, 7) is a diagonal, not an edge: rejected, tags unchanged */
  CHECK_STATUS(cagekit_cage_set_creases(cage, 1, bad_pair, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "not an edge") != NULL);
  CHECK_STATUS(cagekit_cage_set_creases(cage, 1, kCubeEdges, &negative), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_OK(cagekit_cage_get_creases(cage, 0, &count, NULL, NULL));
  CHECK(count == 12);
  CHECK_OK(cagekit_cage_set_corners(cage, 1, &corner, &corner_sharpness));
  CHECK_OK(cagekit_cage_get_corners(cage, 1, &count, &corner, &corner_sharpness));
  CHECK(count == 1 && corner == 0 && corner_sharpness == 2.5f);
  corner = 8;
  CHECK_STATUS(cagekit_cage_set_corners(cage, 1, &corner, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_OK(cagekit_cage_set_holes(cage, 1, &hole));
  CHECK_OK(cagekit_cage_get_holes(cage, 1, &count, holes));
  CHECK(count == 1 && holes[0] == 2);
  hole = 6;
  CHECK_STATUS(cagekit_cage_set_holes(cage, 1, &hole), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_OK(cagekit_cage_set_boundary_rule(cage, CAGEKIT_BOUNDARY_EDGES_AND_CORNERS));
  CHECK_OK(cagekit_cage_get_boundary_rule(cage, &rule));
  CHECK(rule == CAGEKIT_BOUNDARY_EDGES_AND_CORNERS);
  CHECK_STATUS(cagekit_cage_set_boundary_rule(cage, (cagekit_boundary_rule)7), CAGEKIT_ERROR_INVALID_ARGUMENT);
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_cage_get_info(cage, &info));
  CHECK(info.creases == 12 && info.corners == 1 && info.holes == 1 && info.quads == 6 && info.genus == 0);
  cagekit_cage_release(cage);
  cagekit_context_release(context);
}

static void cage_survives_every_format_in_memory(void) {
  cagekit_context context = new_context();
  cagekit_cage cage = new_creased_cube(context), back = NULL;
  cagekit_write_options options = CAGEKIT_WRITE_OPTIONS_INIT;
  cagekit_write_report report;
  cagekit_blob blob = NULL;
  cagekit_mesh_info info;
  const cagekit_file_format formats[4] = {CAGEKIT_FORMAT_OBJ, CAGEKIT_FORMAT_PLY, CAGEKIT_FORMAT_OFF,
                                          CAGEKIT_FORMAT_DRACO};
  int i;
  for (i = 0; i < 4; ++i) {
    options.format = formats[i];
    report.struct_size = sizeof(report);
    CHECK_OK(cagekit_cage_write_memory(cage, &options, &blob, &report));
    CHECK(cagekit_blob_size(blob) == report.bytes && report.bytes > 0);
    CHECK_OK(cagekit_cage_read_memory(context, cagekit_blob_data(blob), cagekit_blob_size(blob), CAGEKIT_FORMAT_AUTO,
                                      &back));
    info.struct_size = sizeof(info);
    CHECK_OK(cagekit_cage_get_info(back, &info));
    CHECK(info.quads == 6 && info.vertices == 8);
    /* OBJ and Draco keep the tags; PLY and OFF hold polygons only */
    CHECK(info.creases == ((formats[i] == CAGEKIT_FORMAT_OBJ || formats[i] == CAGEKIT_FORMAT_DRACO) ? 12u : 0u));
    if (formats[i] == CAGEKIT_FORMAT_DRACO) CHECK(report.max_position_error < 1e-3);
    cagekit_cage_release(back);
    back = NULL;
    cagekit_blob_release(blob);
    blob = NULL;
  }
  options.format = CAGEKIT_FORMAT_AUTO;
  CHECK_STATUS(cagekit_cage_write_memory(cage, &options, &blob, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.format = CAGEKIT_FORMAT_DRACO;
  options.draco_position_bits = 31;
  CHECK_STATUS(cagekit_cage_write_memory(cage, &options, &blob, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(blob == NULL);
  cagekit_cage_release(cage);
  cagekit_context_release(context);
}

/* STL through the C API: an ascii soup of two triangles reads welded (by CAGEKIT_FORMAT_STL and
 * sniffed), a hostile binary count is a parse error, and writing STL is UNSUPPORTED_FORMAT. */
static void stl_is_read_welded_and_not_written(void) {
  cagekit_context context = new_context();
  const char* text =
      "solid quad\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\nendfacet\n"
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid quad\n";
  unsigned char hostile[84];
  cagekit_mesh mesh = NULL;
  cagekit_mesh_info info;
  cagekit_write_options options = CAGEKIT_WRITE_OPTIONS_INIT;
  cagekit_blob blob = NULL;
  int i;
  for (i = 0; i < 2; ++i) {
    CHECK_OK(cagekit_mesh_read_memory(context, text, strlen(text), i ? CAGEKIT_FORMAT_AUTO : CAGEKIT_FORMAT_STL,
                                      &mesh));
    info.struct_size = sizeof(info);
    CHECK_OK(cagekit_mesh_get_info(mesh, &info));
    CHECK(info.vertices == 4 && info.faces == 2 && info.triangles == 2 && info.boundary_loops == 1);
    if (i == 0) {
      options.format = CAGEKIT_FORMAT_STL;
      CHECK_STATUS(cagekit_mesh_write_memory(mesh, &options, &blob, NULL), CAGEKIT_ERROR_UNSUPPORTED_FORMAT);
      CHECK(blob == NULL);
      CHECK(strstr(cagekit_last_error_message(context), "STL: writing is not supported") != NULL);
    }
    cagekit_mesh_release(mesh);
    mesh = NULL;
  }
  memset(hostile, ' ', 80);
  memset(hostile + 80, 0xFF, 4);
  CHECK_STATUS(cagekit_mesh_read_memory(context, hostile, sizeof(hostile), CAGEKIT_FORMAT_STL, &mesh),
               CAGEKIT_ERROR_PARSE);
  CHECK(mesh == NULL);
  CHECK(strstr(cagekit_last_error_message(context), "4294967295") != NULL);
  cagekit_context_release(context);
}

static void corrupt_memory_is_a_parse_error(void) {
  cagekit_context context = new_context();
  const char* text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
  cagekit_mesh mesh = NULL;
  CHECK_STATUS(cagekit_mesh_read_memory(context, text, strlen(text), CAGEKIT_FORMAT_OBJ, &mesh),
               CAGEKIT_ERROR_PARSE);
  CHECK(mesh == NULL);
  CHECK(strstr(cagekit_last_error_message(context), ":4") != NULL);
  CHECK_STATUS(cagekit_mesh_read_memory(context, "\x01\x02garbage", 9, CAGEKIT_FORMAT_DRACO, &mesh),
               CAGEKIT_ERROR_PARSE);
  CHECK_STATUS(cagekit_mesh_read_file(context, "/nonexistent/dir/x.obj", CAGEKIT_FORMAT_AUTO, &mesh),
               CAGEKIT_ERROR_IO);
  cagekit_context_release(context);
}

static int g_progress_calls = 0;
static int cancel_after_first(void* user, const char* stage, double fraction) {
  (void)user;
  (void)stage;
  (void)fraction;
  ++g_progress_calls;
  return 0;
}

static void progress_callback_can_cancel(void) {
  cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
  cagekit_context context = NULL;
  cagekit_cage cage, refined = (cagekit_cage)1;
  cagekit_subdivide_options options = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  desc.progress = cancel_after_first;
  CHECK_OK(cagekit_context_create(&desc, &context));
  cage = new_creased_cube(context);
  options.levels = 4;
  CHECK_STATUS(cagekit_cage_subdivide(cage, &options, &refined), CAGEKIT_ERROR_CANCELLED);
  CHECK(refined == NULL);
  CHECK(g_progress_calls >= 1);
  CHECK_OK(cagekit_context_set_progress(context, NULL, NULL));
  cagekit_context_cancel(context);
  CHECK_STATUS(cagekit_cage_subdivide(cage, &options, &refined), CAGEKIT_ERROR_CANCELLED);
  cagekit_context_reset_cancel(context);
  CHECK_OK(cagekit_cage_subdivide(cage, &options, &refined));
  cagekit_cage_release(refined);
  cagekit_cage_release(cage);
  cagekit_context_release(context);
}

static void subdivision_counts_and_tags(void) {
  cagekit_context context = new_context();
  cagekit_cage cage = new_creased_cube(context), refined = NULL;
  cagekit_subdivide_options options = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  cagekit_mesh_info info;
  uint32_t level;
  for (level = 0; level <= 3; ++level) {
    options.levels = level;
    CHECK_OK(cagekit_cage_subdivide(cage, &options, &refined));
    info.struct_size = sizeof(info);
    CHECK_OK(cagekit_cage_get_info(refined, &info));
    CHECK(info.faces == 6u << (2 * level));
    CHECK(info.quads == info.faces);
    CHECK(info.creases == 12u << level);
    CHECK(info.genus == 0);
    cagekit_cage_release(refined);
    refined = NULL;
  }
  options.levels = CAGEKIT_MAX_SUBDIVISION_LEVELS + 1;
  CHECK_STATUS(cagekit_cage_subdivide(cage, &options, &refined), CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_cage_release(cage);
  cagekit_context_release(context);
}

static void surface_basis_is_a_partition_of_unity(void) {
  cagekit_context context = new_context();
  cagekit_mesh mesh = new_cube(context);
  cagekit_cage cage = NULL;
  cagekit_surface surface = NULL;
  uint32_t ptex = 0, controls = 0, count = 0, k;
  uint32_t indices[64];
  double w[64], wu[64], sum, sum_u, moved[24];
  cagekit_surface_location location = {3, 0.3, 0.7}, bad = {0, 1.5, 0.0};
  cagekit_surface_point a, b;
  int i;
  CHECK_OK(cagekit_cage_create(mesh, &cage));
  CHECK_OK(cagekit_surface_create(cage, NULL, &surface));
  CHECK_OK(cagekit_surface_get_counts(surface, &ptex, &controls));
  CHECK(ptex == 6 && controls == 8);
  CHECK_OK(cagekit_surface_evaluate_basis(surface, &location, 0, &count, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
  CHECK(count > 0 && count <= 64);
  CHECK_OK(cagekit_surface_evaluate_basis(surface, &location, 64, &count, indices, w, wu, NULL, NULL, NULL, NULL));
  sum = sum_u = 0;
  for (k = 0; k < count; ++k) {
    CHECK(indices[k] < 8);
    sum += w[k];
    sum_u += wu[k];
  }
  CHECK(fabs(sum - 1.0) < 1e-12);
  CHECK(fabs(sum_u) < 1e-10);
  /* moving every control point by t moves the surface by t */
  for (i = 0; i < 24; ++i) moved[i] = kCubeD[i] + (i % 3 == 2 ? 0.5 : 0.0);
  CHECK_OK(cagekit_surface_evaluate(surface, NULL, 1, &location, &a));
  CHECK_OK(cagekit_surface_evaluate(surface, moved, 1, &location, &b));
  CHECK(fabs(b.position[2] - a.position[2] - 0.5) < 1e-12);
  CHECK(fabs(b.position[0] - a.position[0]) < 1e-12);
  CHECK_STATUS(cagekit_surface_evaluate(surface, NULL, 1, &bad, &a), CAGEKIT_ERROR_INVALID_ARGUMENT);
  bad.face = 6;
  bad.u = 0.5;
  CHECK_STATUS(cagekit_surface_evaluate(surface, NULL, 1, &bad, &a), CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_surface_release(surface);
  cagekit_cage_release(cage);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

/* The limit surface as Bezier patches: exact ones reproduce cagekit_surface_evaluate, the others
 * stay within the tolerance; bad options, ranges and a cancel fail with the right status. */
static double bezier_weight(int i, double s) {
  const double r = 1.0 - s;
  return i == 0 ? r * r * r : i == 1 ? 3 * s * r * r : i == 2 ? 3 * s * s * r : s * s * s;
}

static void limit_patches_match_the_surface(void) {
  cagekit_context context = new_context();
  cagekit_mesh mesh = new_cube(context);
  cagekit_cage cage = NULL;
  cagekit_surface surface = NULL;
  cagekit_limit_patches patches = NULL;
  cagekit_limit_patch_options options = CAGEKIT_LIMIT_PATCH_OPTIONS_INIT;
  cagekit_limit_patch_info info;
  cagekit_limit_patch* all;
  uint32_t k, exact = 0, count = 0;
  double worst_exact = 0, worst_approx = 0;
  CHECK_OK(cagekit_cage_create(mesh, &cage));
  CHECK_OK(cagekit_surface_create(cage, NULL, &surface));
  CHECK_OK(cagekit_limit_patches_create(cage, &options, &patches));
  memset(&info, 0, sizeof(info));
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_limit_patches_get_info(patches, &info));
  CHECK(info.patch_count == info.exact_count + info.approximated_count);
  CHECK(info.exact_count > 0 && info.approximated_count > 0 && info.over_tolerance_count == 0);
  CHECK(info.max_error <= info.tolerance && fabs(info.tolerance - 1e-4 * info.bbox_diagonal) < 1e-15);
  all = (cagekit_limit_patch*)calloc(info.patch_count, sizeof(cagekit_limit_patch));
  CHECK(all != NULL);
  CHECK_OK(cagekit_limit_patches_get(patches, info.patch_count, &count, all));
  CHECK(count == info.patch_count);
  for (k = 0; k < info.patch_count; ++k) {
    const cagekit_limit_patch* p = &all[k];
    const double s = 0.37, t = 0.81;
    double x[3] = {0, 0, 0}, d;
    cagekit_surface_location l;
    cagekit_surface_point y;
    int i, j, c;
    CHECK(p->ptex_face < 6 && p->cage_face == p->ptex_face);
    for (j = 0; j < 4; ++j)
      for (i = 0; i < 4; ++i)
        for (c = 0; c < 3; ++c) x[c] += p->control_points[3 * (4 * j + i) + c] * bezier_weight(i, s) * bezier_weight(j, t);
    l.face = p->ptex_face;
    l.u = p->u0 + s * (p->u1 - p->u0);
    l.v = p->v0 + t * (p->v1 - p->v0);
    CHECK_OK(cagekit_surface_evaluate(surface, NULL, 1, &l, &y));
    d = sqrt((x[0] - y.position[0]) * (x[0] - y.position[0]) + (x[1] - y.position[1]) * (x[1] - y.position[1]) +
             (x[2] - y.position[2]) * (x[2] - y.position[2]));
    if (p->exact) {
      ++exact;
      if (d > worst_exact) worst_exact = d;
    } else if (d > worst_approx) {
      worst_approx = d;
    }
  }
  CHECK(exact == info.exact_count);
  CHECK(worst_exact < 1e-12 * info.bbox_diagonal);
  CHECK(worst_approx <= 1.5 * info.tolerance);
  free(all);
  CHECK_STATUS(cagekit_limit_patches_get(NULL, 0, &count, NULL), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK_STATUS(cagekit_limit_patches_get_info(patches, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_limit_patches_release(patches);
  patches = NULL;

  options.tolerance = 0.0;
  CHECK_STATUS(cagekit_limit_patches_create(cage, &options, &patches), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(patches == NULL);
  options.tolerance = NAN;
  CHECK_STATUS(cagekit_limit_patches_create(cage, &options, &patches), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.tolerance = 1e-4;
  options.max_depth = 13;
  CHECK_STATUS(cagekit_limit_patches_create(cage, &options, &patches), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.max_depth = 8;
  options.threads = 5000;
  CHECK_STATUS(cagekit_limit_patches_create(cage, &options, &patches), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.threads = 0;
  CHECK_STATUS(cagekit_limit_patches_create(NULL, &options, &patches), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK_STATUS(cagekit_limit_patches_create(cage, &options, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_limit_patches_get_info((cagekit_limit_patches)surface, &info), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK_OK(cagekit_context_set_progress(context, cancel_after_first, NULL));
  CHECK_STATUS(cagekit_limit_patches_create(cage, &options, &patches), CAGEKIT_ERROR_CANCELLED);
  CHECK(patches == NULL);
  cagekit_surface_release(surface);
  cagekit_cage_release(cage);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

/* The last error is kept per thread: a failure on one thread does not overwrite another's. */
static cagekit_context g_shared_context;
static void* fail_on_thread(void* arg) {
  cagekit_mesh mesh = NULL;
  const char* text = "v 0 0 0\nf 1 2 3\n";
  int* ok = (int*)arg;
  *ok = cagekit_mesh_read_memory(g_shared_context, text, strlen(text), CAGEKIT_FORMAT_OBJ, &mesh) ==
            CAGEKIT_ERROR_PARSE &&
        strlen(cagekit_last_error_message(g_shared_context)) > 0;
  return NULL;
}

/* One array output as (object, capacity, count_out, array), for check_two_call_shape. */
typedef cagekit_status (*two_call_fn)(void* object, uint32_t capacity, uint32_t* count_out, void* array);

static cagekit_status mesh_positions(void* mesh, uint32_t capacity, uint32_t* count_out, void* array) {
  return cagekit_mesh_get_positions((cagekit_mesh)mesh, CAGEKIT_SCALAR_FLOAT64, capacity, count_out, array);
}
static cagekit_status cage_holes(void* cage, uint32_t capacity, uint32_t* count_out, void* array) {
  return cagekit_cage_get_holes((cagekit_cage)cage, capacity, count_out, (uint32_t*)array);
}
static cagekit_status limit_patches(void* patches, uint32_t capacity, uint32_t* count_out, void* array) {
  return cagekit_limit_patches_get((cagekit_limit_patches)patches, capacity, count_out, (cagekit_limit_patch*)array);
}

/* The rules of the header's "Buffers" convention on one output of `element` bytes per entry and
 * at least 2 entries; returns the array filled by an exact capacity (free it), with one more entry
 * after it that must stay untouched. `x` names the <x>_capacity / <x>_count_out parameters. */
static unsigned char* check_two_call_shape(cagekit_context context, two_call_fn fn, void* object, size_t element,
                                           const char* x, const char* array_name, uint32_t* count) {
  uint32_t expected = 0;
  size_t i, bytes;
  unsigned char* array;
  char text[64];
  /* count_out NULL: INVALID_ARGUMENT naming it */
  CHECK_STATUS(fn(object, 0, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  snprintf(text, sizeof(text), "%s_count_out", x);
  CHECK(strstr(cagekit_last_error_message(context), text) != NULL);
  /* capacity 0: only the count, the array may be NULL and is not touched */
  CHECK_OK(fn(object, 0, &expected, NULL));
  CHECK(expected >= 2);
  bytes = element * (expected + 1);
  array = (unsigned char*)malloc(bytes);
  CHECK(array != NULL);
  memset(array, 0xa5, bytes);
  *count = 0;
  CHECK_OK(fn(object, 0, count, array));
  CHECK(*count == expected);
  for (i = 0; i < bytes; ++i) CHECK(array[i] == 0xa5);
  /* a nonzero capacity below the count: SIZE_INSUFFICIENT, the count written, the message naming
     the array and both numbers */
  *count = 0;
  CHECK_STATUS(fn(object, expected - 1, count, array), CAGEKIT_ERROR_SIZE_INSUFFICIENT);
  CHECK(*count == expected);
  CHECK(strstr(cagekit_last_error_message(context), array_name) != NULL);
  snprintf(text, sizeof(text), "%s_capacity %u is less than the required %u", x, (unsigned)(expected - 1),
           (unsigned)expected);
  CHECK(strstr(cagekit_last_error_message(context), text) != NULL);
  /* a nonzero capacity with a NULL array: INVALID_ARGUMENT naming it */
  CHECK_STATUS(fn(object, expected, count, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), array_name) != NULL);
  /* the exact capacity: filled, nothing written after it */
  memset(array, 0xa5, bytes);
  *count = 0;
  CHECK_OK(fn(object, expected, count, array));
  CHECK(*count == expected);
  for (i = element * expected; i < bytes; ++i) CHECK(array[i] == 0xa5);
  return array;
}

/* One shape for every array output, checked on three functions that had three shapes before
 * (count optional; range paging; the standard one). */
static void array_outputs_have_one_two_call_shape(void) {
  cagekit_context context = new_context();
  cagekit_mesh mesh = new_cube(context);
  cagekit_cage cage = NULL;
  cagekit_limit_patches patches = NULL;
  cagekit_limit_patch_info info;
  static const uint32_t holes[2] = {4, 1};
  const double* positions;
  const uint32_t* hole_faces;
  const cagekit_limit_patch* patch;
  uint32_t count = 0, k;
  unsigned char* array;

  array = check_two_call_shape(context, mesh_positions, mesh, 3 * sizeof(double), "vertex", "positions", &count);
  positions = (const double*)array;
  CHECK(count == 8 && memcmp(positions, kCubeD, sizeof(kCubeD)) == 0);
  free(array);

  CHECK_OK(cagekit_cage_create(mesh, &cage));
  CHECK_OK(cagekit_cage_set_holes(cage, 2, holes));
  array = check_two_call_shape(context, cage_holes, cage, sizeof(uint32_t), "hole", "faces", &count);
  hole_faces = (const uint32_t*)array;
  CHECK(count == 2 && hole_faces[0] == 1 && hole_faces[1] == 4);
  free(array);

  CHECK_OK(cagekit_cage_set_holes(cage, 0, NULL));
  CHECK_OK(cagekit_limit_patches_create(cage, NULL, &patches));
  memset(&info, 0, sizeof(info));
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_limit_patches_get_info(patches, &info));
  array = check_two_call_shape(context, limit_patches, patches, sizeof(cagekit_limit_patch), "patch", "patch_array",
                               &count);
  patch = (const cagekit_limit_patch*)array;
  CHECK(count == info.patch_count);
  for (k = 1; k < count; ++k) CHECK(patch[k].ptex_face >= patch[k - 1].ptex_face && patch[k].reserved == 0);
  free(array);

  cagekit_limit_patches_release(patches);
  cagekit_cage_release(cage);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

/* Limit B-spline surfaces (cagekit_limit_surfaces_*). */

/* The values of every B-spline basis function N_i (i < count - degree - 1) of a clamped knot
 * vector at x, by the Cox-de Boor recursion (0/0 = 0; x = 1 belongs to the last nonempty span). */
static void cox_de_boor(const double* knots, uint32_t count, uint32_t degree, double x, double* basis) {
  double n[160];
  uint32_t i, p, last = 0;
  for (i = 0; i + 1 < count; ++i)
    if (knots[i] < knots[i + 1]) last = i;
  for (i = 0; i + 1 < count; ++i)
    n[i] = (knots[i] <= x && x < knots[i + 1]) || (i == last && x == knots[i + 1]) ? 1.0 : 0.0;
  for (p = 1; p <= degree; ++p)
    for (i = 0; i + p + 1 < count; ++i) {
      const double a = knots[i + p] > knots[i] ? (x - knots[i]) / (knots[i + p] - knots[i]) : 0.0;
      const double b = knots[i + p + 1] > knots[i + 1] ? (knots[i + p + 1] - x) / (knots[i + p + 1] - knots[i + 1]) : 0.0;
      n[i] = a * n[i] + b * n[i + 1];
    }
  for (i = 0; i + degree + 1 < count; ++i) basis[i] = n[i];
}

/* One surface read through the C API: descriptor, knots, control points. */
typedef struct test_bspline {
  cagekit_limit_surface d;
  double ku[160], kv[160];
  double* points;
} test_bspline;

static void read_bspline(cagekit_limit_surfaces surfaces, uint32_t index, test_bspline* s) {
  uint32_t count = 0;
  CHECK_OK(cagekit_limit_surfaces_get_surface(surfaces, index, &s->d));
  CHECK(s->d.knot_count_u <= 160 && s->d.knot_count_v <= 160);
  CHECK_OK(cagekit_limit_surfaces_get_knots(surfaces, index, CAGEKIT_SURFACE_DIRECTION_U, 160, &count, s->ku));
  CHECK(count == s->d.knot_count_u);
  CHECK_OK(cagekit_limit_surfaces_get_knots(surfaces, index, CAGEKIT_SURFACE_DIRECTION_V, 160, &count, s->kv));
  CHECK(count == s->d.knot_count_v);
  s->points = (double*)calloc(3 * (size_t)s->d.num_u * s->d.num_v, sizeof(double));
  CHECK(s->points != NULL);
  CHECK_OK(cagekit_limit_surfaces_get_control_points(surfaces, index, s->d.num_u * s->d.num_v, &count, s->points));
  CHECK(count == s->d.num_u * s->d.num_v);
}

static void bspline_point(const test_bspline* s, double u, double v, double* x) {
  double bu[160], bv[160];
  uint32_t i, j, c;
  cox_de_boor(s->ku, s->d.knot_count_u, s->d.degree_u, u, bu);
  cox_de_boor(s->kv, s->d.knot_count_v, s->d.degree_v, v, bv);
  x[0] = x[1] = x[2] = 0;
  for (j = 0; j < s->d.num_v; ++j)
    for (i = 0; i < s->d.num_u; ++i)
      for (c = 0; c < 3; ++c) x[c] += bu[i] * bv[j] * s->points[3 * ((size_t)j * s->d.num_u + i) + c];
}

/* (u, v) of side parameter t on side 0..3 (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0). */
static void side_uv(uint32_t side, double t, double* u, double* v) {
  *u = side == 1 ? 1.0 : side == 3 ? 0.0 : t;
  *v = side == 0 ? 0.0 : side == 2 ? 1.0 : t;
}

/* Index in `points` of the k-th control point along side `side` and how many there are. */
static uint32_t border_count(const test_bspline* s, uint32_t side) { return side % 2 == 0 ? s->d.num_u : s->d.num_v; }
static size_t border_point(const test_bspline* s, uint32_t side, uint32_t k) {
  const uint32_t i = side == 0 || side == 2 ? k : side == 1 ? s->d.num_u - 1 : 0;
  const uint32_t j = side == 1 || side == 3 ? k : side == 2 ? s->d.num_v - 1 : 0;
  return 3 * ((size_t)j * s->d.num_u + i);
}

static double distance3(const double* a, const double* b) {
  return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

/* Checks every surface against the limit surface and its neighbours; returns the largest distance
 * to the limit surface at an 11 x 11 grid of every surface. Sets *identical_borders to the number
 * of shared sides whose border control points are the same numbers as the neighbour's. */
static double check_bspline_surfaces(cagekit_cage cage, cagekit_limit_surfaces surfaces,
                                     const cagekit_limit_surface_info* info, uint32_t* identical_borders) {
  cagekit_surface surface = NULL;
  test_bspline* all = (test_bspline*)calloc(info->surface_count, sizeof(test_bspline));
  uint32_t k, side, i, j, exact = 0, count;
  double worst = 0;
  *identical_borders = 0;
  CHECK(all != NULL);
  CHECK_OK(cagekit_surface_create(cage, NULL, &surface));
  for (k = 0; k < info->surface_count; ++k) read_bspline(surfaces, k, &all[k]);
  for (k = 0; k < info->surface_count; ++k) {
    const test_bspline* s = &all[k];
    double worst_here = 0;
    exact += s->d.exact == CAGEKIT_TRUE;
    CHECK(k == 0 || s->d.ptex_face > all[k - 1].d.ptex_face);
    CHECK(s->d.ptex_face < info->ptex_face_count && s->d.reserved == 0);
    CHECK(s->d.degree_u == 3 && s->d.degree_v == 3);
    CHECK(s->d.knot_count_u == s->d.num_u + s->d.degree_u + 1 && s->d.knot_count_v == s->d.num_v + s->d.degree_v + 1);
    /* clamped: degree + 1 zeros and ones, simple interior knots in between */
    for (i = 0; i <= s->d.degree_u; ++i) CHECK(s->ku[i] == 0.0 && s->ku[s->d.knot_count_u - 1 - i] == 1.0);
    for (i = 0; i <= s->d.degree_v; ++i) CHECK(s->kv[i] == 0.0 && s->kv[s->d.knot_count_v - 1 - i] == 1.0);
    for (i = s->d.degree_u; i + s->d.degree_u + 1 < s->d.knot_count_u; ++i) CHECK(s->ku[i] < s->ku[i + 1]);
    for (i = s->d.degree_v; i + s->d.degree_v + 1 < s->d.knot_count_v; ++i) CHECK(s->kv[i] < s->kv[i + 1]);
    for (j = 0; j <= 10; ++j)
      for (i = 0; i <= 10; ++i) {
        cagekit_surface_location l;
        cagekit_surface_point y;
        double x[3], d;
        l.face = s->d.ptex_face;
        l.u = i / 10.0;
        l.v = j / 10.0;
        bspline_point(s, l.u, l.v, x);
        CHECK_OK(cagekit_surface_evaluate(surface, NULL, 1, &l, &y));
        d = distance3(x, y.position);
        if (d > worst_here) worst_here = d;
      }
    /* equal parameters: within the parametric error, which bounds the two-sided one */
    CHECK(worst_here <= s->d.parametric_error * (1 + 1e-9) + 1e-13 * info->bbox_diagonal);
    CHECK(s->d.error <= s->d.parametric_error * (1 + 1e-12) + 1e-15 * info->bbox_diagonal);
    CHECK(s->d.max_normal_deviation_deg >= 0 && s->d.max_normal_deviation_deg <= info->max_normal_deviation_deg);
    if (worst_here > worst) worst = worst_here;
    /* neighbours: symmetric, and the two surfaces meet along the shared range */
    for (side = 0; side < 4; ++side) {
      cagekit_limit_surface_neighbour nb[8];
      const cagekit_limit_surface_side* sd = &s->d.sides[side];
      CHECK(sd->neighbour_count <= 8);
      CHECK_OK(cagekit_limit_surfaces_get_neighbours(surfaces, k, side, 8, &count, nb));
      CHECK(count == sd->neighbour_count);
      CHECK((sd->kind == CAGEKIT_SURFACE_BORDER_BOUNDARY) == (count == 0));
      for (i = 0; i < count && i < 8; ++i) {
        const test_bspline* o = &all[nb[i].surface];
        cagekit_limit_surface_neighbour back[8];
        uint32_t back_count = 0, q, found = 0;
        CHECK(nb[i].surface < info->surface_count && nb[i].surface != k && nb[i].side < 4);
        CHECK(o->d.sides[nb[i].side].kind == sd->kind);
        CHECK_OK(cagekit_limit_surfaces_get_neighbours(surfaces, nb[i].surface, nb[i].side, 8, &back_count, back));
        for (q = 0; q < back_count && q < 8; ++q)
          found += back[q].surface == k && back[q].side == side &&
                   fabs(fmin(back[q].t0, back[q].t1) - fmin(nb[i].n0, nb[i].n1)) < 1e-15 &&
                   fabs(fmax(back[q].t0, back[q].t1) - fmax(nb[i].n0, nb[i].n1)) < 1e-15;
        CHECK(found == 1);
        for (q = 0; q <= 8; ++q) {
          const double t = nb[i].t0 + (nb[i].t1 - nb[i].t0) * q / 8.0, n = nb[i].n0 + (nb[i].n1 - nb[i].n0) * q / 8.0;
          double u, v, a[3], b[3];
          side_uv(side, t, &u, &v);
          bspline_point(s, u, v, a);
          side_uv(nb[i].side, n, &u, &v);
          bspline_point(o, u, v, b);
          CHECK(distance3(a, b) <= 1e-12 * info->bbox_diagonal);
        }
        /* a whole side shared with a whole side of as many control points: the same points */
        if (count == 1 && nb[i].t0 == 0.0 && nb[i].t1 == 1.0 && fabs(nb[i].n1 - nb[i].n0) == 1.0 &&
            border_count(s, side) == border_count(o, nb[i].side)) {
          const uint32_t m = border_count(s, side);
          int same = 1;
          for (q = 0; q < m; ++q) {
            const size_t a = border_point(s, side, q), b = border_point(o, nb[i].side, nb[i].n1 > nb[i].n0 ? q : m - 1 - q);
            same &= s->points[a] == o->points[b] && s->points[a + 1] == o->points[b + 1] &&
                    s->points[a + 2] == o->points[b + 2];
          }
          CHECK(same);
          *identical_borders += (uint32_t)same;
        }
      }
    }
  }
  CHECK(exact == info->exact_count);
  for (k = 0; k < info->surface_count; ++k) free(all[k].points);
  free(all);
  cagekit_surface_release(surface);
  return worst;
}

/* A torus of nu x nv quads, every vertex of valence 4: its limit surface is one bicubic B-spline. */
static cagekit_cage new_torus_cage(cagekit_context context, uint32_t nu, uint32_t nv) {
  double positions[3 * 16 * 16];
  uint32_t quads[4 * 16 * 16], i, j;
  cagekit_mesh mesh;
  cagekit_cage cage = NULL;
  for (i = 0; i < nu; ++i)
    for (j = 0; j < nv; ++j) {
      const double a = 2 * 3.14159265358979323846 * i / nu, b = 2 * 3.14159265358979323846 * j / nv;
      double* p = &positions[3 * (i * nv + j)];
      uint32_t* q = &quads[4 * (i * nv + j)];
      p[0] = (2.0 + 0.7 * cos(b)) * cos(a);
      p[1] = (2.0 + 0.7 * cos(b)) * sin(a);
      p[2] = 0.7 * sin(b) + 0.01 * i; /* not symmetric in z */
      q[0] = i * nv + j;
      q[1] = ((i + 1) % nu) * nv + j;
      q[2] = ((i + 1) % nu) * nv + (j + 1) % nv;
      q[3] = i * nv + (j + 1) % nv;
    }
  mesh = new_uniform_mesh(context, nu * nv, positions, nu * nv, 4, quads);
  CHECK_OK(cagekit_cage_create(mesh, &cage));
  cagekit_mesh_release(mesh);
  return cage;
}

static cagekit_limit_surface_info limit_surface_info(cagekit_limit_surfaces surfaces) {
  cagekit_limit_surface_info info;
  memset(&info, 0, sizeof(info));
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_limit_surfaces_get_info(surfaces, &info));
  return info;
}

static void limit_surfaces_of_a_regular_torus_are_exact(void) {
  cagekit_context context = new_context();
  cagekit_cage cage = new_torus_cage(context, 8, 6);
  cagekit_limit_surfaces surfaces = NULL;
  cagekit_limit_surface_info info;
  uint32_t identical = 0;
  double worst;
  CHECK_OK(cagekit_limit_surfaces_create(cage, NULL, &surfaces));
  info = limit_surface_info(surfaces);
  CHECK(info.surface_count == 48 && info.ptex_face_count == 48);
  CHECK(info.exact_count == 48 && info.approximated_count == 0 && info.over_tolerance_count == 0);
  CHECK(info.max_error_rel <= 1e-12 && fabs(info.max_error_rel * info.bbox_diagonal - info.max_error) < 1e-20);
  CHECK(fabs(info.tolerance - 1e-4 * info.bbox_diagonal) <= 1e-15 * info.bbox_diagonal);
  CHECK(info.level >= 1 && info.level <= 5);
  CHECK(info.max_normal_jump_deg < 1e-6 && info.max_crease_angle_deg == 0.0);
  CHECK(info.max_parametric_error <= 1e-12 * info.bbox_diagonal && info.max_normal_deviation_deg < 1e-6);
  CHECK(info.folded_count == 0 && info.limit_fold_points == 0);
  worst = check_bspline_surfaces(cage, surfaces, &info, &identical);
  CHECK(worst <= 1e-12 * info.bbox_diagonal);
  CHECK(identical == 4 * 48); /* every side of every surface */
  cagekit_limit_surfaces_release(surfaces);
  cagekit_cage_release(cage);
  cagekit_context_release(context);
}

static void limit_surfaces_of_a_cube_approximate_within_the_tolerance(void) {
  cagekit_context context = new_context();
  cagekit_mesh mesh = new_cube(context);
  cagekit_cage cage = NULL, creased = new_creased_cube(context);
  cagekit_limit_surfaces surfaces = NULL;
  cagekit_limit_surface_options options = CAGEKIT_LIMIT_SURFACE_OPTIONS_INIT;
  cagekit_limit_surface_info info;
  cagekit_limit_surface d;
  uint32_t identical = 0, k, side;
  double worst;
  CHECK_OK(cagekit_cage_create(mesh, &cage));
  /* smooth: every ptex face touches a valence-3 corner, so every surface is approximated */
  CHECK_OK(cagekit_limit_surfaces_create(cage, &options, &surfaces));
  info = limit_surface_info(surfaces);
  CHECK(info.surface_count == 6 && info.ptex_face_count == 6);
  CHECK(info.exact_count == 0 && info.approximated_count == 6 && info.over_tolerance_count == 0);
  CHECK(info.max_error > 0 && info.max_error <= info.tolerance && info.folded_count == 0);
  CHECK(info.max_error <= info.max_parametric_error && info.max_normal_deviation_deg < 90.0);
  /* smooth borders: refined until the normal jump is within options.max_normal_jump_deg */
  CHECK(info.max_normal_jump_deg <= options.max_normal_jump_deg && info.max_crease_angle_deg == 0.0);
  worst = check_bspline_surfaces(cage, surfaces, &info, &identical);
  CHECK(worst > 0 && worst <= info.max_parametric_error * (1 + 1e-9));
  CHECK(identical == 4 * 6);
  for (k = 0; k < 6; ++k) {
    CHECK_OK(cagekit_limit_surfaces_get_surface(surfaces, k, &d));
    CHECK(d.cage_face == d.ptex_face && d.exact == CAGEKIT_FALSE && d.error <= info.max_error &&
          d.parametric_error <= info.max_parametric_error);
    for (side = 0; side < 4; ++side)
      CHECK(d.sides[side].kind == CAGEKIT_SURFACE_BORDER_SMOOTH && d.sides[side].neighbour_count == 1 &&
            d.sides[side].max_normal_jump_deg <= info.max_normal_jump_deg);
  }
  cagekit_limit_surfaces_release(surfaces);
  surfaces = NULL;
  /* a coarser tolerance needs no more knots */
  options.tolerance = 1e-2;
  CHECK_OK(cagekit_limit_surfaces_create(cage, &options, &surfaces));
  CHECK(limit_surface_info(surfaces).level <= info.level && limit_surface_info(surfaces).max_error_rel <= 1e-2);
  cagekit_limit_surfaces_release(surfaces);
  surfaces = NULL;
  /* every edge creased: the flat faces of the cube, exact, C0 borders at 90 degrees */
  CHECK_OK(cagekit_limit_surfaces_create(creased, NULL, &surfaces));
  info = limit_surface_info(surfaces);
  CHECK(info.exact_count == 6 && info.approximated_count == 0);
  CHECK(fabs(info.max_crease_angle_deg - 90.0) < 1e-9 && info.max_normal_jump_deg == 0.0);
  worst = check_bspline_surfaces(creased, surfaces, &info, &identical);
  CHECK(worst <= 1e-12 * info.bbox_diagonal);
  for (k = 0; k < 6; ++k) {
    CHECK_OK(cagekit_limit_surfaces_get_surface(surfaces, k, &d));
    for (side = 0; side < 4; ++side)
      CHECK(d.sides[side].kind == CAGEKIT_SURFACE_BORDER_CREASE && fabs(d.sides[side].max_normal_jump_deg - 90.0) < 1e-9);
  }
  cagekit_limit_surfaces_release(surfaces);
  cagekit_cage_release(creased);
  cagekit_cage_release(cage);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

/* The two-call getters as two_call_fn over surface 1 of a cube. */
static cagekit_status surface_knots_u(void* surfaces, uint32_t capacity, uint32_t* count_out, void* array) {
  return cagekit_limit_surfaces_get_knots((cagekit_limit_surfaces)surfaces, 1, CAGEKIT_SURFACE_DIRECTION_U, capacity,
                                          count_out, (double*)array);
}
static cagekit_status surface_control_points(void* surfaces, uint32_t capacity, uint32_t* count_out, void* array) {
  return cagekit_limit_surfaces_get_control_points((cagekit_limit_surfaces)surfaces, 1, capacity, count_out,
                                                   (double*)array);
}

static void limit_surfaces_reject_bad_arguments_and_can_be_cancelled(void) {
  cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
  cagekit_context context = new_context(), small = NULL;
  cagekit_mesh mesh = new_cube(context);
  cagekit_cage cage = NULL, small_cage = NULL;
  cagekit_limit_surfaces surfaces = NULL;
  cagekit_limit_surface_options options = CAGEKIT_LIMIT_SURFACE_OPTIONS_INIT;
  cagekit_limit_surface_info info;
  cagekit_limit_surface d;
  cagekit_limit_surface_neighbour nb[4];
  cagekit_surface_direction bad_direction;
  int32_t minus_one = -1;
  uint32_t count = 0;
  double knots[64];
  unsigned char* array;
  CHECK_OK(cagekit_cage_create(mesh, &cage));
  CHECK_OK(cagekit_limit_surfaces_create(cage, NULL, &surfaces));
  info = limit_surface_info(surfaces);
  /* two-call shape of the variable parts */
  CHECK_OK(cagekit_limit_surfaces_get_surface(surfaces, 1, &d));
  array = check_two_call_shape(context, surface_knots_u, surfaces, sizeof(double), "knot", "knots", &count);
  CHECK(count == d.knot_count_u && ((const double*)array)[0] == 0.0);
  free(array);
  array = check_two_call_shape(context, surface_control_points, surfaces, 3 * sizeof(double), "point", "points", &count);
  CHECK(count == d.num_u * d.num_v);
  free(array);
  CHECK_STATUS(cagekit_limit_surfaces_get_neighbours(surfaces, 1, 0, 0, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_OK(cagekit_limit_surfaces_get_neighbours(surfaces, 1, 0, 0, &count, NULL));
  CHECK(count == 1);
  CHECK_STATUS(cagekit_limit_surfaces_get_neighbours(surfaces, 1, 0, 1, &count, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  /* indices, sides and directions out of range */
  CHECK_STATUS(cagekit_limit_surfaces_get_surface(surfaces, info.surface_count, &d), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "out of range") != NULL);
  CHECK_STATUS(cagekit_limit_surfaces_get_surface(surfaces, 0, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_limit_surfaces_get_knots(surfaces, info.surface_count, CAGEKIT_SURFACE_DIRECTION_V, 64, &count,
                                                knots),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  memcpy(&bad_direction, &minus_one, sizeof(bad_direction));
  CHECK_STATUS(cagekit_limit_surfaces_get_knots(surfaces, 0, bad_direction, 64, &count, knots),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_limit_surfaces_get_knots(surfaces, 0, (cagekit_surface_direction)2, 64, &count, knots),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_limit_surfaces_get_control_points(surfaces, info.surface_count, 0, &count, NULL),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_limit_surfaces_get_neighbours(surfaces, 0, 4, 4, &count, nb), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_limit_surfaces_get_neighbours(surfaces, info.surface_count, 0, 4, &count, nb),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  /* handles and info */
  CHECK_STATUS(cagekit_limit_surfaces_get_info(surfaces, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  info.struct_size = 1;
  CHECK_STATUS(cagekit_limit_surfaces_get_info(surfaces, &info), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_limit_surfaces_get_info(NULL, &info), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK_STATUS(cagekit_limit_surfaces_get_surface((cagekit_limit_surfaces)cage, 0, &d), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK_STATUS(cagekit_limit_surfaces_get_knots(NULL, 0, CAGEKIT_SURFACE_DIRECTION_U, 0, &count, NULL),
               CAGEKIT_ERROR_INVALID_HANDLE);
  cagekit_limit_surfaces_retain(surfaces);
  cagekit_limit_surfaces_release(surfaces);
  cagekit_limit_surfaces_retain(NULL);
  cagekit_limit_surfaces_release(NULL);
  CHECK_OK(cagekit_limit_surfaces_get_surface(surfaces, 0, &d)); /* still alive: one reference left */
  cagekit_limit_surfaces_release(surfaces);
  surfaces = NULL;
  /* options */
  CHECK_STATUS(cagekit_limit_surfaces_create(NULL, &options, &surfaces), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK_STATUS(cagekit_limit_surfaces_create(cage, &options, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.struct_size = 1;
  CHECK_STATUS(cagekit_limit_surfaces_create(cage, &options, &surfaces), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "struct_size") != NULL);
  options.struct_size = sizeof(options);
  options.tolerance = 0.0;
  CHECK_STATUS(cagekit_limit_surfaces_create(cage, &options, &surfaces), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_limit_surface_options.tolerance") != NULL);
  options.tolerance = NAN;
  CHECK_STATUS(cagekit_limit_surfaces_create(cage, &options, &surfaces), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.tolerance = 1e-4;
  options.max_level = 8;
  CHECK_STATUS(cagekit_limit_surfaces_create(cage, &options, &surfaces), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "max_level") != NULL);
  options.max_level = 0;
  CHECK_STATUS(cagekit_limit_surfaces_create(cage, &options, &surfaces), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.max_level = 3;
  options.max_normal_jump_deg = 0.0;
  CHECK_STATUS(cagekit_limit_surfaces_create(cage, &options, &surfaces), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "max_normal_jump_deg") != NULL);
  options.max_normal_jump_deg = 0.5;
  options.threads = 1025;
  CHECK_STATUS(cagekit_limit_surfaces_create(cage, &options, &surfaces), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "threads") != NULL);
  options.threads = 0;
  options.min_level = 0;
  CHECK_STATUS(cagekit_limit_surfaces_create(cage, &options, &surfaces), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.min_level = 4;
  CHECK_STATUS(cagekit_limit_surfaces_create(cage, &options, &surfaces), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "min_level") != NULL);
  CHECK(surfaces == NULL);
  /* min_level = max_level fixes the level */
  options.min_level = 3;
  CHECK_OK(cagekit_limit_surfaces_create(cage, &options, &surfaces));
  CHECK(limit_surface_info(surfaces).level == 3);
  CHECK_OK(cagekit_limit_surfaces_get_surface(surfaces, 0, &d));
  CHECK(d.num_u == 8 + 3 && d.num_v == 8 + 3);
  cagekit_limit_surfaces_release(surfaces);
  surfaces = NULL;
  /* cancel through the progress callback */
  g_progress_calls = 0;
  CHECK_OK(cagekit_context_set_progress(context, cancel_after_first, NULL));
  CHECK_STATUS(cagekit_limit_surfaces_create(cage, NULL, &surfaces), CAGEKIT_ERROR_CANCELLED);
  CHECK(surfaces == NULL && g_progress_calls >= 1);
  CHECK_OK(cagekit_context_set_progress(context, NULL, NULL));
  /* the context's memory budget: 128^2 control points on each of 6 faces do not fit in 1 MiB */
  desc.memory_budget_bytes = 1u << 20;
  CHECK_OK(cagekit_context_create(&desc, &small));
  small_cage = new_creased_cube(small);
  options.min_level = options.max_level = 7;
  CHECK_STATUS(cagekit_limit_surfaces_create(small_cage, &options, &surfaces), CAGEKIT_ERROR_OUT_OF_MEMORY);
  CHECK(surfaces == NULL && strstr(cagekit_last_error_message(small), "memory budget") != NULL);
  cagekit_cage_release(small_cage);
  cagekit_context_release(small);
  cagekit_cage_release(cage);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

static void last_error_is_per_thread(void) {
  pthread_t thread;
  int thread_ok = 0;
  cagekit_mesh mesh = NULL;
  g_shared_context = new_context();
  CHECK_STATUS(cagekit_mesh_read_file(g_shared_context, "/nonexistent.obj", CAGEKIT_FORMAT_AUTO, &mesh),
               CAGEKIT_ERROR_IO);
  CHECK(pthread_create(&thread, NULL, fail_on_thread, &thread_ok) == 0);
  CHECK(pthread_join(thread, NULL) == 0);
  CHECK(thread_ok);
  CHECK(strstr(cagekit_last_error_message(g_shared_context), "nonexistent") != NULL);
  cagekit_context_release(g_shared_context);
}

static void objects_outlive_their_context_reference(void) {
  cagekit_context context = new_context();
  cagekit_mesh mesh = new_cube(context);
  uint32_t vertices = 0;
  cagekit_context_release(context); /* the mesh keeps the context alive */
  CHECK_OK(cagekit_mesh_get_counts(mesh, &vertices, NULL, NULL));
  CHECK(vertices == 8);
  cagekit_mesh_retain(mesh);
  cagekit_mesh_release(mesh);
  CHECK_OK(cagekit_mesh_get_counts(mesh, &vertices, NULL, NULL));
  cagekit_mesh_release(mesh);
  cagekit_mesh_release(NULL);
}

static void simplification_hierarchy_browses_levels_and_builds_a_cage(void) {
  cagekit_context context = new_context();
  /* the unit cube, each side split into two triangles */
  static const uint32_t triangles[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                         2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  cagekit_mesh mesh = NULL, level_mesh = NULL;
  cagekit_hierarchy hierarchy = NULL;
  cagekit_cage cage = NULL;
  cagekit_level_info info;
  cagekit_polygonal_level_info current;
  cagekit_cage_report report;
  cagekit_approximation_error error;
  uint32_t levels = 0, level = 0, faces = 0, loops = 0, clusters[12], count = 0, i, six = 0;
  uint64_t indices = 0;
  uint32_t loops_per_face[12], loop_sizes[24], loop_vertices[64];
  desc.vertex_count = 8;
  desc.positions = kCubeD;
  desc.face_count = 12;
  desc.face_indices = triangles;
  CHECK_OK(cagekit_mesh_create(context, &desc, &mesh));
  CHECK_OK(cagekit_hierarchy_create(mesh, NULL, &hierarchy));
  CHECK_OK(cagekit_hierarchy_get_level_count(hierarchy, &levels));
  CHECK(levels >= 7); /* at least the six coplanar pair merges */
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_hierarchy_get_level_info(hierarchy, 0, &info));
  CHECK(info.faces == 12 && info.vertices == 8);
  CHECK_OK(cagekit_hierarchy_get_level_info(hierarchy, levels - 1, &info));
  CHECK(info.faces <= 6);
  CHECK_STATUS(cagekit_hierarchy_get_level_info(hierarchy, levels, &info), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_OK(cagekit_hierarchy_get_current_level(hierarchy, &level));
  CHECK(level == levels - 1);

  /* the level with the six sides: merging coplanar triangles is free, so it comes first */
  CHECK_OK(cagekit_hierarchy_find_level(hierarchy, CAGEKIT_LEVEL_BY_FACES, 6, &level));
  CHECK_OK(cagekit_hierarchy_set_level(hierarchy, level));
  current.struct_size = sizeof(current);
  CHECK_OK(cagekit_hierarchy_get_current_info(hierarchy, &current));
  CHECK(current.faces == 6 && current.vertices == 8 && current.invalid_faces == 0 && current.faces_with_holes == 0);
  CHECK_OK(cagekit_hierarchy_get_faces(hierarchy, 0, &faces, NULL, 0, &loops, NULL, 0, &indices, NULL));
  CHECK(faces == 6 && loops == 6 && indices == 24);
  CHECK_OK(cagekit_hierarchy_get_faces(hierarchy, 12, &faces, loops_per_face, 24, &loops, loop_sizes, 64, &indices,
                                       loop_vertices));
  for (i = 0; i < 6; ++i) six += loops_per_face[i] == 1 && loop_sizes[i] == 4;
  CHECK(six == 6);
  CHECK_OK(cagekit_hierarchy_get_clusters(hierarchy, 12, &count, clusters));
  CHECK(count == 12);
  for (i = 0; i < 12; ++i) CHECK(clusters[i] < 6);
  for (i = 0; i < 12; i += 2) CHECK(clusters[i] == clusters[i + 1]); /* the two triangles of a side */

  report.struct_size = sizeof(report);
  CHECK_OK(cagekit_hierarchy_build_cage(hierarchy, NULL, &cage, &report));
  CHECK(report.quads == 6 && report.triangles == 0 && report.creases == 12);
  CHECK(report.diagonals_flipped == 0 && report.cells_merged == 0);
  {
    /* the default rule (creases where the input is sharp): the cube's 90-degree edges are
       sharp input features at a feature angle of 85 degrees, not at 95 */
    cagekit_cage_options cage_options = CAGEKIT_CAGE_OPTIONS_INIT;
    cagekit_cage other = NULL;
    CHECK(cage_options.crease_rule == CAGEKIT_CREASES_SHARP_INPUT && cage_options.feature_angle_degrees == 40.0);
    cage_options.feature_angle_degrees = 85.0;
    CHECK_OK(cagekit_hierarchy_build_cage(hierarchy, &cage_options, &other, &report));
    CHECK(report.creases == 12);
    cagekit_cage_release(other);
    cage_options.feature_angle_degrees = 95.0;
    CHECK_OK(cagekit_hierarchy_build_cage(hierarchy, &cage_options, &other, &report));
    CHECK(report.creases == 0);
    cagekit_cage_release(other);
    cage_options.feature_angle_degrees = 200.0;
    CHECK_STATUS(cagekit_hierarchy_build_cage(hierarchy, &cage_options, &other, &report),
                 CAGEKIT_ERROR_INVALID_ARGUMENT);
    cage_options.feature_angle_degrees = 40.0;
    cage_options.crease_rule = (cagekit_crease_rule)7;
    CHECK_STATUS(cagekit_hierarchy_build_cage(hierarchy, &cage_options, &other, &report),
                 CAGEKIT_ERROR_INVALID_ARGUMENT);
    /* the thesis's rule with the input check: the cube's sides meet at 90 degrees in the input
       too: kept at 85, dropped at 95 */
    cage_options.crease_rule = CAGEKIT_CREASES_CLUSTER_ANGLE;
    cage_options.input_crease_angle_degrees = 85.0;
    CHECK_OK(cagekit_hierarchy_build_cage(hierarchy, &cage_options, &other, &report));
    CHECK(report.creases == 12);
    cagekit_cage_release(other);
    cage_options.input_crease_angle_degrees = 95.0;
    CHECK_OK(cagekit_hierarchy_build_cage(hierarchy, &cage_options, &other, &report));
    CHECK(report.creases == 0);
    cagekit_cage_release(other);
    cage_options.input_crease_angle_degrees = NAN;
    CHECK_STATUS(cagekit_hierarchy_build_cage(hierarchy, &cage_options, &other, &report),
                 CAGEKIT_ERROR_INVALID_ARGUMENT);
  }
  CHECK_OK(cagekit_hierarchy_get_polygon_mesh(hierarchy, &level_mesh));
  error.struct_size = sizeof(error);
  CHECK_OK(cagekit_mesh_measure_error(mesh, level_mesh, &error));
  CHECK(error.hausdorff_rel < 1e-12 && error.hausdorff_sym_rel < 1e-12);
  /* the cube's borders are straight: refined contours add nothing; a bad tolerance is refused */
  {
    cagekit_mesh refined = NULL;
    uint32_t refined_vertices = 0, refined_faces = 0;
    CHECK_OK(cagekit_hierarchy_get_refined_polygon_mesh(hierarchy, 0.01, &refined));
    CHECK_OK(cagekit_mesh_get_counts(refined, &refined_vertices, &refined_faces, NULL));
    CHECK(refined_vertices == 8 && refined_faces == 6);
    cagekit_mesh_release(refined);
    refined = (cagekit_mesh)1;
    CHECK_STATUS(cagekit_hierarchy_get_refined_polygon_mesh(hierarchy, 0.0, &refined), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK(refined == NULL);
    CHECK_STATUS(cagekit_hierarchy_get_refined_polygon_mesh(hierarchy, NAN, &refined), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK_STATUS(cagekit_hierarchy_get_refined_polygon_mesh(hierarchy, 0.01, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  }

  /* a cancelling progress callback stops the simplification with no handle made */
  {
    cagekit_hierarchy cancelled = (cagekit_hierarchy)1;
    CHECK_OK(cagekit_context_set_progress(context, cancel_after_first, NULL));
    CHECK_STATUS(cagekit_hierarchy_create(mesh, NULL, &cancelled), CAGEKIT_ERROR_CANCELLED);
    CHECK(cancelled == NULL);
    CHECK_OK(cagekit_context_set_progress(context, NULL, NULL));
  }

  /* level 0 is the input again */
  CHECK_OK(cagekit_hierarchy_set_level(hierarchy, 0));
  CHECK_OK(cagekit_hierarchy_get_current_info(hierarchy, &current));
  CHECK(current.faces == 12);
  CHECK_STATUS(cagekit_hierarchy_set_level(hierarchy, levels), CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_mesh_release(level_mesh);
  cagekit_cage_release(cage);
  cagekit_hierarchy_release(hierarchy);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

/* --- fitting (thesis ch. 7) --- */

/* A lat-long sphere of radius 0.75 around the unit cube's centre: 2 poles + 11 rings of 24. */
#define SPHERE_RINGS 12
#define SPHERE_SEGMENTS 24
#define SPHERE_VERTICES (2 + (SPHERE_RINGS - 1) * SPHERE_SEGMENTS)
#define SPHERE_TRIANGLES (2 * SPHERE_SEGMENTS * (SPHERE_RINGS - 1))
static cagekit_mesh new_sphere(cagekit_context context) {
  static double positions[3 * SPHERE_VERTICES];
  static uint32_t triangles[3 * SPHERE_TRIANGLES];
  const double pi = 3.14159265358979323846;
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  cagekit_mesh mesh = NULL;
  uint32_t r, k, v = 0, t = 0;
  positions[0] = 0.5, positions[1] = 0.5, positions[2] = 0.5 + 0.75;
  v = 1;
  for (r = 1; r < SPHERE_RINGS; ++r)
    for (k = 0; k < SPHERE_SEGMENTS; ++k, ++v) {
      const double theta = pi * r / SPHERE_RINGS, phi = 2 * pi * k / SPHERE_SEGMENTS;
      positions[3 * v] = 0.5 + 0.75 * sin(theta) * cos(phi);
      positions[3 * v + 1] = 0.5 + 0.75 * sin(theta) * sin(phi);
      positions[3 * v + 2] = 0.5 + 0.75 * cos(theta);
    }
  positions[3 * v] = 0.5, positions[3 * v + 1] = 0.5, positions[3 * v + 2] = 0.5 - 0.75;
  for (k = 0; k < SPHERE_SEGMENTS; ++k) { /* north cap */
    const uint32_t k1 = (k + 1) % SPHERE_SEGMENTS;
    triangles[t++] = 0, triangles[t++] = 1 + k, triangles[t++] = 1 + k1;
  }
  for (r = 1; r + 1 < SPHERE_RINGS; ++r)
    for (k = 0; k < SPHERE_SEGMENTS; ++k) {
      const uint32_t k1 = (k + 1) % SPHERE_SEGMENTS;
      const uint32_t a = 1 + (r - 1) * SPHERE_SEGMENTS + k, b = 1 + (r - 1) * SPHERE_SEGMENTS + k1;
      const uint32_t c = a + SPHERE_SEGMENTS, d = b + SPHERE_SEGMENTS;
      triangles[t++] = a, triangles[t++] = c, triangles[t++] = d;
      triangles[t++] = a, triangles[t++] = d, triangles[t++] = b;
    }
  for (k = 0; k < SPHERE_SEGMENTS; ++k) { /* south cap */
    const uint32_t k1 = (k + 1) % SPHERE_SEGMENTS, base = 1 + (SPHERE_RINGS - 2) * SPHERE_SEGMENTS;
    triangles[t++] = v, triangles[t++] = base + k1, triangles[t++] = base + k;
  }
  desc.vertex_count = SPHERE_VERTICES;
  desc.positions = positions;
  desc.face_count = SPHERE_TRIANGLES;
  desc.face_indices = triangles;
  CHECK(t == 3 * SPHERE_TRIANGLES);
  CHECK_OK(cagekit_mesh_create(context, &desc, &mesh));
  CHECK_OK(cagekit_mesh_validate(mesh, NULL));
  return mesh;
}

static void out_of_range_enum_values_are_rejected(void) {
  /* Values outside every enum's range (-1, 99) must give INVALID_ARGUMENT, never undefined
   * behaviour inside the library (run under UBSan in CI). */
  static const int32_t bad[2] = {-1, 99};
  cagekit_context context = new_context();
  cagekit_context other = NULL;
  cagekit_cage cage = new_creased_cube(context);
  cagekit_mesh mesh = new_cube(context), made = NULL;
  cagekit_cage read = NULL;
  cagekit_hierarchy hierarchy = NULL;
  double positions[24];
  uint32_t level = 0, count = 0;
  int i;
  static const char kObj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  static const uint32_t tri[3] = {0, 1, 2};
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
  desc.vertex_count = 3;
  desc.positions = kCubeD;
  desc.face_count = 1;
  desc.uniform_face_size = 3;
  desc.face_indices = tri;
  CHECK_OK(cagekit_mesh_create(context, &desc, &made));
  CHECK_OK(cagekit_hierarchy_create(made, NULL, &hierarchy));
  cagekit_mesh_release(made);
  made = NULL;
  for (i = 0; i < 2; ++i) {
    cagekit_context_desc cdesc = CAGEKIT_CONTEXT_DESC_INIT;
    cagekit_mesh_desc mdesc = desc;
    memcpy(&cdesc.log_level, &bad[i], sizeof(bad[i]));
    CHECK_STATUS(cagekit_context_create(&cdesc, &other), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK(other == NULL);
    memcpy(&mdesc.position_type, &bad[i], sizeof(bad[i]));
    CHECK_STATUS(cagekit_mesh_create(context, &mdesc, &made), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK(made == NULL);
    CHECK_STATUS(cagekit_cage_set_boundary_rule(cage, (cagekit_boundary_rule)bad[i]), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK_STATUS(cagekit_mesh_get_positions(mesh, (cagekit_scalar_type)bad[i], 8, &count, positions),
                 CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK_STATUS(cagekit_cage_read_memory(context, kObj, sizeof(kObj) - 1, (cagekit_file_format)bad[i], &read),
                 CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK(read == NULL);
    CHECK_STATUS(cagekit_hierarchy_find_level(hierarchy, (cagekit_level_query)bad[i], 1.0, &level),
                 CAGEKIT_ERROR_INVALID_ARGUMENT);
  }
  cagekit_hierarchy_release(hierarchy);
  cagekit_mesh_release(mesh);
  cagekit_cage_release(cage);
  cagekit_context_release(context);
}

static void memory_budget_fails_cleanly_before_allocating(void) {
  /* A 1 MiB budget: small work goes through, big work fails with OUT_OF_MEMORY and a message
   * that names the budget; the same calls succeed in a context without a budget. */
  cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
  cagekit_context small = NULL, unlimited = NULL;
  cagekit_cage cage = NULL, refined = NULL, read = NULL;
  cagekit_mesh mesh = NULL, huge = NULL;
  cagekit_subdivide_options sub = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  cagekit_mesh_desc mdesc = CAGEKIT_MESH_DESC_INIT;
  static char obj[3 * 1024 * 1024];
  size_t length = 0;
  uint32_t i;
  desc.memory_budget_bytes = 1u << 20;
  CHECK_OK(cagekit_context_create(&desc, &small));
  unlimited = new_context();
  cage = new_creased_cube(small);
  sub.levels = 2; /* 384 face-vertices: fine */
  CHECK_OK(cagekit_cage_subdivide(cage, &sub, &refined));
  cagekit_cage_release(refined);
  refined = NULL;
  sub.levels = 7; /* 393K face-vertices: tens of MiB */
  CHECK_STATUS(cagekit_cage_subdivide(cage, &sub, &refined), CAGEKIT_ERROR_OUT_OF_MEMORY);
  CHECK(refined == NULL);
  CHECK(strstr(cagekit_last_error_message(small), "memory budget") != NULL);
  cagekit_cage_release(cage);
  /* A 3 MiB OBJ text: refused by the budget, read without it. */
  for (i = 0; length + 64 < sizeof(obj) && i < 200000; ++i)
    length += (size_t)sprintf(obj + length, "v %u %u 0\n", i, (i * i) % 13u);
  length += (size_t)sprintf(obj + length, "f 1 2 3\n");
  CHECK_STATUS(cagekit_cage_read_memory(small, obj, length, CAGEKIT_FORMAT_OBJ, &read), CAGEKIT_ERROR_OUT_OF_MEMORY);
  CHECK(read == NULL);
  CHECK_OK(cagekit_cage_read_memory(unlimited, obj, length, CAGEKIT_FORMAT_OBJ, &read));
  cagekit_cage_release(read);
  /* Claimed counts far beyond the budget fail before the buffers are read. */
  mdesc.vertex_count = 100000000u;
  mdesc.positions = kCubeD;
  mdesc.face_count = 1;
  mdesc.uniform_face_size = 3;
  mdesc.face_indices = kCubeQuads;
  CHECK_STATUS(cagekit_mesh_create(small, &mdesc, &huge), CAGEKIT_ERROR_OUT_OF_MEMORY);
  CHECK(huge == NULL);
  mesh = new_cube(small); /* small meshes are fine */
  CHECK(mesh != NULL);
  cagekit_mesh_release(mesh);
  cagekit_context_release(small);
  cagekit_context_release(unlimited);
}

/* A sphere scan bound to the cube cage fitted to it (the deformer tests' setup). */
typedef struct bound_sphere {
  cagekit_context context;
  cagekit_mesh cube_mesh, sphere;
  cagekit_cage cube, fitted;
  cagekit_binding binding;
} bound_sphere;

static bound_sphere bind_fitted_sphere(const cagekit_bind_options* options) {
  bound_sphere b;
  b.context = new_context();
  b.cube_mesh = new_cube(b.context);
  b.sphere = new_sphere(b.context);
  b.cube = b.fitted = NULL;
  b.binding = NULL;
  CHECK_OK(cagekit_cage_create(b.cube_mesh, &b.cube));
  CHECK_OK(fit_without_passes(b.cube, b.sphere, NULL, &b.fitted, NULL));
  CHECK_OK(cagekit_multires_bind(b.fitted, b.sphere, options, &b.binding));
  return b;
}

static void release_bound_sphere(bound_sphere* b) {
  cagekit_binding_release(b->binding);
  cagekit_cage_release(b->fitted);
  cagekit_cage_release(b->cube);
  cagekit_mesh_release(b->sphere);
  cagekit_mesh_release(b->cube_mesh);
  cagekit_context_release(b->context);
}

/* cagekit_cpu_deformer_deform_f32 / _update_f32: every float written is the double call's value
 * rounded to float (compact path: approximate normals; sparse-row path: exact normals), and the
 * same bad input is refused. */
static void binding_deformer_vertex_order_is_a_permutation(void) {
  bound_sphere b = bind_fitted_sphere(NULL);
  cagekit_binding binding = b.binding;
  cagekit_binding_info info;
  uint32_t order[300], seen[300], count = 0, i, sequential = 0;
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_binding_get_info(binding, &info));
  /* Two calls: the count, then the order. */
  CHECK_OK(cagekit_binding_get_deformer_vertex_order(binding, 0, &count, NULL));
  CHECK(count == info.scan_vertex_count && count <= 300);
  CHECK_STATUS(cagekit_binding_get_deformer_vertex_order(binding, 2, &count, order), CAGEKIT_ERROR_SIZE_INSUFFICIENT);
  CHECK_OK(cagekit_binding_get_deformer_vertex_order(binding, 300, &count, order));
  memset(seen, 0, sizeof seen);
  for (i = 0; i < count; ++i) {
    CHECK(order[i] < count);
    if (order[i] < count) seen[order[i]] += 1;
    sequential += i > 0 && order[i] == order[i - 1] + 1;
  }
  for (i = 0; i < count; ++i) CHECK(seen[i] == 1);
  CHECK(sequential < count - 1); /* the sphere's own order is not the deformer's */
  CHECK_STATUS(cagekit_binding_get_deformer_vertex_order(binding, 300, NULL, order), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_binding_get_deformer_vertex_order(NULL, 300, &count, order), CAGEKIT_ERROR_INVALID_HANDLE);
  release_bound_sphere(&b);
}

static void cpu_deformer_float32_outputs_match_double(void) {
  bound_sphere b;
  cagekit_cage fitted = NULL;
  cagekit_binding binding = NULL;
  cagekit_cpu_deformer d64 = NULL, d32 = NULL, fresh = NULL;
  cagekit_bind_options options = CAGEKIT_BIND_OPTIONS_INIT;
  cagekit_binding_info info;
  double control[24], positions[3 * 300], normals[3 * 300];
  float positions32[3 * 300], normals32[3 * 300];
  uint32_t i, updated64 = 0, updated32 = 0, moved[2] = {2, 5}, mismatches = 0, written = 0;
  int pass;
  options.exact_normals = 1;
  b = bind_fitted_sphere(&options);
  fitted = b.fitted;
  binding = b.binding;
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_binding_get_info(binding, &info));
  CHECK(info.vertex_count > 200 && info.vertex_count <= 300 && info.compact_cells > 0);
  {
    cagekit_mesh fitted_mesh = NULL;
    CHECK_OK(cagekit_cage_get_mesh(fitted, &fitted_mesh));
    CHECK_OK(cagekit_mesh_get_positions(fitted_mesh, CAGEKIT_SCALAR_FLOAT64, 8, &written, control));
    cagekit_mesh_release(fitted_mesh);
  }
  CHECK_OK(cagekit_cpu_deformer_create(binding, 2, &d64));
  CHECK_OK(cagekit_cpu_deformer_create(binding, 2, &d32));
  for (pass = 0; pass < 2; ++pass) {
    const cagekit_normal_mode mode = pass == 0 ? CAGEKIT_NORMALS_APPROXIMATE : CAGEKIT_NORMALS_EXACT;
    control[3 * 4 + 1] += 0.07;
    CHECK_OK(cagekit_cpu_deformer_deform(d64, control, 8, mode, 300, &written, positions, normals));
    CHECK_OK(cagekit_cpu_deformer_deform_f32(d32, control, 8, mode, 300, &written, positions32, normals32));
    for (i = 0; i < 3 * info.vertex_count; ++i)
      mismatches += positions32[i] != (float)positions[i] || normals32[i] != (float)normals[i];
    /* Incremental: the support of the moved points, the rest left as it was. */
    control[3 * 2 + 0] -= 0.05;
    control[3 * 5 + 2] += 0.04;
    CHECK_OK(cagekit_cpu_deformer_update(d64, control, 8, moved, 2, mode, 300, &written, positions, normals,
                                         &updated64));
    CHECK_OK(cagekit_cpu_deformer_update_f32(d32, control, 8, moved, 2, mode, 300, &written, positions32, normals32,
                                             &updated32));
    CHECK(updated32 == updated64 && updated32 > 0);
    for (i = 0; i < 3 * info.vertex_count; ++i)
      mismatches += positions32[i] != (float)positions[i] || normals32[i] != (float)normals[i];
  }
  CHECK(mismatches == 0);
  /* The two-call shape over the bound vertices: the count always, capacity 0 a query that deforms
     nothing (the arrays keep the last deform's values), a short capacity SIZE_INSUFFICIENT. */
  CHECK(written == info.vertex_count);
  written = 0;
  control[0] += 0.5;
  CHECK_OK(cagekit_cpu_deformer_deform_f32(d32, control, 8, CAGEKIT_NORMALS_APPROXIMATE, 0, &written, positions32,
                                           normals32));
  CHECK(written == info.vertex_count);
  for (i = 0; i < 3 * info.vertex_count; ++i) mismatches += positions32[i] != (float)positions[i];
  CHECK(mismatches == 0);
  control[0] -= 0.5;
  CHECK_STATUS(cagekit_cpu_deformer_deform_f32(d32, control, 8, CAGEKIT_NORMALS_APPROXIMATE, 300, NULL, positions32,
                                               NULL),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(b.context), "vertex_count_out") != NULL);
  written = 0;
  CHECK_STATUS(cagekit_cpu_deformer_update(d64, control, 8, moved, 2, CAGEKIT_NORMALS_EXACT, 10, &written, positions,
                                           normals, NULL),
               CAGEKIT_ERROR_SIZE_INSUFFICIENT);
  CHECK(written == info.vertex_count);
  /* Positions only, normals only. */
  CHECK_OK(cagekit_cpu_deformer_deform_f32(d32, control, 8, CAGEKIT_NORMALS_APPROXIMATE, 300, &written,
                                           positions32, NULL));
  CHECK_OK(cagekit_cpu_deformer_deform_f32(d32, control, 8, CAGEKIT_NORMALS_APPROXIMATE, 300, &written,
                                           NULL, normals32));
  /* Bad input. */
  CHECK_STATUS(cagekit_cpu_deformer_deform_f32(d32, control, 7, CAGEKIT_NORMALS_APPROXIMATE, 300, &written,
                                               positions32, NULL),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_cpu_deformer_deform_f32(d32, NULL, 8, CAGEKIT_NORMALS_APPROXIMATE, 300, &written,
                                               positions32, NULL),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_cpu_deformer_deform_f32(d32, control, 8, CAGEKIT_NORMALS_APPROXIMATE, 10, &written,
                                               positions32, NULL),
               CAGEKIT_ERROR_SIZE_INSUFFICIENT);
  CHECK_STATUS(cagekit_cpu_deformer_deform_f32(d32, control, 8, (cagekit_normal_mode)9, 300, &written,
                                               positions32, NULL),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_cpu_deformer_deform_f32((cagekit_cpu_deformer)binding, control, 8, CAGEKIT_NORMALS_APPROXIMATE,
                                               300, &written, positions32, NULL),
               CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK_OK(cagekit_cpu_deformer_create(binding, 1, &fresh));
  CHECK_STATUS(cagekit_cpu_deformer_update_f32(fresh, control, 8, moved, 2, CAGEKIT_NORMALS_APPROXIMATE, 300, &written,
                                               positions32, normals32, NULL),
               CAGEKIT_ERROR_INVALID_OPERATION); /* before a first deform */
  CHECK_OK(cagekit_cpu_deformer_deform_f32(fresh, control, 8, CAGEKIT_NORMALS_APPROXIMATE, 300, &written,
                                           positions32, normals32));
  moved[0] = 8;
  CHECK_STATUS(cagekit_cpu_deformer_update_f32(fresh, control, 8, moved, 1, CAGEKIT_NORMALS_APPROXIMATE, 300, &written,
                                               positions32, normals32, NULL),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_cpu_deformer_update_f32(fresh, control, 8, NULL, 1, CAGEKIT_NORMALS_APPROXIMATE, 300, &written,
                                               positions32, normals32, NULL),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_cpu_deformer_release(fresh);
  cagekit_cpu_deformer_release(d32);
  cagekit_cpu_deformer_release(d64);
  release_bound_sphere(&b);
}

static void multires_binding_reproduces_and_deforms_the_scan(void) {
  cagekit_context context = new_context();
  cagekit_mesh cube_mesh = new_cube(context), sphere = new_sphere(context);
  cagekit_cage cube = NULL, fitted = NULL;
  cagekit_binding binding = NULL;
  cagekit_cpu_deformer full = NULL, incremental = NULL;
  cagekit_bind_options options = CAGEKIT_BIND_OPTIONS_INIT;
  cagekit_binding_info info;
  double control[24], scan[3 * 300], positions[3 * 300], normals[3 * 300], positions2[3 * 300], normals2[3 * 300];
  uint32_t count = 0, i, updated = 0, moved[2] = {1, 6}, written = 0;
  double worst = 0, diff = 0;
  CHECK_OK(cagekit_cage_create(cube_mesh, &cube));
  CHECK_OK(fit_without_passes(cube, sphere, NULL, &fitted, NULL));
  options.mode = CAGEKIT_DISPLACEMENT_LOCAL_FRAME;
  options.exact_normals = 1;
  CHECK_OK(cagekit_multires_bind(fitted, sphere, &options, &binding));
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_binding_get_info(binding, &info));
  CHECK(info.control_count == 8 && info.vertex_count > 200 && info.vertex_count <= 300);
  CHECK(info.basis_entries >= info.vertex_count && info.has_exact_normals == 1);
  CHECK_OK(cagekit_mesh_get_positions(sphere, CAGEKIT_SCALAR_FLOAT64, 300, &count, scan));
  {
    cagekit_mesh fitted_mesh = NULL;
    CHECK_OK(cagekit_cage_get_mesh(fitted, &fitted_mesh));
    CHECK_OK(cagekit_mesh_get_positions(fitted_mesh, CAGEKIT_SCALAR_FLOAT64, 8, &written, control));
    cagekit_mesh_release(fitted_mesh);
  }
  CHECK_OK(cagekit_cpu_deformer_create(binding, 0, &full));
  CHECK_OK(cagekit_cpu_deformer_create(binding, 1, &incremental));
  /* Undeformed: the scan comes back (local-frame mode is exact). */
  CHECK_OK(cagekit_cpu_deformer_deform(full, control, 8, CAGEKIT_NORMALS_EXACT, 300, &written, positions, normals));
  for (i = 0; i < 3 * count; ++i) worst = fabs(positions[i] - scan[i]) > worst ? fabs(positions[i] - scan[i]) : worst;
  CHECK(worst < 1e-9);
  for (i = 0; i < count; ++i) {
    const double* n = normals + 3 * i;
    CHECK(fabs(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] - 1.0) < 1e-9);
  }
  /* Incremental equals full. */
  CHECK_OK(cagekit_cpu_deformer_deform(incremental, control, 8, CAGEKIT_NORMALS_EXACT, 300, &written,
                                       positions2, normals2));
  control[3 * 1 + 0] += 0.1;
  control[3 * 6 + 2] -= 0.05;
  CHECK_OK(cagekit_cpu_deformer_update(incremental, control, 8, moved, 2, CAGEKIT_NORMALS_EXACT, 300, &written,
                                       positions2, normals2, &updated));
  CHECK(updated > 0 && updated <= count);
  CHECK_OK(cagekit_cpu_deformer_deform(full, control, 8, CAGEKIT_NORMALS_EXACT, 300, &written, positions, normals));
  for (i = 0; i < 3 * count; ++i) {
    diff = fabs(positions[i] - positions2[i]) > diff ? fabs(positions[i] - positions2[i]) : diff;
    diff = fabs(normals[i] - normals2[i]) > diff ? fabs(normals[i] - normals2[i]) : diff;
  }
  CHECK(diff < 1e-12);
  /* Bad input. */
  CHECK_STATUS(cagekit_cpu_deformer_deform(full, control, 7, CAGEKIT_NORMALS_EXACT, 300, &written, positions, normals),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_cpu_deformer_deform(full, control, 8, CAGEKIT_NORMALS_EXACT, 10, &written, positions, normals),
               CAGEKIT_ERROR_SIZE_INSUFFICIENT);
  CHECK_STATUS(cagekit_cpu_deformer_deform(full, NULL, 8, CAGEKIT_NORMALS_EXACT, 300, &written, positions, normals),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_cpu_deformer_deform(full, control, 8, (cagekit_normal_mode)7, 300, &written, positions, normals),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  moved[0] = 99;
  CHECK_STATUS(cagekit_cpu_deformer_update(incremental, control, 8, moved, 1, CAGEKIT_NORMALS_EXACT, 300, &written,
                                           positions2, normals2, NULL),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_cpu_deformer_update(incremental, control, 8, moved, 0, CAGEKIT_NORMALS_APPROXIMATE, 300,
                                           &written, positions2, normals2, NULL),
               CAGEKIT_ERROR_INVALID_OPERATION); /* mode differs from the last deform's */
  control[0] = NAN;
  CHECK_STATUS(cagekit_cpu_deformer_deform(full, control, 8, CAGEKIT_NORMALS_EXACT, 300, &written, positions, normals),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  {
    cagekit_cpu_deformer none = NULL;
    CHECK_STATUS(cagekit_cpu_deformer_create((cagekit_binding)sphere, 0, &none), CAGEKIT_ERROR_INVALID_HANDLE);
    CHECK(none == NULL);
  }
  options.mode = (cagekit_displacement_mode)5;
  {
    cagekit_binding none = NULL;
    CHECK_STATUS(cagekit_multires_bind(fitted, sphere, &options, &none), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK(none == NULL);
  }
  /* The deformers keep the binding alive after the host released it. */
  cagekit_binding_release(binding);
  control[0] = 0.0;
  CHECK_OK(cagekit_cpu_deformer_deform(incremental, control, 8, CAGEKIT_NORMALS_EXACT, 300, &written,
                                       positions2, NULL));
  cagekit_cpu_deformer_release(full);
  cagekit_cpu_deformer_release(incremental);
  cagekit_cage_release(fitted);
  cagekit_cage_release(cube);
  cagekit_mesh_release(sphere);
  cagekit_mesh_release(cube_mesh);
  cagekit_context_release(context);
}

static void sector_split_duplicates_sharp_vertices(void) {
  cagekit_context context = new_context();
  cagekit_mesh cube_mesh = new_cube(context);
  cagekit_cage cube = NULL;
  cagekit_binding binding = NULL, none = NULL;
  cagekit_bind_options options = CAGEKIT_BIND_OPTIONS_INIT;
  cagekit_binding_info info;
  uint32_t sources[64], sizes[16], indices[64], n = 0, faces = 0, i;
  uint64_t index_count = 0;
  CHECK(options.sharp_angle_degrees < 0); /* off by default */
  CHECK_OK(cagekit_cage_create(cube_mesh, &cube));
  options.sharp_angle_degrees = 45.0;
  CHECK_OK(cagekit_multires_bind(cube, cube_mesh, &options, &binding));
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_binding_get_info(binding, &info));
  /* Every cube corner lies on three sharp edges: one bound vertex per adjacent face. */
  CHECK(info.has_sector_split == 1 && info.scan_vertex_count == 8 && info.vertex_count == 24);
  CHECK_OK(cagekit_binding_get_vertex_sources(binding, 64, &n, sources));
  CHECK(n == 24);
  for (i = 0; i < 8; ++i) CHECK(sources[i] == i);
  for (i = 8; i < 24; ++i) CHECK(sources[i] < 8);
  CHECK_OK(cagekit_binding_get_faces(binding, 16, &faces, sizes, 64, &index_count, indices));
  CHECK(faces == 6 && index_count == 24);
  for (i = 0; i < 24; ++i) CHECK(indices[i] < 24);
  options.sharp_angle_degrees = 181.0;
  CHECK_STATUS(cagekit_multires_bind(cube, cube_mesh, &options, &none), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.sharp_angle_degrees = NAN;
  CHECK_STATUS(cagekit_multires_bind(cube, cube_mesh, &options, &none), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(none == NULL);
  cagekit_binding_release(binding);
  cagekit_cage_release(cube);
  cagekit_mesh_release(cube_mesh);
  cagekit_context_release(context);
}

static void saved_binding_round_trips_and_bad_bytes_fail(void) {
  cagekit_context context = new_context();
  cagekit_mesh cube_mesh = new_cube(context), sphere = new_sphere(context), cage_mesh = NULL;
  cagekit_cage cube = NULL, fitted = NULL, saved_cage = NULL;
  cagekit_binding binding = NULL, loaded = NULL, none = NULL;
  cagekit_cpu_deformer d0 = NULL, d1 = NULL;
  cagekit_blob blob = NULL, again = NULL;
  cagekit_binding_info a, b;
  double control[24], p0[3 * 300], p1[3 * 300];
  unsigned char bad[64];
  uint32_t i, written = 0;
  CHECK_OK(cagekit_cage_create(cube_mesh, &cube));
  CHECK_OK(fit_without_passes(cube, sphere, NULL, &fitted, NULL));
  CHECK_OK(cagekit_multires_bind(fitted, sphere, NULL, &binding));
  CHECK_OK(cagekit_binding_write_memory(binding, &blob));
  CHECK(cagekit_blob_size(blob) > 100);
  CHECK_OK(cagekit_binding_read_memory(context, cagekit_blob_data(blob), cagekit_blob_size(blob), 1, &loaded));
  a.struct_size = b.struct_size = sizeof(a);
  CHECK_OK(cagekit_binding_get_info(binding, &a));
  CHECK_OK(cagekit_binding_get_info(loaded, &b));
  CHECK(a.vertex_count == b.vertex_count && a.control_count == b.control_count && a.basis_entries == b.basis_entries &&
        a.bbox_diagonal == b.bbox_diagonal && a.max_sideways_residual == b.max_sideways_residual);
  /* The saved cage is the fitted one; both bindings deform alike, and re-saving gives the same bytes. */
  CHECK_OK(cagekit_binding_get_cage(loaded, &saved_cage));
  CHECK_OK(cagekit_cage_get_mesh(saved_cage, &cage_mesh));
  CHECK_OK(cagekit_mesh_get_positions(cage_mesh, CAGEKIT_SCALAR_FLOAT64, 8, &written, control));
  control[0] += 0.05;
  CHECK_OK(cagekit_cpu_deformer_create(binding, 1, &d0));
  CHECK_OK(cagekit_cpu_deformer_create(loaded, 1, &d1));
  CHECK_OK(cagekit_cpu_deformer_deform(d0, control, 8, CAGEKIT_NORMALS_APPROXIMATE, 300, &written, p0, NULL));
  CHECK_OK(cagekit_cpu_deformer_deform(d1, control, 8, CAGEKIT_NORMALS_APPROXIMATE, 300, &written, p1, NULL));
  for (i = 0; i < 3 * a.vertex_count; ++i) CHECK(p0[i] == p1[i]);
  CHECK_OK(cagekit_binding_write_memory(loaded, &again));
  CHECK(cagekit_blob_size(again) == cagekit_blob_size(blob) &&
        memcmp(cagekit_blob_data(again), cagekit_blob_data(blob), cagekit_blob_size(blob)) == 0);
  /* Without a sector split: identity sources, no faces of its own. */
  {
    uint32_t sources[300], n = 0, faces = 7;
    uint64_t indices = 7;
    CHECK(a.has_sector_split == 0 && a.scan_vertex_count == a.vertex_count);
    CHECK_OK(cagekit_binding_get_vertex_sources(loaded, 0, &n, NULL));
    CHECK(n == a.vertex_count);
    CHECK_STATUS(cagekit_binding_get_vertex_sources(loaded, 2, &n, sources), CAGEKIT_ERROR_SIZE_INSUFFICIENT);
    CHECK_OK(cagekit_binding_get_vertex_sources(loaded, 300, &n, sources));
    for (i = 0; i < n; ++i) CHECK(sources[i] == i);
    CHECK_OK(cagekit_binding_get_faces(loaded, 0, &faces, NULL, 0, &indices, NULL));
    CHECK(faces == 0 && indices == 0);
    CHECK_STATUS(cagekit_binding_get_faces(loaded, 0, NULL, NULL, 0, &indices, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  }
  /* Damaged bytes: a precise error, no handle. */
  CHECK_STATUS(cagekit_binding_read_memory(context, cagekit_blob_data(blob), cagekit_blob_size(blob) / 2, 1, &none),
               CAGEKIT_ERROR_PARSE);
  CHECK(none == NULL);
  memcpy(bad, cagekit_blob_data(blob), sizeof(bad));
  bad[0] = 'X';
  CHECK_STATUS(cagekit_binding_read_memory(context, bad, sizeof(bad), 1, &none), CAGEKIT_ERROR_PARSE);
  CHECK(strstr(cagekit_last_error_message(context), "CAGEKITB") != NULL);
  CHECK_STATUS(cagekit_binding_read_memory(context, NULL, 10, 1, &none), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_binding_read_memory(context, bad, sizeof(bad), 1, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_binding_read_file(context, "/nonexistent/x.ckb", 0, &none), CAGEKIT_ERROR_IO);
  CHECK_STATUS(cagekit_binding_read_file(context, NULL, 0, &none), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cagekit_binding_write_file(binding, "/nonexistent/x.ckb"), CAGEKIT_ERROR_IO);
  {
    cagekit_blob none_blob = NULL;
    CHECK_STATUS(cagekit_binding_write_memory((cagekit_binding)sphere, &none_blob), CAGEKIT_ERROR_INVALID_HANDLE);
    CHECK(none_blob == NULL);
  }
  cagekit_blob_release(again);
  cagekit_blob_release(blob);
  cagekit_cpu_deformer_release(d1);
  cagekit_cpu_deformer_release(d0);
  cagekit_mesh_release(cage_mesh);
  cagekit_cage_release(saved_cage);
  cagekit_binding_release(loaded);
  cagekit_binding_release(binding);
  cagekit_cage_release(fitted);
  cagekit_cage_release(cube);
  cagekit_mesh_release(sphere);
  cagekit_mesh_release(cube_mesh);
  cagekit_context_release(context);
}

static void fit_reduces_the_error_every_pass(void) {
  cagekit_context context = new_context();
  cagekit_mesh cube_mesh = new_cube(context), sphere = new_sphere(context);
  cagekit_cage cube = NULL, fitted = NULL, again = NULL;
  cagekit_fit_options options = CAGEKIT_FIT_OPTIONS_INIT;
  cagekit_fit_report report;
  cagekit_fit_pass passes[8];
  cagekit_mesh_info info;
  double positions[24];
  uint32_t count = 0, i;
  CHECK_OK(cagekit_cage_create(cube_mesh, &cube));
  options.max_passes = 4;
  options.tolerance = 0.0;
  options.threads = 2;

  /* first call: pass_capacity 0, only the count of states */
  memset(&report, 0, sizeof(report));
  report.struct_size = sizeof(report);
  CHECK_OK(cagekit_cage_fit(cube, sphere, &options, &fitted, &report, 0, &count, NULL));
  CHECK(fitted != NULL);
  CHECK(report.pass_count >= 2 && report.pass_count <= 5 && count == report.pass_count);
  CHECK(report.final.l2 < report.initial.l2);
  CHECK(report.final.max_rel < report.initial.max_rel);
  CHECK(report.final.rms_rel < 0.5 * report.initial.rms_rel);
  CHECK(report.bbox_diagonal > 2.5 && report.bbox_diagonal < 2.6); /* 1.5 * sqrt(3) */
  CHECK(report.seconds > 0 && report.fairing_used == 0 && report.stopped_by_tolerance == 0);
  count = report.pass_count;

  /* second call: more than the max_passes + 1 entries that always suffice; the entry after the
     states measured stays untouched */
  memset(passes, 0, sizeof(passes));
  passes[count].l2 = -7;
  i = count;
  CHECK_OK(cagekit_cage_fit(cube, sphere, &options, &again, &report, 8, &count, passes));
  CHECK(report.pass_count == count && count == i);
  CHECK(report.best_pass < count && passes[0].l2 == report.initial.l2 &&
        passes[report.best_pass].l2 == report.final.l2);
  for (i = 1; i < count; ++i) CHECK(passes[i].l2 <= passes[i - 1].l2);
  for (i = 0; i < count; ++i) CHECK(passes[i].mean_rel <= passes[i].max_rel && passes[i].mean_projection_steps >= 0);
  CHECK(passes[count].l2 == -7);

  /* exactly max_passes + 1 entries */
  memset(passes, 0, sizeof(passes));
  cagekit_cage_release(again);
  again = NULL;
  CHECK_OK(cagekit_cage_fit(cube, sphere, &options, &again, &report, options.max_passes + 1, &count, passes));
  CHECK(report.pass_count == count && passes[0].l2 == report.initial.l2 && passes[count - 1].l2 > 0);

  /* same connectivity, the input cage unchanged, the output moved */
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_cage_get_info(fitted, &info));
  CHECK(info.vertices == 8 && info.quads == 6 && info.faces == 6);
  {
    cagekit_mesh m = NULL;
    double moved = 0;
    CHECK_OK(cagekit_cage_get_mesh(cube, &m));
    CHECK_OK(cagekit_mesh_get_positions(m, CAGEKIT_SCALAR_FLOAT64, 8, &count, positions));
    for (i = 0; i < 24; ++i) CHECK(positions[i] == kCubeD[i]);
    cagekit_mesh_release(m);
    CHECK_OK(cagekit_cage_get_mesh(fitted, &m));
    CHECK_OK(cagekit_mesh_get_positions(m, CAGEKIT_SCALAR_FLOAT64, 8, &count, positions));
    for (i = 0; i < 24; ++i) moved += fabs(positions[i] - kCubeD[i]);
    CHECK(moved > 0.1);
    cagekit_mesh_release(m);
  }

  /* piecewise-linear projection and CGLS also reduce the error; report NULL is allowed */
  options.projection = CAGEKIT_PROJECTION_PIECEWISE_LINEAR;
  options.solver = CAGEKIT_LSQ_CGLS;
  options.max_passes = 2;
  cagekit_cage_release(again);
  again = NULL;
  CHECK_OK(cagekit_cage_fit(cube, sphere, &options, &again, NULL, 0, &count, NULL));
  cagekit_cage_release(again);
  again = NULL;
  CHECK_OK(fit_without_passes(cube, sphere, &options, &again, &report));
  CHECK(report.final.l2 < report.initial.l2);

  /* NULL options = defaults */
  cagekit_cage_release(again);
  again = NULL;
  CHECK_OK(fit_without_passes(cube, sphere, NULL, &again, &report));
  CHECK(report.pass_count >= 2 && report.pass_count <= 6 && report.final.l2 < report.initial.l2);

  cagekit_cage_release(again);
  cagekit_cage_release(fitted);
  cagekit_cage_release(cube);
  cagekit_mesh_release(sphere);
  cagekit_mesh_release(cube_mesh);
  cagekit_context_release(context);
}

static void fit_keeps_tags_and_pinned_crease_vertices(void) {
  cagekit_context context = new_context();
  cagekit_mesh sphere = new_sphere(context), m = NULL;
  cagekit_cage cube = new_creased_cube(context), fitted = NULL;
  cagekit_fit_options options = CAGEKIT_FIT_OPTIONS_INIT;
  cagekit_fit_report report;
  cagekit_mesh_info info;
  double positions[24];
  uint32_t count = 0, i;
  memset(&report, 0, sizeof(report));
  report.struct_size = sizeof(report);
  options.max_passes = 2;
  CHECK_OK(fit_without_passes(cube, sphere, &options, &fitted, &report));
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_cage_get_info(fitted, &info));
  CHECK(info.creases == 12 && info.quads == 6);
  CHECK(report.final.l2 <= report.initial.l2);
  cagekit_cage_release(fitted);
  fitted = NULL;
  /* every vertex of the creased cube is on a sharp crease: nothing may move */
  options.keep_crease_vertices = 1;
  CHECK_OK(fit_without_passes(cube, sphere, &options, &fitted, &report));
  CHECK_OK(cagekit_cage_get_mesh(fitted, &m));
  CHECK_OK(cagekit_mesh_get_positions(m, CAGEKIT_SCALAR_FLOAT64, 8, &count, positions));
  for (i = 0; i < 24; ++i) CHECK(positions[i] == kCubeD[i]);
  CHECK(fabs(report.final.l2 - report.initial.l2) <= 1e-9 * report.initial.l2);
  cagekit_mesh_release(m);
  cagekit_cage_release(fitted);
  cagekit_cage_release(cube);
  cagekit_mesh_release(sphere);
  cagekit_context_release(context);
}

static int g_fit_stage_seen;
static int cancel_in_fit(void* user, const char* stage, double fraction) {
  (void)user;
  (void)fraction;
  if (strcmp(stage, "fit") != 0) return 1;
  g_fit_stage_seen = 1;
  return 0;
}

static int g_fit_progress_calls;
static double g_fit_last_fraction;
static int count_fit_progress(void* user, const char* stage, double fraction) {
  (void)user;
  if (strcmp(stage, "fit") == 0) {
    if (fraction < g_fit_last_fraction || fraction > 1) g_fit_last_fraction = 99; /* flags a regression */
    else g_fit_last_fraction = fraction;
    ++g_fit_progress_calls;
  }
  return 1;
}

#define EXPECT_BAD_FIT_OPTION(assignment, field)                                                       \
  do {                                                                                                 \
    cagekit_fit_options o_ = CAGEKIT_FIT_OPTIONS_INIT;                                                 \
    cagekit_cage out_ = (cagekit_cage)1;                                                               \
    assignment;                                                                                        \
    CHECK_STATUS(fit_without_passes(cube, sphere, &o_, &out_, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);  \
    CHECK(out_ == NULL);                                                                               \
    CHECK(strstr(cagekit_last_error_message(context), field) != NULL);                                 \
  } while (0)

static void fit_rejects_bad_arguments_and_can_be_cancelled(void) {
  cagekit_context context = new_context();
  cagekit_mesh sphere = new_sphere(context), cube_mesh = new_cube(context);
  cagekit_cage cube = new_creased_cube(context), out = (cagekit_cage)1;
  cagekit_fit_report report;
  cagekit_fit_options small = CAGEKIT_FIT_OPTIONS_INIT;
  uint32_t pass_count = 0;

  EXPECT_BAD_FIT_OPTION(o_.tolerance = NAN, "tolerance");
  EXPECT_BAD_FIT_OPTION(o_.tolerance = -1e-3, "tolerance");
  EXPECT_BAD_FIT_OPTION(o_.fairing = -1, "fairing");
  EXPECT_BAD_FIT_OPTION(o_.fairing = INFINITY, "fairing");
  EXPECT_BAD_FIT_OPTION(o_.tangential_weight = 1.5, "tangential_weight");
  EXPECT_BAD_FIT_OPTION(o_.tangential_weight = NAN, "tangential_weight");
  EXPECT_BAD_FIT_OPTION(o_.max_passes = 100001, "max_passes");
  EXPECT_BAD_FIT_OPTION(o_.max_passes = (uint32_t)-1, "max_passes");
  EXPECT_BAD_FIT_OPTION(o_.keep_crease_vertices = 2, "keep_crease_vertices");
  EXPECT_BAD_FIT_OPTION(o_.projection = (cagekit_projection_mode)2, "projection");
  EXPECT_BAD_FIT_OPTION(o_.projection = (cagekit_projection_mode)-1, "projection");
  EXPECT_BAD_FIT_OPTION(o_.solver = (cagekit_lsq_solver)7, "solver");
  EXPECT_BAD_FIT_OPTION(o_.threads = 5000, "threads");
  EXPECT_BAD_FIT_OPTION(o_.max_projection_steps = 100001, "max_projection_steps");
  EXPECT_BAD_FIT_OPTION(o_.projection_epsilon = 0, "projection_epsilon");
  EXPECT_BAD_FIT_OPTION(o_.projection_epsilon = NAN, "projection_epsilon");
  EXPECT_BAD_FIT_OPTION(o_.projection_seed_resolution = 0, "projection_seed_resolution");
  EXPECT_BAD_FIT_OPTION(o_.crease_feature_reach = 1.5, "crease_feature_reach");
  EXPECT_BAD_FIT_OPTION(o_.crease_feature_reach = NAN, "crease_feature_reach");
  EXPECT_BAD_FIT_OPTION(o_.crease_feature_reach = -0.01, "crease_feature_reach");
  EXPECT_BAD_FIT_OPTION(o_.struct_size = 0, "struct_size");

  /* an older, smaller options struct: the missing fields take their defaults */
  small.struct_size = offsetof(cagekit_fit_options, keep_crease_vertices);
  small.max_passes = 1;
  small.projection_epsilon = -1; /* beyond struct_size: not read */
  CHECK_OK(fit_without_passes(cube, sphere, &small, &out, NULL));
  cagekit_cage_release(out);
  /* one that ends before crease_feature_reach (1.0's reverse_sample_factor struct) */
  small = (cagekit_fit_options)CAGEKIT_FIT_OPTIONS_INIT;
  small.struct_size = offsetof(cagekit_fit_options, crease_feature_reach);
  small.crease_feature_reach = -1; /* beyond struct_size: not read */
  CHECK_OK(fit_without_passes(cube, sphere, &small, &out, NULL));
  cagekit_cage_release(out);

  /* bad report structs and pass arrays */
  memset(&report, 0, sizeof(report));
  out = (cagekit_cage)1;
  CHECK_STATUS(fit_without_passes(cube, sphere, NULL, &out, &report), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(out == NULL && strstr(cagekit_last_error_message(context), "struct_size") != NULL);
  CHECK_STATUS(cagekit_cage_fit(cube, sphere, NULL, &out, NULL, 6, &pass_count, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "passes") != NULL);
  CHECK_STATUS(cagekit_cage_fit(cube, sphere, NULL, &out, NULL, 0, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(out == NULL && strstr(cagekit_last_error_message(context), "pass_count_out") != NULL);

  /* NULL and wrong handles */
  CHECK_STATUS(fit_without_passes(NULL, sphere, NULL, &out, NULL), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK(out == NULL);
  CHECK_STATUS(fit_without_passes(cube, NULL, NULL, &out, NULL), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK(strstr(cagekit_last_error_message(context), "scan") != NULL);
  CHECK_STATUS(fit_without_passes((cagekit_cage)(void*)cube_mesh, sphere, NULL, &out, NULL),
               CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK_STATUS(fit_without_passes(cube, (cagekit_mesh)(void*)cube, NULL, &out, NULL), CAGEKIT_ERROR_INVALID_HANDLE);
  CHECK_STATUS(fit_without_passes(cube, sphere, NULL, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);

  /* a scan with a non-finite position */
  {
    static const double bad_positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    double copy[9];
    cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
    static const uint32_t tri[3] = {0, 1, 2};
    cagekit_mesh bad = NULL;
    memcpy(copy, bad_positions, sizeof(copy));
    copy[4] = NAN;
    desc.vertex_count = 3;
    desc.positions = copy;
    desc.face_count = 1;
    desc.face_indices = tri;
    CHECK_OK(cagekit_mesh_create(context, &desc, &bad));
    CHECK_STATUS(fit_without_passes(cube, bad, NULL, &out, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK(out == NULL);
    cagekit_mesh_release(bad);
  }

  /* progress: stage "fit", non-decreasing fractions, reaching 1 */
  g_fit_progress_calls = 0;
  g_fit_last_fraction = 0;
  CHECK_OK(cagekit_context_set_progress(context, count_fit_progress, NULL));
  CHECK_OK(fit_without_passes(cube, sphere, NULL, &out, NULL));
  CHECK(g_fit_progress_calls >= 2 && g_fit_last_fraction == 1.0);
  cagekit_cage_release(out);

  /* cancelled by the progress callback, and by cagekit_context_cancel */
  g_fit_stage_seen = 0;
  out = (cagekit_cage)1;
  CHECK_OK(cagekit_context_set_progress(context, cancel_in_fit, NULL));
  CHECK_STATUS(fit_without_passes(cube, sphere, NULL, &out, NULL), CAGEKIT_ERROR_CANCELLED);
  CHECK(out == NULL && g_fit_stage_seen);
  CHECK_OK(cagekit_context_set_progress(context, NULL, NULL));
  cagekit_context_cancel(context);
  out = (cagekit_cage)1;
  CHECK_STATUS(fit_without_passes(cube, sphere, NULL, &out, NULL), CAGEKIT_ERROR_CANCELLED);
  CHECK(out == NULL);
  cagekit_context_reset_cancel(context);
  CHECK_OK(fit_without_passes(cube, sphere, NULL, &out, NULL));
  cagekit_cage_release(out);

  cagekit_cage_release(cube);
  cagekit_mesh_release(cube_mesh);
  cagekit_mesh_release(sphere);
  cagekit_context_release(context);
}


static int g_progress_reports;
static int count_progress(void* user, const char* stage, double fraction) {
  (void)user;
  (void)stage;
  (void)fraction;
  ++g_progress_reports;
  return 1;
}

/* The fit cannot be repeated for a second call, so its pass array is checked before any work: a
 * nonzero capacity below max_passes + 1 is SIZE_INSUFFICIENT with max_passes + 1 written, and no
 * progress is reported (nothing ran); max_passes + 1 entries always suffice. The same for
 * cagekit_scan_to_cage's fit_passes. */
static void fit_with_a_short_pass_array_fails_before_any_work(void) {
  cagekit_context context = new_context();
  cagekit_mesh sphere = new_sphere(context), cube_mesh = new_cube(context);
  cagekit_cage cube = NULL, out = (cagekit_cage)1, limit = (cagekit_cage)1;
  cagekit_fit_options options = CAGEKIT_FIT_OPTIONS_INIT;
  cagekit_scan_to_cage_options journey = CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT;
  cagekit_fit_report report;
  cagekit_fit_pass passes[5];
  uint32_t count = 0;
  CHECK_OK(cagekit_cage_create(cube_mesh, &cube));
  CHECK_OK(cagekit_context_set_progress(context, count_progress, NULL));
  options.max_passes = 4;
  memset(&report, 0, sizeof(report));
  report.struct_size = sizeof(report);
  report.pass_count = 77;
  g_progress_reports = 0;
  CHECK_STATUS(cagekit_cage_fit(cube, sphere, &options, &out, &report, 4, &count, passes),
               CAGEKIT_ERROR_SIZE_INSUFFICIENT);
  CHECK(out == NULL && count == 5 && g_progress_reports == 0 && report.pass_count == 77);
  CHECK(strstr(cagekit_last_error_message(context), "passes: pass_capacity 4 is less than the required 5") != NULL);
  /* max_passes + 1 entries suffice whatever the fit does */
  CHECK_OK(cagekit_cage_fit(cube, sphere, &options, &out, &report, 5, &count, passes));
  CHECK(g_progress_reports > 0 && count == report.pass_count && count >= 2 && count <= 5);
  CHECK(passes[0].l2 == report.initial.l2 && passes[report.best_pass].l2 == report.final.l2);
  cagekit_cage_release(out);

  /* the journey's fit: options.fit's max_passes (2) + 1 */
  options.max_passes = 2;
  journey.fit = &options;
  journey.target = 30;
  g_progress_reports = 0;
  out = (cagekit_cage)1;
  CHECK_STATUS(cagekit_scan_to_cage(sphere, &journey, &out, &limit, NULL, NULL, 2, &count, passes),
               CAGEKIT_ERROR_SIZE_INSUFFICIENT);
  CHECK(out == NULL && limit == NULL && count == 3 && g_progress_reports == 0);
  CHECK(strstr(cagekit_last_error_message(context), "fit_passes: fit_pass_capacity 2") != NULL);
  CHECK_STATUS(cagekit_scan_to_cage(sphere, &journey, &out, NULL, NULL, NULL, 3, NULL, passes),
               CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "fit_pass_count_out") != NULL);

  CHECK_OK(cagekit_context_set_progress(context, NULL, NULL));
  cagekit_cage_release(cube);
  cagekit_mesh_release(cube_mesh);
  cagekit_mesh_release(sphere);
  cagekit_context_release(context);
}

/* Open cylinder of radius 1 about z, height 4, n_around x n_along quads split into triangles. */
static cagekit_mesh new_triangle_cylinder(cagekit_context context, int n_around, int n_along) {
  const uint32_t nv = (uint32_t)(n_around * (n_along + 1)), nf = (uint32_t)(2 * n_around * n_along);
  double* positions = (double*)malloc(3 * nv * sizeof(double));
  uint32_t* faces = (uint32_t*)malloc(3 * nf * sizeof(uint32_t));
  uint32_t at = 0;
  cagekit_mesh mesh = NULL;
  for (int j = 0; j <= n_along; ++j)
    for (int i = 0; i < n_around; ++i) {
      const double a = 6.283185307179586 * i / n_around;
      double* p = positions + 3 * (j * n_around + i);
      p[0] = cos(a);
      p[1] = sin(a);
      p[2] = 4.0 * j / n_along;
    }
  for (int j = 0; j < n_along; ++j)
    for (int i = 0; i < n_around; ++i) {
      const uint32_t a = (uint32_t)(j * n_around + i), b = (uint32_t)(j * n_around + (i + 1) % n_around);
      const uint32_t c = b + (uint32_t)n_around, d = a + (uint32_t)n_around;
      const uint32_t tri[6] = {a, b, c, a, c, d};
      memcpy(faces + at, tri, sizeof(tri));
      at += 6;
    }
  mesh = new_uniform_mesh(context, nv, positions, nf, 3, faces);
  free(positions);
  free(faces);
  return mesh;
}

/* Three triangles on one edge: not a 2-manifold. */
static cagekit_mesh new_three_triangles_on_one_edge(cagekit_context context) {
  static const double p[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  static const uint32_t f[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  return new_uniform_mesh(context, 5, p, 3, 3, f);
}

static void anisotropic_remesh_follows_a_cylinder(void) {
  cagekit_context context = new_context();
  cagekit_mesh mesh = new_triangle_cylinder(context, 96, 96);
  cagekit_anisotropic_options options = CAGEKIT_ANISOTROPIC_OPTIONS_INIT;
  cagekit_anisotropic_report report;
  cagekit_cage cage = NULL;
  cagekit_mesh_info info;
  memset(&report, 0, sizeof(report));
  report.struct_size = sizeof(report);
  options.tolerance = 0.001;
  options.curvature_radius = 0.0;
  CHECK_OK(cagekit_mesh_remesh_anisotropic(mesh, &options, &cage, &report));
  CHECK(report.quality.faces > 300);
  CHECK(report.quality.quads >= report.quality.faces * 95 / 100);
  CHECK(report.quality.max_face_valence <= 5);
  CHECK(report.holes == 0);
  CHECK(report.quality.creases == 0);
  CHECK(report.quality.min_scaled_jacobian > 0.5);
  CHECK(report.mean_alignment_deg < 2.0);
  memset(&info, 0, sizeof(info));
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_cage_get_info(cage, &info));
  CHECK(info.faces == report.quality.faces);
  cagekit_cage_release(cage);
  /* Bad arguments. */
  cage = (cagekit_cage)1;
  options.tolerance = 0.0;
  CHECK_STATUS(cagekit_mesh_remesh_anisotropic(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(cage == NULL);
  CHECK(strstr(cagekit_last_error_message(context),
               "cagekit_anisotropic_options.tolerance must be finite and in (0, 1], not 0") != NULL);
  options.tolerance = 0.002;
  options.max_face_valence = 2;
  CHECK_STATUS(cagekit_mesh_remesh_anisotropic(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context),
               "cagekit_anisotropic_options.max_face_valence must be in 3..1000000, not 2") != NULL);
  CHECK_STATUS(cagekit_mesh_remesh_anisotropic(mesh, NULL, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  cagekit_mesh_release(mesh);
  mesh = new_three_triangles_on_one_edge(context);
  CHECK_STATUS(cagekit_mesh_remesh_anisotropic(mesh, NULL, &cage, NULL), CAGEKIT_ERROR_INVALID_MESH);
  CHECK(strstr(cagekit_last_error_message(context), "manifold") != NULL ||
        strstr(cagekit_last_error_message(context), "edge") != NULL);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
  {
    /* A 1 MB budget: the estimate (~560 bytes per triangle) fails before anything is allocated. */
    cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
    desc.memory_budget_bytes = 1u << 20;
    CHECK_OK(cagekit_context_create(&desc, &context));
    mesh = new_triangle_cylinder(context, 96, 96);
    CHECK_STATUS(cagekit_mesh_remesh_anisotropic(mesh, NULL, &cage, NULL), CAGEKIT_ERROR_OUT_OF_MEMORY);
    cagekit_mesh_release(mesh);
    cagekit_context_release(context);
  }
}

static void quad_remesh_of_a_cylinder(void) {
  cagekit_context context = new_context();
  cagekit_mesh mesh = new_triangle_cylinder(context, 32, 24);
  cagekit_quad_remesh_options options = CAGEKIT_QUAD_REMESH_OPTIONS_INIT;
  cagekit_quad_remesh_report report;
  cagekit_cage cage = NULL;
  cagekit_mesh_info info;
  CHECK(options.edge_length == 0.05 && options.regions == 30 && options.t_joint_weight == 100.0 &&
        options.refinement_passes == 1);
  memset(&report, 0, sizeof(report));
  report.struct_size = sizeof(report);
  options.regions = 6;
  options.edge_length = 0.08;
  CHECK_OK(cagekit_mesh_remesh_quad(mesh, &options, &cage, &report));
  CHECK(report.regions == 6);
  CHECK(report.quality.faces > 50);
  CHECK(report.quality.quads >= report.quality.faces * 90 / 100);
  CHECK(report.quality.creases == 0); /* a smooth surface: no sharp region boundary */
  CHECK(report.quality.min_scaled_jacobian > 0.0);
  memset(&info, 0, sizeof(info));
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_cage_get_info(cage, &info));
  CHECK(info.faces == report.quality.faces && info.vertices == report.quality.vertices);
  cagekit_cage_release(cage);
  {
    /* A caller whose struct ends before `regions` (an older, shorter struct): the fields it
     * lacks take their defaults (30 regions). */
    cagekit_quad_remesh_options old = CAGEKIT_QUAD_REMESH_OPTIONS_INIT;
    old.struct_size = offsetof(cagekit_quad_remesh_options, regions);
    old.regions = 0xffffffffu; /* not read */
    CHECK_OK(cagekit_mesh_remesh_quad(mesh, &old, &cage, &report));
    CHECK(report.regions == 30);
    cagekit_cage_release(cage);
  }
  /* Bad options: precise errors, out stays NULL. */
  cage = (cagekit_cage)1;
  options.edge_length = 0.0;
  CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(cage == NULL);
  CHECK(strstr(cagekit_last_error_message(context),
               "cagekit_quad_remesh_options.edge_length must be finite and in (0, 1], not 0") != NULL);
  options.edge_length = 0.08;
  options.pentagon_weight = -5.0;
  CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "weight") != NULL);
  options.pentagon_weight = 40.0;
  {
    /* More regions than triangles with a seed (the host's regions are not adjusted): refused. */
    const uint32_t seed[1] = {0};
    options.regions = 1000000;
    options.seed_faces = seed;
    options.seed_face_count = 1;
    CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(cagekit_last_error_message(context), "regions") != NULL);
    options.seed_faces = NULL;
    options.seed_face_count = 0;
  }
  {
    /* Without pins or seeds a count the mesh cannot take is adjusted, not refused (capped at
     * the triangle count), and the report says what was asked and what was done. */
    options.regions = 1000000;
    options.edge_length = 0.2;
    options.refinement_passes = 0;
    memset(&report, 0, sizeof(report));
    report.struct_size = sizeof(report);
    CHECK_OK(cagekit_mesh_remesh_quad(mesh, &options, &cage, &report));
    CHECK(report.requested_regions == 1000000);
    CHECK(report.regions + report.merged_regions == 32 * 24 * 2 + report.split_regions);
    CHECK(report.reseeded_regions == 0); /* the first segmentation's layout, at the triangle count */
    options.edge_length = 0.08;
    options.refinement_passes = 1;
    cagekit_cage_release(cage);
    cage = (cagekit_cage)1;
  }
  options.regions = 6;
  options.refinement_passes = 17;
  CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "refinement_passes") != NULL);
  options.refinement_passes = 1;
  {
    /* Host control: one pinned region (two triangles sharing an edge of the cylinder's first
     * quad) and two seeds; then bad arrays. */
    const uint32_t pinned_offsets[2] = {0, 2}, pinned_faces[2] = {0, 1}, seeds[2] = {700, 1200};
    const uint32_t bad_offsets[2] = {0, 5000}, far_faces[2] = {0, 1200};
    options.pinned_region_count = 1;
    options.pinned_region_offsets = pinned_offsets;
    options.pinned_faces = pinned_faces;
    options.seed_faces = seeds;
    options.seed_face_count = 2;
    CHECK_OK(cagekit_mesh_remesh_quad(mesh, &options, &cage, &report));
    CHECK(report.regions == 6 && report.quality.faces > 20);
    cagekit_cage_release(cage);
    options.pinned_faces = far_faces; /* not edge-connected */
    CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(cagekit_last_error_message(context), "connected") != NULL);
    options.pinned_faces = pinned_faces;
    options.pinned_region_offsets = bad_offsets; /* beyond the face count */
    CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(cagekit_last_error_message(context), "pinned_region_offsets") != NULL);
    options.pinned_region_offsets = NULL;
    CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
    options.pinned_region_count = 0;
    options.seed_faces = NULL; /* with a count */
    CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
    options.seed_faces = pinned_faces;
    options.seed_face_count = 1;
    options.regions = 1000; /* fine; then a seed out of range */
    options.seed_faces = &bad_offsets[1];
    CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(cagekit_last_error_message(context), "out of range") != NULL);
    options.seed_faces = NULL;
    options.seed_face_count = 0;
    options.regions = 6;
  }
  options.regions = 0;
  options.region_tolerance = -1.0;
  CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context),
               "cagekit_quad_remesh_options.region_tolerance must be finite and >= 0, not -1") != NULL);
  options.region_tolerance = 0.01;
  cagekit_mesh_release(mesh);
  mesh = new_three_triangles_on_one_edge(context);
  options.regions = 1;
  CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &options, &cage, NULL), CAGEKIT_ERROR_INVALID_MESH);
  CHECK(strstr(cagekit_last_error_message(context), "edge") != NULL);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

/* The creases of `cage`: their count, and whether every crease vertex lies at height z (within
 * 1e-6). */
static uint32_t creases_at_height(cagekit_cage cage, double z, int* all_at_z) {
  cagekit_mesh mesh = NULL;
  uint32_t count = 0, vertices = 0, i;
  uint32_t* pairs;
  double* positions;
  CHECK_OK(cagekit_cage_get_creases(cage, 0, &count, NULL, NULL));
  CHECK_OK(cagekit_cage_get_mesh(cage, &mesh));
  CHECK_OK(cagekit_mesh_get_positions(mesh, CAGEKIT_SCALAR_FLOAT64, 0, &vertices, NULL));
  pairs = (uint32_t*)malloc(2 * (size_t)(count + 1) * sizeof(uint32_t));
  positions = (double*)malloc(3 * (size_t)(vertices + 1) * sizeof(double));
  CHECK_OK(cagekit_cage_get_creases(cage, count, &count, pairs, NULL));
  CHECK_OK(cagekit_mesh_get_positions(mesh, CAGEKIT_SCALAR_FLOAT64, vertices, &vertices, positions));
  *all_at_z = 1;
  for (i = 0; i < 2 * count; ++i)
    if (fabs(positions[3 * pairs[i] + 2] - z) > 1e-6) *all_at_z = 0;
  free(pairs);
  free(positions);
  cagekit_mesh_release(mesh);
  return count;
}

/* The host's sharp edges (issue 22): a ring of edges halfway up a smooth open cylinder, which
 * nothing would make sharp by its angle. Every method keeps it: simplify never merges across it
 * and the cage's creases lie on it; the remeshers' creases lie on it (with their angle tests
 * off); scan_to_cage finds it again after conditioning. Bad pairs are INVALID_ARGUMENT. */
static void sharp_edges_are_kept_by_every_method(void) {
  enum { kAround = 32, kAlong = 16 };
  cagekit_context context = new_context();
  cagekit_mesh mesh = new_triangle_cylinder(context, kAround, kAlong);
  uint32_t ring[2 * kAround], bad[2] = {0, 2 * kAround + 5}, i, levels = 0, level = 0, count = 0;
  uint32_t clusters[2 * kAround * kAlong];
  int at_mid = 0, straddles = 0;
  cagekit_hierarchy hierarchy = NULL;
  cagekit_cage cage = NULL, limit = NULL;
  cagekit_simplify_options simplify = CAGEKIT_SIMPLIFY_OPTIONS_INIT;
  cagekit_cage_options cage_options = CAGEKIT_CAGE_OPTIONS_INIT;
  cagekit_quad_remesh_options quad = CAGEKIT_QUAD_REMESH_OPTIONS_INIT;
  cagekit_anisotropic_options anisotropic = CAGEKIT_ANISOTROPIC_OPTIONS_INIT;
  cagekit_scan_to_cage_options scan = CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT;
  cagekit_scan_to_cage_report report;
  for (i = 0; i < kAround; ++i) { /* row kAlong / 2: z = 2 */
    ring[2 * i] = (kAlong / 2) * kAround + i;
    ring[2 * i + 1] = (kAlong / 2) * kAround + (i + 1) % kAround;
  }
  cage_options.tag_boundary_edges = CAGEKIT_FALSE;
  /* Simplify: without the ring the coarse cage of a smooth cylinder has no crease at all. */
  CHECK_OK(cagekit_hierarchy_create(mesh, NULL, &hierarchy));
  CHECK_OK(cagekit_hierarchy_find_level(hierarchy, CAGEKIT_LEVEL_BY_FACES, 12, &level));
  CHECK_OK(cagekit_hierarchy_set_level(hierarchy, level));
  CHECK_OK(cagekit_hierarchy_build_cage(hierarchy, &cage_options, &cage, NULL));
  CHECK(creases_at_height(cage, 2.0, &at_mid) == 0);
  cagekit_cage_release(cage);
  cagekit_hierarchy_release(hierarchy);
  simplify.sharp_edges = ring;
  simplify.sharp_edge_count = kAround;
  CHECK_OK(cagekit_hierarchy_create(mesh, &simplify, &hierarchy));
  CHECK_OK(cagekit_hierarchy_get_level_count(hierarchy, &levels));
  CHECK_OK(cagekit_hierarchy_set_level(hierarchy, levels - 1)); /* the coarsest level */
  CHECK_OK(cagekit_hierarchy_get_clusters(hierarchy, 2 * kAround * kAlong, &count, clusters));
  CHECK(count == 2 * kAround * kAlong);
  for (i = 0; i < count; ++i) { /* faces of rows below the ring never share a cluster with those above */
    uint32_t k;
    for (k = 0; k < count; ++k)
      if (clusters[i] == clusters[k] && (i < count / 2) != (k < count / 2)) straddles = 1;
  }
  CHECK(!straddles);
  CHECK_OK(cagekit_hierarchy_find_level(hierarchy, CAGEKIT_LEVEL_BY_FACES, 12, &level));
  CHECK_OK(cagekit_hierarchy_set_level(hierarchy, level));
  CHECK_OK(cagekit_hierarchy_build_cage(hierarchy, &cage_options, &cage, NULL)); /* creases from the hierarchy */
  CHECK(creases_at_height(cage, 2.0, &at_mid) >= 3 && at_mid);
  cagekit_cage_release(cage);
  cagekit_hierarchy_release(hierarchy);
  /* Quad: region borders on the ring, creases there only (the angle test off). */
  quad.regions = 6;
  quad.edge_length = 0.08;
  quad.crease_angle_degrees = -1.0;
  quad.sharp_edges = ring;
  quad.sharp_edge_count = kAround;
  CHECK_OK(cagekit_mesh_remesh_quad(mesh, &quad, &cage, NULL));
  CHECK(creases_at_height(cage, 2.0, &at_mid) >= 3 && at_mid);
  cagekit_cage_release(cage);
  /* Anisotropic: a feature line along the ring (the angle test off). */
  anisotropic.tolerance = 0.004;
  anisotropic.feature_angle_degrees = -1.0;
  anisotropic.sharp_edges = ring;
  anisotropic.sharp_edge_count = kAround;
  CHECK_OK(cagekit_mesh_remesh_anisotropic(mesh, &anisotropic, &cage, NULL));
  CHECK(creases_at_height(cage, 2.0, &at_mid) >= 3 && at_mid);
  cagekit_cage_release(cage);
  /* scan_to_cage: the ring found again after conditioning. */
  memset(&report, 0, sizeof(report));
  report.struct_size = sizeof(report);
  scan.target = 12;
  scan.cage = &cage_options;
  scan.sharp_edges = ring;
  scan.sharp_edge_count = kAround;
  CHECK_OK(scan_to_cage_without_passes(mesh, &scan, &cage, &limit, &report));
  CHECK(report.sharp_edges == kAround && report.sharp_edges_dropped == 0);
  CHECK(creases_at_height(cage, 2.0, &at_mid) >= 3);
  cagekit_cage_release(cage);
  cagekit_cage_release(limit);
  /* Bad pairs: not an edge, NULL with a count, nested in scan_to_cage. */
  cage = NULL;
  quad.sharp_edges = bad;
  quad.sharp_edge_count = 1;
  CHECK_STATUS(cagekit_mesh_remesh_quad(mesh, &quad, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "is not an edge of the mesh") != NULL);
  anisotropic.sharp_edges = bad;
  anisotropic.sharp_edge_count = 1;
  CHECK_STATUS(cagekit_mesh_remesh_anisotropic(mesh, &anisotropic, &cage, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  simplify.sharp_edges = bad;
  simplify.sharp_edge_count = 1;
  CHECK_STATUS(cagekit_hierarchy_create(mesh, &simplify, &hierarchy), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "is not an edge of the mesh") != NULL);
  simplify.sharp_edges = NULL;
  CHECK_STATUS(cagekit_hierarchy_create(mesh, &simplify, &hierarchy), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context),
               "cagekit_simplify_options.sharp_edges must not be NULL with sharp_edge_count 1") != NULL);
  cage_options.sharp_edges = ring;
  cage_options.sharp_edge_count = kAround;
  CHECK_STATUS(scan_to_cage_without_passes(mesh, &scan, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(cage == NULL && hierarchy == NULL);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

/* The whole journey in one call (cagekit_scan_to_cage): a clean scan, the same scan as a
 * triangle soup with one triangle flipped (welded and oriented by the conditioning), a tiny input
 * that is its own cage, bounds that cannot be met (QUALITY, nothing returned) and bad input. */
static void scan_to_cage_conditions_fits_and_judges(void) {
  cagekit_context context = new_context();
  cagekit_mesh sphere = new_sphere(context), soup = NULL, degenerate = NULL, cube = new_cube(context);
  cagekit_cage cage = NULL, limit = NULL;
  cagekit_scan_to_cage_options options = CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT;
  cagekit_scan_to_cage_report report;
  cagekit_fit_report fit;
  cagekit_fit_pass passes[6];
  cagekit_mesh_info info;
  uint32_t pass_count = 0, count = 0;
  uint64_t index_count = 0;
  static double soup_positions[9 * SPHERE_TRIANGLES];
  static uint32_t soup_triangles[3 * SPHERE_TRIANGLES];
  static const double flat[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0};
  static const uint32_t flat_triangles[] = {0, 1, 2, 1, 2, 3};
  double positions[3 * SPHERE_VERTICES];
  uint32_t triangles[3 * SPHERE_TRIANGLES], i, k;
  cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;

  memset(&report, 0, sizeof(report));
  report.struct_size = sizeof(report);
  memset(&fit, 0, sizeof(fit));
  fit.struct_size = sizeof(fit);
  options.target = 30;
  /* the default fit's max_passes (5) + 1 entries */
  CHECK_OK(cagekit_scan_to_cage(sphere, &options, &cage, &limit, &report, &fit, 6, &pass_count, passes));
  CHECK(cage != NULL && limit != NULL);
  CHECK(report.conditioned_faces == SPHERE_TRIANGLES && report.welded_vertices == 0 && report.flipped_faces == 0);
  CHECK(report.used_method == CAGEKIT_SCAN_SIMPLIFY && report.fallback == 0 && report.fallback_reason[0] == 0);
  CHECK(report.simplify_target_used == 30.0);
  CHECK(report.cage_faces >= 30 && report.cage_faces <= 120 && report.holes_added == 0);
  CHECK(report.fit_pass_count >= 2 && report.fit_final.max_rel < report.fit_initial.max_rel);
  CHECK(fit.pass_count == report.fit_pass_count && fit.best_pass == report.fit_best_pass);
  CHECK(pass_count == fit.pass_count && passes[fit.best_pass].max_rel == report.fit_final.max_rel);
  CHECK(fit.final.max_rel == report.fit_final.max_rel);
  CHECK(report.fit_final_two_sided.surface_to_scan_max_rel >= 0 && report.fit_final_two_sided.two_sided_rms_rel > 0);
  printf("scan_to_cage sphere: %llu cage faces, scan->limit %.4g, limit->scan %.4g\n", (unsigned long long)report.cage_faces,
         report.scan_to_limit_max_rel, report.limit_to_scan_max_rel);
  CHECK(report.scan_to_limit_max_rel < 0.05 && report.limit_to_scan_max_rel < 0.05);
  CHECK(report.self_intersections == 0 && report.self_intersection_triangles > 0);
  info.struct_size = sizeof(info);
  CHECK_OK(cagekit_cage_get_info(limit, &info));
  CHECK(info.faces == report.limit_faces && report.limit_levels == 3);
  /* The two-sided refit: when kept, the one-sided fit it replaced was at least 5 % farther. */
  CHECK(report.two_sided_refit == 0 || report.two_sided_refit == 1);
  if (report.two_sided_refit)
    CHECK(0.95 * report.one_sided_fit_max_rel >
          (report.scan_to_limit_max_rel > report.limit_to_scan_max_rel ? report.scan_to_limit_max_rel
                                                                         : report.limit_to_scan_max_rel));
  else
    CHECK(report.one_sided_fit_max_rel == 0);
  cagekit_cage_release(cage);
  cagekit_cage_release(limit);
  cage = limit = NULL;
  /* Switched off, and a caller built against the struct without the member: no refit. */
  options.two_sided_refit_factor = 0;
  CHECK_OK(scan_to_cage_without_passes(sphere, &options, &cage, NULL, &report));
  CHECK(report.two_sided_refit == 0 && report.one_sided_fit_max_rel == 0);
  cagekit_cage_release(cage);
  cage = NULL;
  options.two_sided_refit_factor = 3;
  options.struct_size = offsetof(cagekit_scan_to_cage_options, two_sided_refit_factor);
  CHECK_OK(scan_to_cage_without_passes(sphere, &options, &cage, NULL, &report));
  cagekit_cage_release(cage);
  cage = NULL;
  options.struct_size = sizeof(options);

  /* The sphere as a soup: every triangle with its own corners, one of them flipped. */
  CHECK_OK(cagekit_mesh_get_positions(sphere, CAGEKIT_SCALAR_FLOAT64, SPHERE_VERTICES, &count, positions));
  CHECK_OK(cagekit_mesh_get_faces(sphere, 0, &count, NULL, 3 * SPHERE_TRIANGLES, &index_count, triangles));
  for (i = 0; i < SPHERE_TRIANGLES; ++i)
    for (k = 0; k < 3; ++k) {
      const uint32_t corner = i == 7 ? 2 - k : k; /* triangle 7 reversed */
      memcpy(&soup_positions[9 * i + 3 * k], &positions[3 * triangles[3 * i + corner]], 3 * sizeof(double));
      soup_triangles[3 * i + k] = 3 * i + k;
    }
  desc.vertex_count = 3 * SPHERE_TRIANGLES;
  desc.positions = soup_positions;
  desc.face_count = SPHERE_TRIANGLES;
  desc.face_indices = soup_triangles;
  CHECK_OK(cagekit_mesh_create(context, &desc, &soup));
  CHECK_OK(scan_to_cage_without_passes(soup, &options, &cage, NULL, &report));
  CHECK(report.welded_vertices == 3 * SPHERE_TRIANGLES - SPHERE_VERTICES && report.flipped_faces == 1);
  CHECK(report.conditioned_vertices == SPHERE_VERTICES && report.components == 1);
  CHECK(report.limit_to_scan_max_rel < 0.05);
  cagekit_cage_release(cage);
  cage = NULL;
  /* Without conditioning, the sphere with one triangle reversed is refused (inconsistent
   * orientation); with it, the triangle is flipped back. */
  {
    cagekit_mesh flipped = NULL;
    uint32_t t = triangles[3 * 7];
    triangles[3 * 7] = triangles[3 * 7 + 1];
    triangles[3 * 7 + 1] = t;
    desc.vertex_count = SPHERE_VERTICES;
    desc.positions = positions;
    desc.face_count = SPHERE_TRIANGLES;
    desc.face_indices = triangles;
    CHECK_OK(cagekit_mesh_create(context, &desc, &flipped));
    options.repair = 0;
    CHECK_STATUS(scan_to_cage_without_passes(flipped, &options, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_MESH);
    CHECK(cage == NULL);
    options.repair = 1;
    CHECK_OK(scan_to_cage_without_passes(flipped, &options, &cage, NULL, &report));
    CHECK(report.flipped_faces == 1 && report.welded_vertices == 0);
    cagekit_cage_release(cage);
    cage = NULL;
    cagekit_mesh_release(flipped);
  }

  /* A 6-quad cube asked for 60 faces is its own cage (its 12 sharp edges creased). */
  options.target = 60;
  CHECK_OK(scan_to_cage_without_passes(cube, &options, &cage, NULL, &report));
  CHECK(report.input_is_cage == 1 && report.cage_faces == 6 && report.creases == 12);
  cagekit_cage_release(cage);
  cage = NULL;

  /* Bounds no surface meets: QUALITY naming the figure, nothing returned. */
  options.target = 6;
  options.max_limit_to_scan_rel = 1e-12;
  options.limit_to_scan_factor = 1e-12;
  options.small_input_faces = 0;
  CHECK_STATUS(scan_to_cage_without_passes(sphere, &options, &cage, &limit, NULL), CAGEKIT_ERROR_QUALITY);
  CHECK(cage == NULL && limit == NULL);
  CHECK(strstr(cagekit_last_error_message(context), "strays") != NULL);
  CHECK(strcmp(cagekit_status_string(CAGEKIT_ERROR_QUALITY), "result misses its quality bounds") == 0);

  /* Bad input and options. */
  options = (cagekit_scan_to_cage_options)CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT;
  desc.vertex_count = 4;
  desc.positions = flat;
  desc.face_count = 2;
  desc.face_indices = flat_triangles;
  CHECK_OK(cagekit_mesh_create(context, &desc, &degenerate));
  CHECK_STATUS(scan_to_cage_without_passes(degenerate, &options, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_MESH);
  CHECK(strstr(cagekit_last_error_message(context), "nothing left") != NULL);
  CHECK_STATUS(scan_to_cage_without_passes(sphere, &options, NULL, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.target = 0;
  CHECK_STATUS(scan_to_cage_without_passes(sphere, &options, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.target = 60;
  options.limit_levels = 0;
  CHECK_STATUS(scan_to_cage_without_passes(sphere, &options, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.limit_levels = 3;
  options.weld_tolerance_rel = -1;
  CHECK_STATUS(scan_to_cage_without_passes(sphere, &options, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.weld_tolerance_rel = 0;
  options.finer_simplify_attempts = 9;
  CHECK_STATUS(scan_to_cage_without_passes(sphere, &options, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.finer_simplify_attempts = 2;
  options.two_sided_refit_factor = -1;
  CHECK_STATUS(scan_to_cage_without_passes(sphere, &options, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "two_sided_refit_factor") != NULL);
  options.two_sided_refit_factor = NAN;
  CHECK_STATUS(scan_to_cage_without_passes(sphere, &options, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  options.two_sided_refit_factor = 3;
  {
    cagekit_fit_options bad_fit = CAGEKIT_FIT_OPTIONS_INIT;
    bad_fit.reverse_sample_factor = 101;
    options.fit = &bad_fit;
    CHECK_STATUS(scan_to_cage_without_passes(sphere, &options, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(cagekit_last_error_message(context), "reverse_sample_factor") != NULL);
    options.fit = NULL;
  }
  memcpy(&options.method, &(int32_t){7}, sizeof(int32_t));
  CHECK_STATUS(scan_to_cage_without_passes(sphere, &options, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(cage == NULL);
  CHECK_STATUS(scan_to_cage_without_passes(NULL, NULL, &cage, NULL, NULL), CAGEKIT_ERROR_INVALID_HANDLE);
  /* Cancelled by the progress callback: CANCELLED, nothing returned; the context's memory budget
   * applies too (OUT_OF_MEMORY before the work). */
  options = (cagekit_scan_to_cage_options)CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT;
  CHECK_OK(cagekit_context_set_progress(context, cancel_after_first, NULL));
  CHECK_STATUS(scan_to_cage_without_passes(sphere, &options, &cage, &limit, NULL), CAGEKIT_ERROR_CANCELLED);
  CHECK(cage == NULL && limit == NULL);
  CHECK_OK(cagekit_context_set_progress(context, NULL, NULL));
  {
    cagekit_context_desc small = CAGEKIT_CONTEXT_DESC_INIT;
    cagekit_context tight = NULL;
    cagekit_mesh copy = NULL;
    small.memory_budget_bytes = 64 * 1024; /* holds the mesh, not the fit (~3 KB per sample) */
    CHECK_OK(cagekit_context_create(&small, &tight));
    desc.vertex_count = SPHERE_VERTICES;
    desc.positions = positions;
    desc.face_count = SPHERE_TRIANGLES;
    desc.face_indices = triangles;
    CHECK_OK(cagekit_mesh_create(tight, &desc, &copy));
    CHECK_STATUS(scan_to_cage_without_passes(copy, &options, &cage, NULL, NULL), CAGEKIT_ERROR_OUT_OF_MEMORY);
    CHECK(cage == NULL);
    cagekit_mesh_release(copy);
    cagekit_context_release(tight);
  }
  cagekit_mesh_release(degenerate);
  cagekit_mesh_release(soup);
  cagekit_mesh_release(cube);
  cagekit_mesh_release(sphere);
  cagekit_context_release(context);
}

/* cagekit_bool32, one rule for every boolean input: 0 or 1; 2 is INVALID_ARGUMENT with the
 * message "cagekit_<struct>.<field> must be 0 or 1, not 2", before any work. */
static void booleans_are_0_or_1(void) {
  cagekit_context context = new_context();
  cagekit_mesh mesh = new_cube(context);
  cagekit_cage cage = new_creased_cube(context);
  cagekit_cage out = NULL;
  cagekit_blob blob = NULL;
  cagekit_binding binding = NULL;
  cagekit_hierarchy hierarchy = NULL;
  cagekit_write_options write = CAGEKIT_WRITE_OPTIONS_INIT;
  cagekit_subdivide_options subdivide = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  cagekit_cage_options cage_options = CAGEKIT_CAGE_OPTIONS_INIT;
  cagekit_fit_options fit = CAGEKIT_FIT_OPTIONS_INIT;
  cagekit_bind_options bind = CAGEKIT_BIND_OPTIONS_INIT;
  cagekit_scan_to_cage_options scan = CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT;
  CHECK(CAGEKIT_TRUE == 1u && CAGEKIT_FALSE == 0u && sizeof(cagekit_bool32) == 4);
  write.format = CAGEKIT_FORMAT_PLY;
  write.ply_binary = 2;
  CHECK_STATUS(cagekit_cage_write_memory(cage, &write, &blob, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_write_options.ply_binary must be 0 or 1, not 2") != NULL);
  CHECK(blob == NULL);
  subdivide.limit_positions = 2;
  CHECK_STATUS(cagekit_cage_subdivide(cage, &subdivide, &out), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_subdivide_options.limit_positions") != NULL);
  CHECK_OK(cagekit_hierarchy_create(mesh, NULL, &hierarchy));
  cage_options.tag_boundary_edges = 2;
  CHECK_STATUS(cagekit_hierarchy_build_cage(hierarchy, &cage_options, &out, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_cage_options.tag_boundary_edges") != NULL);
  fit.keep_crease_vertices = 2;
  CHECK_STATUS(fit_without_passes(cage, mesh, &fit, &out, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_fit_options.keep_crease_vertices") != NULL);
  fit.keep_crease_vertices = CAGEKIT_FALSE;
  fit.select_best_two_sided = 0xffffffffu;
  CHECK_STATUS(fit_without_passes(cage, mesh, &fit, &out, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_fit_options.select_best_two_sided") != NULL);
  bind.exact_normals = 2;
  CHECK_STATUS(cagekit_multires_bind(cage, mesh, &bind, &binding), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_bind_options.exact_normals") != NULL);
  scan.repair = 2;
  CHECK_STATUS(scan_to_cage_without_passes(mesh, &scan, &out, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_scan_to_cage_options.repair") != NULL);
  scan.repair = CAGEKIT_TRUE;
  scan.fallback_to_simplify = 7;
  CHECK_STATUS(scan_to_cage_without_passes(mesh, &scan, &out, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_scan_to_cage_options.fallback_to_simplify") != NULL);
  CHECK(out == NULL && binding == NULL);
  cagekit_hierarchy_release(hierarchy);
  cagekit_cage_release(cage);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

/* Every options struct is checked by its table, with one message format naming the struct and
 * the field, the rule and the value: integers, reals, flags, enums and thread counts alike. */
static void option_errors_name_struct_field_rule_and_value(void) {
  cagekit_context context = new_context();
  cagekit_mesh mesh = new_cube(context);
  cagekit_cage cage = new_creased_cube(context);
  cagekit_cage out = NULL;
  cagekit_mesh repaired = NULL;
  cagekit_blob blob = NULL;
  cagekit_binding binding = NULL;
  cagekit_limit_patches patches = NULL;
  cagekit_write_options write = CAGEKIT_WRITE_OPTIONS_INIT;
  cagekit_subdivide_options subdivide = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  cagekit_repair_options repair = CAGEKIT_REPAIR_OPTIONS_INIT;
  cagekit_fit_options fit = CAGEKIT_FIT_OPTIONS_INIT;
  cagekit_bind_options bind = CAGEKIT_BIND_OPTIONS_INIT;
  cagekit_limit_patch_options limit = CAGEKIT_LIMIT_PATCH_OPTIONS_INIT;
  cagekit_scan_to_cage_options scan = CAGEKIT_SCAN_TO_CAGE_OPTIONS_INIT;
  write.format = CAGEKIT_FORMAT_DRACO;
  write.draco_position_bits = 0;
  CHECK_STATUS(cagekit_cage_write_memory(cage, &write, &blob, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context),
               "cagekit_write_options.draco_position_bits must be in 1..30, not 0") != NULL);
  write.draco_position_bits = 14;
  write.draco_speed = -1;
  CHECK_STATUS(cagekit_cage_write_memory(cage, &write, &blob, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_write_options.draco_speed must be in 0..10, not -1") != NULL);
  subdivide.levels = 99;
  CHECK_STATUS(cagekit_cage_subdivide(cage, &subdivide, &out), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_subdivide_options.levels must be in 0..") != NULL);
  CHECK(strstr(cagekit_last_error_message(context), ", not 99") != NULL);
  repair.steps = 0x100;
  CHECK_STATUS(cagekit_mesh_repair(mesh, &repair, &repaired, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context),
               "cagekit_repair_options.steps must be a combination of CAGEKIT_REPAIR_* flags (0x7f), not 0x100") != NULL);
  fit.projection = (cagekit_projection_mode)9;
  CHECK_STATUS(fit_without_passes(cage, mesh, &fit, &out, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context),
               "cagekit_fit_options.projection must be a cagekit_projection_mode (CAGEKIT_PROJECTION_EXACT, "
               "CAGEKIT_PROJECTION_PIECEWISE_LINEAR), not 9") != NULL);
  fit.projection = CAGEKIT_PROJECTION_EXACT;
  fit.tangential_weight = 1.5;
  CHECK_STATUS(fit_without_passes(cage, mesh, &fit, &out, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context),
               "cagekit_fit_options.tangential_weight must be finite and in [0, 1], not 1.5") != NULL);
  bind.threads = 5000;
  CHECK_STATUS(cagekit_multires_bind(cage, mesh, &bind, &binding), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context), "cagekit_bind_options.threads must be in 0..1024, not 5000") != NULL);
  limit.tolerance = 0.0;
  CHECK_STATUS(cagekit_limit_patches_create(cage, &limit, &patches), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context),
               "cagekit_limit_patch_options.tolerance must be finite and > 0, not 0") != NULL);
  scan.target = 0.5;
  CHECK_STATUS(scan_to_cage_without_passes(mesh, &scan, &out, NULL, NULL), CAGEKIT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cagekit_last_error_message(context),
               "cagekit_scan_to_cage_options.target must be finite and in [1, 1e+12], not 0.5") != NULL);
  CHECK(out == NULL && repaired == NULL && blob == NULL && binding == NULL && patches == NULL);
  cagekit_cage_release(cage);
  cagekit_mesh_release(mesh);
  cagekit_context_release(context);
}

int main(void) {
  static const c_test_case tests[] = {
      {"version_is_consistent", version_is_consistent},
      {"context_rejects_other_abi_and_bad_struct_size", context_rejects_other_abi_and_bad_struct_size},
      {"older_smaller_struct_is_accepted", older_smaller_struct_is_accepted},
      {"mesh_round_trips_through_buffers", mesh_round_trips_through_buffers},
      {"bad_descriptions_are_rejected", bad_descriptions_are_rejected},
      {"wrong_handle_types_are_detected", wrong_handle_types_are_detected},
      {"validation_names_the_problem_and_repair_fixes_it", validation_names_the_problem_and_repair_fixes_it},
      {"cage_tags_round_trip_and_bad_tags_fail", cage_tags_round_trip_and_bad_tags_fail},
      {"cage_survives_every_format_in_memory", cage_survives_every_format_in_memory},
      {"stl_is_read_welded_and_not_written", stl_is_read_welded_and_not_written},
      {"corrupt_memory_is_a_parse_error", corrupt_memory_is_a_parse_error},
      {"progress_callback_can_cancel", progress_callback_can_cancel},
      {"subdivision_counts_and_tags", subdivision_counts_and_tags},
      {"surface_basis_is_a_partition_of_unity", surface_basis_is_a_partition_of_unity},
      {"limit_patches_match_the_surface", limit_patches_match_the_surface},
      {"array_outputs_have_one_two_call_shape", array_outputs_have_one_two_call_shape},
      {"limit_surfaces_of_a_regular_torus_are_exact", limit_surfaces_of_a_regular_torus_are_exact},
      {"limit_surfaces_of_a_cube_approximate_within_the_tolerance",
       limit_surfaces_of_a_cube_approximate_within_the_tolerance},
      {"limit_surfaces_reject_bad_arguments_and_can_be_cancelled",
       limit_surfaces_reject_bad_arguments_and_can_be_cancelled},
      {"last_error_is_per_thread", last_error_is_per_thread},
      {"objects_outlive_their_context_reference", objects_outlive_their_context_reference},
      {"simplification_hierarchy_browses_levels_and_builds_a_cage",
       simplification_hierarchy_browses_levels_and_builds_a_cage},
      {"out_of_range_enum_values_are_rejected", out_of_range_enum_values_are_rejected},
      {"booleans_are_0_or_1", booleans_are_0_or_1},
      {"option_errors_name_struct_field_rule_and_value", option_errors_name_struct_field_rule_and_value},
      {"memory_budget_fails_cleanly_before_allocating", memory_budget_fails_cleanly_before_allocating},
      {"multires_binding_reproduces_and_deforms_the_scan", multires_binding_reproduces_and_deforms_the_scan},
      {"cpu_deformer_float32_outputs_match_double", cpu_deformer_float32_outputs_match_double},
      {"binding_deformer_vertex_order_is_a_permutation", binding_deformer_vertex_order_is_a_permutation},
      {"saved_binding_round_trips_and_bad_bytes_fail", saved_binding_round_trips_and_bad_bytes_fail},
      {"sector_split_duplicates_sharp_vertices", sector_split_duplicates_sharp_vertices},
      {"fit_reduces_the_error_every_pass", fit_reduces_the_error_every_pass},
      {"fit_keeps_tags_and_pinned_crease_vertices", fit_keeps_tags_and_pinned_crease_vertices},
      {"fit_rejects_bad_arguments_and_can_be_cancelled", fit_rejects_bad_arguments_and_can_be_cancelled},
      {"fit_with_a_short_pass_array_fails_before_any_work", fit_with_a_short_pass_array_fails_before_any_work},
      {"anisotropic_remesh_follows_a_cylinder", anisotropic_remesh_follows_a_cylinder},
      {"quad_remesh_of_a_cylinder", quad_remesh_of_a_cylinder},
      {"sharp_edges_are_kept_by_every_method", sharp_edges_are_kept_by_every_method},
      {"scan_to_cage_conditions_fits_and_judges", scan_to_cage_conditions_fits_and_judges},
  };
  return run_tests(tests, (int)(sizeof(tests) / sizeof(tests[0])));
}
