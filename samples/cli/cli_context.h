// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Shared plumbing of the CLI commands: argument parsing helpers, the CageKit context with a
// stderr progress bar, RAII holders for handles and the error convention (one line, exit 2).
#include <cagekit/cagekit.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

namespace cli {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;
constexpr int kExitUsage = 64;

// Thrown by commands; main() prints "cagekit: <message>" and exits with `code`.
struct Failure : std::runtime_error {
  Failure(int c, const std::string& message) : std::runtime_error(message), code(c) {}
  int code;
};

class Args {
 public:
  Args(int argc, char** argv, int first);
  // Removes and returns --name (a flag without value).
  bool flag(const std::string& name);
  // Removes --name VALUE; returns fallback when absent.
  std::string option(const std::string& name, const std::string& fallback);
  // Removes --name N; N must be an integer in [min, max]; fallback when absent.
  int integer(const std::string& name, int fallback, int min, int max);
  // Removes --name X; X must be a finite number in [min, max]; fallback when absent.
  double real(const std::string& name, double fallback, double min, double max);
  // Remaining positional arguments; fails on leftover --options.
  std::vector<std::string> positional(size_t min_count, size_t max_count, const char* usage);

 private:
  std::vector<std::string> args_;
};

class Session {
 public:
  explicit Session(bool quiet);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  cagekit_context context() const { return context_; }
  // Throws Failure(kExitBadInput, "<what>: <last error message>") when status is an error.
  void check(cagekit_status status, const std::string& what) const;
  // Ends the progress line on stderr (if one was started).
  void finish_progress() const;

 private:
  cagekit_context context_ = nullptr;
};

template <class H, void (*Release)(H)>
class Handle {
 public:
  Handle() = default;
  ~Handle() { Release(h_); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  H* out() { Release(h_); h_ = nullptr; return &h_; }
  H get() const { return h_; }

 private:
  H h_ = nullptr;
};

using Mesh = Handle<cagekit_mesh, cagekit_mesh_release>;
using Cage = Handle<cagekit_cage, cagekit_cage_release>;
using Binding = Handle<cagekit_binding, cagekit_binding_release>;
using Deformer = Handle<cagekit_cpu_deformer, cagekit_cpu_deformer_release>;

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// `text` as a JSON string literal, quotes included (nlohmann::json's escaping: control characters as
// \uXXXX, invalid UTF-8 bytes replaced by U+FFFD), for the commands' --json output.
std::string json_string(const std::string& text);

// The cage's control points, xyz interleaved (errors: Failure naming `what`).
std::vector<double> cage_positions(const Session& session, cagekit_cage cage, const std::string& what);

// The format of an output path (.obj .ply .off .drc); Failure(kExitUsage) for others and for .stl
// (read only).
cagekit_file_format format_from_extension(const std::string& path);

int command_info(Args& args);
int command_convert(Args& args);
int command_subdivide(Args& args);
int command_simplify(Args& args);
int command_remesh(Args& args);
// The remesher a command runs and its options.
struct RemeshSettings {
  bool quad = false;  // cagekit_mesh_remesh_quad; else cagekit_mesh_remesh_anisotropic
  cagekit_anisotropic_options anisotropic = CAGEKIT_ANISOTROPIC_OPTIONS_INIT;
  cagekit_quad_remesh_options quad_options = CAGEKIT_QUAD_REMESH_OPTIONS_INIT;
};
// What both remeshers' reports say, as remesh_json_fields prints it (quad: lines = arcs, no holes
// or alignment).
struct RemeshFigures {
  cagekit_remesh_quality quality{};
  uint64_t regions = 0, lines = 0, holes = 0;
  double mean_alignment_deg = 0.0;
};
// --method/--tolerance/--feature-angle/... (anisotropic) and --edge-length/--regions/--weights/...
// (quad) of remesh and `pipeline --method anisotropic|quad` (values out of range: Failure with
// kExitBadInput).
RemeshSettings parse_remesh_options(Args& args, const std::string& method);
// The method and its main settings as JSON fields (no braces): "method": "anisotropic",
// "tolerance": ... or "method": "quad", "edge_length": ..., "weights": [tri, pent, tjoint].
std::string remesh_method_json(const RemeshSettings& settings);
// The report's JSON fields (no braces): faces, vertices, quads_pct, ..., mean_alignment_deg.
std::string remesh_json_fields(const RemeshFigures& figures, const cagekit_approximation_error& error);
int command_demo(Args& args);
int command_fit(Args& args);
int command_pipeline(Args& args);
int command_bind(Args& args);
// --sharp-angle DEG of bind/deform: one bound vertex per smooth sector (-1 when absent).
double parse_sharp_angle(Args& args);
int command_deform(Args& args);
int command_bench_deform(Args& args);

}  // namespace cli

namespace cli {

// A file read as a cage when it is a valid control mesh, else as a plain mesh (so that info
// and convert also work on scans with defects); parse/I/O errors throw Failure.
struct LoadedInput {
  Cage cage;             // set when the file is a valid cage
  Mesh mesh;             // set otherwise
  std::string problem;   // why it is not a valid cage
};
void load_input(const Session& session, const std::string& path, LoadedInput* input);

}  // namespace cli
