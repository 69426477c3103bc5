// SPDX-License-Identifier: GPL-3.0-or-later
// cagekit — command-line front end of the CageKit SDK.
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <string>

#include "cli_context.h"

namespace {

const char* kUsage =
    "usage: cagekit COMMAND [ARGS]\n"
    "commands:\n"
    "  info IN [--json]                         statistics of a mesh or cage file\n"
    "  convert IN OUT [--bits N] [--ascii]      convert between .obj .ply .off .drc, also from .stl (read only;\n"
    "                                           keeps cage tags in .obj/.drc)\n"
    "  subdivide IN OUT --levels N [--limit]    uniform Catmull-Clark refinement with creases\n"
    "  simplify IN OUT (--faces N | --vertices N) [--cage] [--clusters FILE.ply] [--json]\n"
    "      [--creases sharp-input|cluster-angle] [--feature-angle DEG] [--crease-angle DEG] [--input-crease-angle DEG]\n"
    "                                           creases where the scan is sharp (input edges above DEG=40, noise\n"
    "                                           filtered), or by the clusters' normals (thesis rule, DEG=30)\n"
    "                                           structure-preserving simplification (thesis ch. 3); --cage: quad-dominant cage\n"
    "  remesh IN OUT --method anisotropic [--tolerance REL] [--feature-angle DEG] [--max-face-valence N]\n"
    "      [--curvature-radius REL] [--threads N] [--json]\n"
    "                                           curvature-line remeshing (thesis ch. 5): quad-dominant, edges along\n"
    "                                           the principal directions; OUT keeps feature lines as creases\n"
    "  remesh IN OUT --method quad [--edge-length REL] [--regions N] [--weights TRI,PENT,TJOINT] [--refinement-passes N]\n"
    "      [--region-tolerance T] [--feature-angle DEG] [--threads N] [--json]\n"
    "                                           two-step quad-dominant remeshing (thesis ch. 6): N regions (0: by\n"
    "                                           tolerance), boundary samples REL of the diagonal apart; OUT keeps\n"
    "                                           sharp region boundaries as creases\n"
    "  fit SCAN CAGE OUT [--passes N] [--tolerance T] [--projection exact|linear] [--fairing F] [--keep-creases]\n"
    "      [--threads N] [--json]               fit the cage's limit surface to the scan's vertices (thesis ch. 7);\n"
    "                                           OUT keeps the cage's connectivity and crease tags\n"
    "  pipeline SCAN OUTDIR (--faces N | --vertices N) [--method simplify] [--creases sharp-input|cluster-angle]\n"
    "      [--feature-angle DEG] [--crease-angle DEG] [--input-crease-angle DEG] [--passes N]\n"
    "      [--tolerance T] [--projection exact|linear] [--fairing F] [--keep-creases] [--limit-levels L] [--json]\n"
    "                                           simplify -> quad-dominant cage with creases -> fit; writes\n"
    "                                           OUTDIR/cage.obj (fitted), limit.obj (its limit, L=3 levels), report.json\n"
    "  pipeline SCAN OUTDIR --method anisotropic [--tolerance REL] [--feature-angle DEG] [--fit-tolerance T] ...\n"
    "                                           the same with curvature-line remeshing (thesis ch. 5) as step 1\n"
    "  pipeline SCAN OUTDIR --method quad [--edge-length REL] [--regions N] [--weights TRI,PENT,TJOINT] [--refinement-passes N]\n"
    "      [--fit-tolerance T] ...              the same with two-step quad-dominant remeshing (thesis ch. 6)\n"
    "      every pipeline: [--no-repair] [--components all|largest] [--weld-tolerance REL] [--no-fallback]\n"
    "                                           the scan is conditioned first; a result that is not good is an\n"
    "                                           error (exit 2), after a fallback to simplify unless --no-fallback\n"
    "  bind SCAN CAGE OUT.ckb [--local-frame] [--exact-normals] [--sharp-angle DEG] [--threads N] [--json]\n"
    "                                           bind the scan to the cage's limit surface (thesis ch. 8), save it\n"
    "  deform SCAN (CAGE | BINDING.ckb) EDITED_CAGE OUT [--local-frame] [--sharp-angle DEG] [--json]\n"
    "                                           bind the scan (or load its saved binding) and rebuild it over the\n"
    "                                           edited cage (same connectivity), details kept; --sharp-angle:\n"
    "                                           one vertex per smooth sector at sharp edges (its own normal)\n"
    "  bench-deform SCAN CAGE [--frames N] [--moved K] [--threads N] [--vertex-order scan|deformer] [--json]\n"
    "                                           frames per second of the CPU deformer (full and K moved points)\n"
    "  demo [OUTDIR]                            run the pipeline on a generated noisy scan of a CAD-like part\n"
    "  version                                  print the library version\n"
    "options: --quiet (no progress on stderr)\n"
    "exit codes: 0 ok, 2 bad input (one line on stderr names the file and the problem; for fit, pipeline and\n"
    "            bench-deform also option values out of range), 64 usage\n";

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
    std::fputs(kUsage, argc < 2 ? stderr : stdout);
    return argc < 2 ? cli::kExitUsage : 0;
  }
  const std::string command = argv[1];
  try {
    cli::Args args(argc, argv, 2);
    if (command == "info") return cli::command_info(args);
    if (command == "convert") return cli::command_convert(args);
    if (command == "subdivide") return cli::command_subdivide(args);
    if (command == "simplify") return cli::command_simplify(args);
    if (command == "remesh") return cli::command_remesh(args);
    if (command == "fit") return cli::command_fit(args);
    if (command == "pipeline") return cli::command_pipeline(args);
    if (command == "bind") return cli::command_bind(args);
    if (command == "deform") return cli::command_deform(args);
    if (command == "bench-deform") return cli::command_bench_deform(args);
    if (command == "demo") return cli::command_demo(args);
    if (command == "version") {
      std::printf("cagekit %s (ABI %u)\n", cagekit_version_string(), cagekit_abi_version());
      return 0;
    }
    std::fprintf(stderr, "cagekit: unknown command '%s'\n%s", command.c_str(), kUsage);
    return cli::kExitUsage;
  } catch (const cli::Failure& f) {
    std::fprintf(stderr, "cagekit: %s\n", f.what());
    return f.code;
  } catch (const std::bad_alloc&) {
    // Allocation failures outside the C API (which reports them as OUT_OF_MEMORY itself).
    std::fprintf(stderr, "cagekit: out of memory\n");
    return cli::kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cagekit: %s\n", e.what());
    return 1;
  }
}
