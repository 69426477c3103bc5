// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Shared plumbing of the CLI commands: their options in CLI11, the CageKit context with a
// stderr progress bar (a cagekit::Context from <cagekit/cagekit.hpp>) and the error convention
// (one line, exit 2).
#include <cagekit/cagekit.hpp>

#include <chrono>
#include <functional>
#include <initializer_list>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace CLI {
class App;
}  // namespace CLI

namespace cli {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;
constexpr int kExitUsage = 64;

// Thrown by commands; main() prints "cagekit: <message>" (for kExitUsage with a hint to --help)
// and exits with `code`.
struct Failure : std::runtime_error {
  Failure(int c, const std::string& message) : std::runtime_error(message), code(c) {}
  int code;
};

// The options of a subcommand, each declared once (name, default, range, help) and used both to
// declare it in CLI11 (which parses the command line and writes --help) and to read it back.
struct FlagOption {
  const char* name;
  const char* help;
};
struct TextOption {
  const char* name;
  const char* fallback;  // when absent
  const char* value_name;
  const char* help;
};
template <class T>
struct RangedOption {
  const char* name;
  T fallback;  // when absent; outside [min, max]: "not given" (not shown as a default)
  T min, max;
  const char* value_name;
  const char* help;
};
using IntegerOption = RangedOption<int>;
using RealOption = RangedOption<double>;

// One subcommand's options and positionals in CLI11. CLI11 keeps every value as text; integer()
// and real() check it here, so that a value out of range is a Failure(kExitUsage) that the
// commands whose option values are input (fit, pipeline, remesh, bench-deform) report as bad
// input (kExitBadInput) instead.
class Options {
 public:
  explicit Options(CLI::App* app) : app_(app) {}
  Options(const Options&) = delete;
  Options& operator=(const Options&) = delete;
  CLI::App* app() const { return app_; }

  // Declaring (before parsing). A name already declared in this subcommand is shared: its first
  // declaration (help, default) stays, and each reader applies its own range.
  void add(const FlagOption& option);
  void add(const TextOption& option);
  void add(const IntegerOption& option);
  void add(const RealOption& option);
  void add_quiet();  // --quiet: no progress, warnings or summary lines
  void add_positional(const char* name, const char* help, bool required = true);

  // Reading (after parsing).
  bool given(const char* name) const;  // on the command line
  bool flag(const FlagOption& option) const { return given(option.name); }
  bool quiet() const { return given("--quiet"); }
  std::string text(const TextOption& option) const;
  // Failure(kExitUsage) naming the option unless the value is an integer in [min, max].
  int integer(const IntegerOption& option) const;
  // Failure(kExitUsage) naming the option unless the value is a finite number in [min, max].
  double real(const RealOption& option) const;
  std::string positional(const char* name) const;  // "" when an optional one is absent
  // Failure(kExitUsage) when one of `names` was given: "NAME does not apply <why>".
  void refuse(std::initializer_list<const char*> names, const std::string& why) const;

 private:
  CLI::App* app_;
  std::map<std::string, std::string> texts_;  // node-based: CLI11 keeps references into it
};

// The CageKit context of a command: warnings and progress on stderr unless quiet.
class Session {
 public:
  explicit Session(bool quiet);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  const cagekit::Context& context() const { return context_; }
  // Returns call()'s result; a cagekit::Error it throws becomes Failure(kExitBadInput,
  // "<what>: <SDK message>") (see fail()).
  template <class Call>
  auto run(const std::string& what, Call&& call) const -> decltype(call()) {
    try {
      return call();
    } catch (const cagekit::Error& error) {
      fail(error, what);
    }
  }
  // Throws Failure(kExitBadInput, "<what>: <message>") for a failed SDK call: one line, `what`
  // added unless the message starts with it (reader messages name their file).
  [[noreturn]] void fail(const cagekit::Error& error, const std::string& what) const;
  // Ends the progress line on stderr (if one was started).
  void finish_progress() const;

