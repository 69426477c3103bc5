/* SPDX-License-Identifier: GPL-3.0-or-later
 *
 * c_host: the smallest complete host of libcagekit, in C99, using only the public header.
 *   c_host IN OUT [LEVELS]
 * loads a scan (OBJ/PLY/OFF/DRC), builds a cage from it (for now a copy of the mesh: the
 * simplification that makes coarse cages is a later stage), subdivides it LEVELS times
 * (default 1) and writes the result as OBJ. Exit code 0 on success, 2 on bad input.
 */
#include <cagekit/cagekit.h>

#include <stdio.h>
#include <stdlib.h>

static int report_failure(cagekit_context context, cagekit_status status, const char* what) {
  fprintf(stderr, "c_host: %s failed (%s): %s\n", what, cagekit_status_string(status),
          cagekit_last_error_message(context));
  return 2;
}

static int print_progress(void* user_data, const char* stage, double fraction) {
  (void)user_data;
  fprintf(stderr, "\r%s %3.0f%%", stage, fraction * 100.0);
  if (fraction >= 1.0) fputc('\n', stderr);
  return 1; /* continue */
}

int main(int argc, char** argv) {
  cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
  cagekit_context context = NULL;
  cagekit_mesh scan = NULL;
  cagekit_cage cage = NULL, refined = NULL;
  cagekit_subdivide_options subdivide = CAGEKIT_SUBDIVIDE_OPTIONS_INIT;
  cagekit_write_options write = CAGEKIT_WRITE_OPTIONS_INIT;
  cagekit_mesh_info info;
  cagekit_status status;
  int exit_code = 2;

  if (argc < 3 || argc > 4) {
    fprintf(stderr, "usage: c_host IN OUT.obj [LEVELS]\n");
    return 64;
  }
  subdivide.levels = argc == 4 ? (uint32_t)strtoul(argv[3], NULL, 10) : 1u;
  if (cagekit_abi_version() != CAGEKIT_ABI_VERSION) {
    fprintf(stderr, "c_host: built for CageKit ABI %d, loaded %u\n", CAGEKIT_ABI_VERSION, cagekit_abi_version());
    return 2;
  }
  desc.progress = print_progress;
  status = cagekit_context_create(&desc, &context);
  if (CAGEKIT_FAILED(status)) return report_failure(NULL, status, "cagekit_context_create");

  status = cagekit_mesh_read_file(context, argv[1], CAGEKIT_FORMAT_AUTO, &scan);
  if (CAGEKIT_FAILED(status)) { exit_code = report_failure(context, status, "reading the scan"); goto done; }
  status = cagekit_cage_create(scan, &cage);
  if (CAGEKIT_FAILED(status)) { exit_code = report_failure(context, status, "building the cage"); goto done; }
  status = cagekit_cage_subdivide(cage, &subdivide, &refined);
  if (CAGEKIT_FAILED(status)) { exit_code = report_failure(context, status, "subdividing"); goto done; }
  write.format = CAGEKIT_FORMAT_OBJ;
  status = cagekit_cage_write_file(refined, argv[2], &write, NULL);
  if (CAGEKIT_FAILED(status)) { exit_code = report_failure(context, status, "writing"); goto done; }

  info.struct_size = sizeof(info);
  status = cagekit_cage_get_info(refined, &info);
  if (CAGEKIT_FAILED(status)) { exit_code = report_failure(context, status, "statistics"); goto done; }
  printf("c_host: %s -> %s: level %u, %llu vertices, %llu quads, genus %lld\n", argv[1], argv[2], subdivide.levels,
         (unsigned long long)info.vertices, (unsigned long long)info.quads, (long long)info.genus);
  exit_code = 0;

done:
  cagekit_cage_release(refined);
  cagekit_cage_release(cage);
  cagekit_mesh_release(scan);
  cagekit_context_release(context);
  return exit_code;
}
