// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli_context.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <cstdio>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <unistd.h>

namespace cli {

namespace {

std::string number_text(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", x);
  return buffer;
}

// The option's text in CLI11; the value is checked by the reader.
CLI::Option* add_text_option(CLI::App* app, std::map<std::string, std::string>& texts, const char* name,
                             const char* value_name, const std::string& help) {
  return app->add_option(name, texts[name], help)->type_name(value_name);
}

}  // namespace

void Options::add(const FlagOption& option) {
  if (app_->get_option_no_throw(option.name)) return;
  app_->add_flag(option.name, option.help);
}

void Options::add(const TextOption& option) {
  if (app_->get_option_no_throw(option.name)) return;
  CLI::Option* o = add_text_option(app_, texts_, option.name, option.value_name, option.help);
  if (*option.fallback) o->default_str(option.fallback);
}

void Options::add(const IntegerOption& option) {
  if (app_->get_option_no_throw(option.name)) return;
  CLI::Option* o = add_text_option(app_, texts_, option.name, option.value_name,
                                   std::string(option.help) + " (" + std::to_string(option.min) + ".." +
                                       std::to_string(option.max) + ")");
  if (option.fallback >= option.min && option.fallback <= option.max) o->default_str(std::to_string(option.fallback));
}

void Options::add(const RealOption& option) {
  if (app_->get_option_no_throw(option.name)) return;
  CLI::Option* o = add_text_option(app_, texts_, option.name, option.value_name,
                                   std::string(option.help) + " [" + number_text(option.min) + ", " +
                                       number_text(option.max) + "]");
  if (option.fallback >= option.min && option.fallback <= option.max) o->default_str(number_text(option.fallback));
}

void Options::add_quiet() { add(FlagOption{"--quiet", "no progress, warnings or summary lines"}); }

void Options::add_positional(const char* name, const char* help, bool required) {
  CLI::Option* o = app_->add_option(name, texts_[name], help)->type_name("");
  if (required) o->required();
}

bool Options::given(const char* name) const {
  const CLI::Option* o = app_->get_option_no_throw(name);
  return o != nullptr && o->count() > 0;
}

std::string Options::text(const TextOption& option) const {
  return given(option.name) ? texts_.at(option.name) : std::string(option.fallback);
}

std::string Options::positional(const char* name) const {
  const auto it = texts_.find(name);
  return it == texts_.end() ? std::string() : it->second;
}

int Options::integer(const IntegerOption& option) const {
  const std::string text = given(option.name) ? texts_.at(option.name) : std::string();
  if (text.empty()) return option.fallback;
  const std::string name = option.name;
  const int min = option.min, max = option.max;
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

double Options::real(const RealOption& option) const {
  const std::string text = given(option.name) ? texts_.at(option.name) : std::string();
  if (text.empty()) return option.fallback;
  const std::string name = option.name;
  const double min = option.min, max = option.max;
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

void Options::refuse(std::initializer_list<const char*> names, const std::string& why) const {
  for (const char* name : names)
    if (given(name)) throw Failure(kExitUsage, std::string(name) + " does not apply " + why);
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
bool print_progress(bool terminal, const char* stage, double fraction) {
  const int percent = static_cast<int>(fraction * 100.0 + 0.5);
  if (!terminal) {
    if (g_progress.stage != stage) {
      std::fprintf(stderr, "cagekit: stage: %s\n", stage);
      g_progress.stage = stage;
    }
    return true;
  }
  if (g_progress.stage != stage || percent != g_progress.last_percent) {
    std::fprintf(stderr, "\r%-12s %3d%%", stage, percent);
    std::fflush(stderr);
    g_progress.active = true;
    g_progress.stage = stage;
    g_progress.last_percent = percent;
  }
  return true;
}

void print_log(cagekit_log_level level, const char* message) {
  if (level >= CAGEKIT_LOG_ERROR) return;  // errors are printed once, by main()
  if (g_progress.active) std::fputc('\n', stderr), g_progress.active = false;
  std::fprintf(stderr, "cagekit: warning: %s\n", message);
}

cagekit::Context create_context(bool quiet) {
  cagekit::ContextOptions options;
  if (!quiet) {
    const bool terminal = isatty(fileno(stderr)) != 0;
    options.log = print_log;
    // Never throws: nothing to cross the C ABI (cagekit.hpp would carry it across anyway).
    options.progress = [terminal](const char* stage, double fraction) {
      return print_progress(terminal, stage, fraction);
    };
  }
  try {
    return cagekit::Context::create(std::move(options));
  } catch (const cagekit::Error& error) {
    throw Failure(kExitBadInput, std::string("cannot start CageKit: ") + error.message());
  }
}

}  // namespace

Session::Session(bool quiet) : context_(create_context(quiet)) {}

Session::~Session() { finish_progress(); }

void Session::finish_progress() const {
  if (g_progress.active) {
    std::fputc('\n', stderr);
    g_progress = ProgressState{};
  }
}

void Session::fail(const cagekit::Error& error, const std::string& what) const {
  finish_progress();
  // Reader messages already start with the file name; others get the context added.
  std::string message = error.message();
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
  try {
    input->cage = session.context().read_cage(path);
    return;
  } catch (const cagekit::Error& error) {
    if (error.status() != CAGEKIT_ERROR_INVALID_MESH) session.fail(error, path);
    input->problem = error.message();
  }
  input->mesh = session.run(path, [&] { return session.context().read_mesh(path); });
}

std::vector<double> cage_positions(const Session& session, const cagekit::Cage& cage, const std::string& what) {
  return session.run(what, [&] { return cage.mesh().positions(); });
}

std::string json_string(const std::string& text) {
  return nlohmann::json(text).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

namespace {

void write_json(std::string& out, const nlohmann::ordered_json& value, const char* separator) {
  if (value.is_object()) {
    out += '{';
    bool first = true;
    for (const auto& member : value.items()) {
      if (!first) out += separator;
      first = false;
      out += json_string(member.key());
      out += ": ";
      write_json(out, member.value(), ", ");
    }
    out += '}';
  } else if (value.is_array()) {
    out += '[';
    for (size_t i = 0; i < value.size(); ++i) {
      if (i) out += ", ";
      write_json(out, value[i], ", ");
    }
    out += ']';
  } else {
    out += value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  }
}

}  // namespace

std::string json_text(const nlohmann::ordered_json& value, const char* top_separator) {
  std::string out;
  write_json(out, value, top_separator);
  return out;
}

nlohmann::ordered_json json_rounded(double x, const char* format) {
  if (!std::isfinite(x)) return nullptr;
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, x);
  // Written as printf wrote it: "40" stays an integer (not 40.0), "0.5" a number with a fraction.
  if (std::strspn(buffer, "-0123456789") == std::strlen(buffer) && std::strlen(buffer) < 19)
    return std::strtoll(buffer, nullptr, 10);
  return std::strtod(buffer, nullptr);
}

}  // namespace cli