 private:
  cagekit::Context context_;
};

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// `text` as a JSON string literal, quotes included (nlohmann::json's escaping: control characters as
// \uXXXX, invalid UTF-8 bytes replaced by U+FFFD), for the commands' --json output.
std::string json_string(const std::string& text);

// The JSON reports are nlohmann::ordered_json objects (members in insertion order), written by
// json_text in the layout the CLI has always printed: one line, ", " and ": " separators (scripts
// grep for '"key": '); `top_separator` separates the top-level members (",\n " in report.json).
std::string json_text(const nlohmann::ordered_json& value, const char* top_separator = ", ");
// x rounded as the reports have always printed it with `format` ("%.9g", "%.3f", ...): an integer
// when that text is one ("40"), else the number the text reads as; null when x is not finite.
nlohmann::ordered_json json_rounded(double x, const char* format);

// The cage's control points, xyz interleaved (errors: Failure naming `what`).
std::vector<double> cage_positions(const Session& session, const cagekit::Cage& cage, const std::string& what);

// The format of an output path (.obj .ply .off .drc); Failure(kExitUsage) for others and for .stl
// (read only).
cagekit_file_format format_from_extension(const std::string& path);

// A subcommand of `cagekit`: add_* declares it and its options in the app; run() does the work
// once the command line is parsed and returns the exit code (errors throw Failure).
struct Command {
  CLI::App* app;
  std::function<int()> run;
};
Command add_info(CLI::App& cagekit);
Command add_convert(CLI::App& cagekit);
Command add_subdivide(CLI::App& cagekit);
Command add_simplify(CLI::App& cagekit);
Command add_remesh(CLI::App& cagekit);
Command add_fit(CLI::App& cagekit);
Command add_pipeline(CLI::App& cagekit);
Command add_bind(CLI::App& cagekit);
Command add_deform(CLI::App& cagekit);
Command add_bench_deform(CLI::App& cagekit);
Command add_render(CLI::App& cagekit);
Command add_demo(CLI::App& cagekit);
Command add_export_surfaces(CLI::App& cagekit);  // needs CAGEKIT_CLI_HAS_OCCT, else says so
Command add_batch(CLI::App& cagekit);

// The options of `cagekit pipeline` that shape its result (--method, --faces, the cage, fit and
// remesh options, --limit-levels, the conditioning, --no-fallback, --two-sided-refit; not --json or
// --quiet). `cagekit batch` declares the same ones and forwards those given to each child pipeline.
void add_pipeline_options(Options& options);

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
  int64_t reseeded_regions = -1;  // quad: the report's reseeded_regions (-1: anisotropic, not written)
  double mean_alignment_deg = 0.0;
};
// The options of remesh and `pipeline --method anisotropic|quad`: --tolerance, --max-face-valence,
// --curvature-radius (anisotropic), --edge-length, --regions, --region-tolerance, --weights,
// --refinement-passes (quad), --feature-angle and --threads (both).
void add_remesh_options(Options& options);
// The settings of `method` ("anisotropic" or "quad"); an unknown method and values out of range
// are Failure(kExitBadInput).
RemeshSettings parse_remesh_options(const Options& options, const std::string& method);
// Failure(kExitUsage) when an option of the other method was given (--tolerance excepted: it is
// also the fit's, in the pipeline).
void refuse_other_remesh_options(const Options& options, const RemeshSettings& settings);
// The method and its main settings: {"method": "anisotropic", "tolerance": ...} or {"method": "quad",
// "edge_length": ..., "weights": [tri, pent, tjoint], "refinement_passes": ...}.
nlohmann::ordered_json remesh_method_json(const RemeshSettings& settings);
// The report's figures: {"faces", "vertices", "quads_pct", ..., "lines", "holes"}.
nlohmann::ordered_json remesh_json_fields(const RemeshFigures& figures, const cagekit_approximation_error& error);
// --sharp-angle DEG of bind and deform: one bound vertex per smooth sector.
void add_sharp_angle(Options& options);
// Its value, -1 when absent; not a number of degrees in [0, 180]: Failure(kExitBadInput).
double parse_sharp_angle(const Options& options);

}  // namespace cli

namespace cli {

// A file read as a cage when it is a valid control mesh, else as a plain mesh (so that info
// and convert also work on scans with defects); parse/I/O errors throw Failure.
struct LoadedInput {
  cagekit::Cage cage;    // set when the file is a valid cage
  cagekit::Mesh mesh;    // set otherwise
  std::string problem;   // why it is not a valid cage
};
void load_input(const Session& session, const std::string& path, LoadedInput* input);

}  // namespace cli
