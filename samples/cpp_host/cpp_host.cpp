// SPDX-License-Identifier: GPL-3.0-or-later
//
// cpp_host: the scan -> cage -> fit -> bind -> deform journey of a C++ plugin, using only the
// header-only C++ layer <cagekit/cagekit.hpp> (RAII handles, exceptions, std::vector results).
//   cpp_host SCAN OUTDIR [FACES]
// reads a scan (OBJ/PLY/OFF/STL/DRC), simplifies it to a quad-dominant cage of about FACES faces
// (default 60, thesis ch. 3), fits the cage's limit surface to the scan (ch. 7), binds the scan to
// the fitted cage (ch. 8) and deforms it after stretching the cage by 20 % along x. Writes
// OUTDIR/cage.obj (fitted, with creases), OUTDIR/deformed.obj (the edited scan) and prints one
// line of figures. Exit code 0 on success, 2 on bad input, 64 on usage errors.
#include <cagekit/cagekit.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 3 || argc > 4) {
    std::fprintf(stderr, "usage: cpp_host SCAN OUTDIR [FACES]\n");
    return 64;
  }
  const std::string scan_path = argv[1], out_dir = argv[2];
  const double faces = argc == 4 ? std::strtod(argv[3], nullptr) : 60.0;
  if (!(faces >= 1)) {
    std::fprintf(stderr, "cpp_host: FACES must be a number >= 1, not '%s'\n", argv[3]);
    return 64;
  }
  if (cagekit::abi_version() != CAGEKIT_ABI_VERSION) {
    std::fprintf(stderr, "cpp_host: built for CageKit ABI %d, loaded %u\n", CAGEKIT_ABI_VERSION, cagekit::abi_version());
    return 2;
  }
  try {
    cagekit::Context::Options options;
    std::string stage;
    options.progress = [&stage](const char* now, double) {  // one line per stage
      if (stage != now) std::fprintf(stderr, "cpp_host: %s\n", (stage = now).c_str());
      return true;  // false would cancel the running call
    };
    const cagekit::Context context = cagekit::Context::create(std::move(options));

    // Scan -> hierarchy -> the coarsest level with at most FACES faces -> quad-dominant cage.
    const cagekit::Mesh scan = context.read_mesh(scan_path);
    cagekit::Hierarchy hierarchy = scan.create_hierarchy();
    hierarchy.set_level(hierarchy.find_level(CAGEKIT_LEVEL_BY_FACES, faces));
    const cagekit::Cage cage = hierarchy.build_cage();

    // Fit the cage's limit surface to the scan.
    const cagekit::Cage::Fit fit = cage.fit(scan);
    const cagekit_fit_pass& first = fit.passes.front();
    const cagekit_fit_pass& best = fit.passes[fit.report.best_pass];
    fit.cage.write_file(out_dir + "/cage.obj");

    // Bind the scan to the fitted cage in local frames (the detail vectors keep their tangential
    // parts, so the unedited cage gives the scan back exactly).
    cagekit_bind_options bind = cagekit::defaults<cagekit_bind_options>();
    bind.mode = CAGEKIT_DISPLACEMENT_LOCAL_FRAME;
    cagekit::CpuDeformer deformer = fit.cage.bind(scan, bind).create_cpu_deformer();
    std::vector<double> control = fit.cage.mesh().positions();
    const std::vector<double> rest = deformer.deform(control).positions;
    const std::vector<double> original = scan.positions();
    double rest_error = 0.0;
    for (size_t i = 0; i < original.size(); ++i) rest_error = std::max(rest_error, std::fabs(rest[i] - original[i]));

    // Edit: stretch the cage by 20 % along x about its centre, and rebuild the scan over it.
    double lo = control[0], hi = control[0];
    for (size_t i = 0; i < control.size(); i += 3) lo = std::min(lo, control[i]), hi = std::max(hi, control[i]);
    const double centre = 0.5 * (lo + hi);
    for (size_t i = 0; i < control.size(); i += 3) control[i] = centre + 1.2 * (control[i] - centre);
    const cagekit::Deformed<double> edited = deformer.deform(control);
    const cagekit::Faces scan_faces = scan.faces();
    context.create_mesh(edited.positions, scan_faces.face_sizes, scan_faces.face_indices)
        .write_file(out_dir + "/deformed.obj");

    const cagekit_mesh_info info = fit.cage.info();
    const double diagonal = scan.info().bbox_diagonal;
    std::printf(
        "cpp_host: %s: cage %llu faces (%llu quads), fit RMS %.4g -> %.4g of the diagonal in %u passes, "
        "rest pose within %.3g of the diagonal, %u vertices deformed\n",
        scan_path.c_str(), (unsigned long long)info.faces, (unsigned long long)info.quads, first.rms_rel,
        best.rms_rel, static_cast<unsigned>(fit.passes.size() - 1), rest_error / diagonal, edited.vertex_count);
    return 0;
  } catch (const cagekit::Error& e) {
    std::fprintf(stderr, "cpp_host: %s failed (%s): %s\n", e.function(), cagekit::status_string(e.status()),
                 e.message());
    return 2;
  }
}
