// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli_context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include <nlohmann/json.hpp>
#include <unistd.h>

namespace cli {

Args::Args(int argc, char** argv, int first) {
  for (int i = first; i < argc; ++i) args_.emplace_back(argv[i]);
}

bool Args::flag(const std::string& name) {
  auto it = std::find(args_.begin(), args_.end(), name);
  if (it == args_.end()) return false;
  args_.erase(it);
  return true;
}

std::string Args::option(const std::string& name, const std::string& fallback) {
  auto it = std::find(args_.begin(), args_.end(), name);
  if (it == args_.end()) return fallback;
  if (it + 1 == args_.end()) throw Failure(kExitUsage, name + " needs a value");
  std::string value = *(it + 1);
  args_.erase(it, it + 2);
  return value;
}

int Args::integer(const std::string& name, int fallback, int min, int max) {
  const std::string text = option(name, "");
  if (text.empty()) return fallback;
  size_t used = 0;
  long value = min - 1L;
  try {
    value = std::stol(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || value < min || value > max)
    throw Failure(kExitUsage, name + " must be an integer in " + std::to_string(min) + ".." + std::to_string(max) +
                                  ", not '" + text + "'");
  return static_cast<int>(value);
}

double Args::real(const std::string& name, double fallback, double min, double max) {
  const std::string text = option(name, "");
  if (text.empty()) return fallback;
  size_t used = 0;
  double value = min - 1.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !(value >= min && value <= max))
    throw Failure(kExitUsage, name + " must be a number in [" + std::to_string(min) + ", " + std::to_string(max) +
                                  "], not '" + text + "'");
  return value;
}

std::vector<std::string> Args::positional(size_t min_count, size_t max_count, const char* usage) {
  for (const std::string& a : args_)
    if (a.size() > 1 && a[0] == '-' && a[1] == '-') throw Failure(kExitUsage, "unknown option " + a + "\nusage: " + usage);
  if (args_.size() < min_count || args_.size() > max_count) throw Failure(kExitUsage, std::string("usage: ") + usage);
  return args_;
}

namespace {

struct ProgressState {
  bool active = false;  // a \r progress line is open on the terminal
  std::string stage;
  int last_percent = -1;
};
ProgressState g_progress;

// On a terminal one line is redrawn with \r as the percentage moves; into a file or a pipe (a log,
// a batch job) each stage is one line, written when it starts.
int print_progress(void* terminal, const char* stage, double fraction) {
  const int percent = static_cast<int>(fraction * 100.0 + 0.5);
  if (terminal == nullptr) {
    if (g_progress.stage != stage) {
      std::fprintf(stderr, "cagekit: stage: %s\n", stage);
      g_progress.stage = stage;
    }
    return 1;
  }
  if (g_progress.stage != stage || percent != g_progress.last_percent) {
    std::fprintf(stderr, "\r%-12s %3d%%", stage, percent);
    std::fflush(stderr);
    g_progress.active = true;
    g_progress.stage = stage;
    g_progress.last_percent = percent;
  }
  return 1;
}

void print_log(void*, cagekit_log_level level, const char* message) {
  if (level >= CAGEKIT_LOG_ERROR) return;  // errors are printed once, by main()
  if (g_progress.active) std::fputc('\n', stderr), g_progress.active = false;
  std::fprintf(stderr, "cagekit: warning: %s\n", message);
}

}  // namespace

Session::Session(bool quiet) {
  cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
  desc.log = quiet ? nullptr : print_log;
  desc.progress = quiet ? nullptr : print_progress;
  static int terminal_marker;
  desc.progress_user_data = isatty(fileno(stderr)) ? &terminal_marker : nullptr;
  if (cagekit_context_create(&desc, &context_) != CAGEKIT_SUCCESS)
    throw Failure(kExitBadInput, std::string("cannot start CageKit: ") + cagekit_last_error_message(nullptr));
}

Session::~Session() {
  finish_progress();
  cagekit_context_release(context_);
}

void Session::finish_progress() const {
  if (g_progress.active) {
    std::fputc('\n', stderr);
    g_progress = ProgressState{};
  }
}

void Session::check(cagekit_status status, const std::string& what) const {
  if (CAGEKIT_SUCCEEDED(status)) return;
  finish_progress();
  std::string message = cagekit_last_error_message(context_);
  if (message.empty()) message = cagekit_status_string(status);
  // Reader messages already start with the file name; others get the context added.
  if (message.rfind(what, 0) != 0) message = what + ": " + message;
  // One line: multi-line diagnostics (validation summaries) are joined.
  while (!message.empty() && message.back() == '\n') message.pop_back();
  for (size_t at = message.find('\n'); at != std::string::npos; at = message.find('\n', at))
    message.replace(at, 1, "; ");
  throw Failure(kExitBadInput, message);
}

cagekit_file_format format_from_extension(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == "obj") return CAGEKIT_FORMAT_OBJ;
  if (ext == "ply") return CAGEKIT_FORMAT_PLY;
  if (ext == "off") return CAGEKIT_FORMAT_OFF;
  if (ext == "drc") return CAGEKIT_FORMAT_DRACO;
  // Output files only: STL is read only, refused before any work is done.
  if (ext == "stl") throw Failure(kExitUsage, path + ": STL: writing is not supported (use .obj, .ply, .off or .drc)");
  throw Failure(kExitUsage, path + ": unknown file extension (use .obj, .ply, .off or .drc)");
}

}  // namespace cli

namespace cli {

void load_input(const Session& session, const std::string& path, LoadedInput* input) {
  const cagekit_status status = cagekit_cage_read_file(session.context(), path.c_str(), CAGEKIT_FORMAT_AUTO,
                                                       input->cage.out());
  if (status != CAGEKIT_ERROR_INVALID_MESH) {
    session.check(status, path);
    return;
  }
  input->problem = cagekit_last_error_message(session.context());
  session.check(cagekit_mesh_read_file(session.context(), path.c_str(), CAGEKIT_FORMAT_AUTO, input->mesh.out()), path);
}

std::vector<double> cage_positions(const Session& session, cagekit_cage cage, const std::string& what) {
  Mesh mesh;
  session.check(cagekit_cage_get_mesh(cage, mesh.out()), what);
  uint32_t count = 0;
  session.check(cagekit_mesh_get_positions(mesh.get(), CAGEKIT_SCALAR_FLOAT64, 0, &count, nullptr), what);
  std::vector<double> xyz(3 * size_t(count));
  session.check(cagekit_mesh_get_positions(mesh.get(), CAGEKIT_SCALAR_FLOAT64, count, &count, xyz.data()), what);
  return xyz;
}

std::string json_string(const std::string& text) {
  return nlohmann::json(text).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace cli
