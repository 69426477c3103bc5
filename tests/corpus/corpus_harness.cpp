// SPDX-License-Identifier: GPL-3.0-or-later
// corpus_harness: runs `cagekit pipeline` with every method on every mesh of the corpus (issue 18),
// each run in a child process with a time and a memory limit, judges each result by the issue's
// definition of "good", and writes results.json, results.md and one summary line per method. With
// --baseline it fails on results worse than a committed baseline (see README.md for the rules).
//
// The harness reads the meshes and cages it judges through the public C API only; the runs
// themselves go through the CLI in children (samples/cli/job_runner.h), so a crash or a hang of
// the SDK ends one record, not the harness.
#include <cagekit/cagekit.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "crease_metrics.h"
#include "job_runner.h"
#include "thumbnails.h"

#ifndef CAGEKIT_MESH_CLASSES
#define CAGEKIT_MESH_CLASSES ""
#endif

namespace fs = std::filesystem;

namespace {

// ------------------------------------------------------------------------------------------
// A small JSON reader (report.json and the baseline): objects, arrays, strings, numbers,
// true/false/null. Enough for files this project writes; throws std::runtime_error otherwise.

struct Json {
  enum Type { kNull, kBool, kNumber, kString, kArray, kObject } type = kNull;
  bool boolean = false;
  double number = 0.0;
  std::string text;
  std::vector<Json> items;
  std::vector<std::pair<std::string, Json>> members;

  const Json* get(const std::string& key) const {
    if (type != kObject) return nullptr;
    for (const auto& m : members)
      if (m.first == key) return &m.second;
    return nullptr;
  }
  // The number at a path of keys, when every step exists and it is a number.
  std::optional<double> number_at(std::initializer_list<const char*> path) const {
    const Json* at = this;
    for (const char* key : path) {
      at = at->get(key);
      if (!at) return std::nullopt;
    }
    if (at->type == kNumber) return at->number;
    return std::nullopt;
  }
};

class JsonParser {
 public:
  explicit JsonParser(const std::string& text) : s_(text) {}
  Json parse() {
    Json value = parse_value();
    skip_space();
    if (at_ != s_.size()) fail("trailing characters");
    return value;
  }

 private:
  [[noreturn]] void fail(const char* what) const {
    throw std::runtime_error(std::string("JSON: ") + what + " at byte " + std::to_string(at_));
  }
  void skip_space() {
    while (at_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[at_]))) ++at_;
  }
  bool take(const char* word) {
    const size_t n = std::strlen(word);
    if (s_.compare(at_, n, word) != 0) return false;
    at_ += n;
    return true;
  }
  Json parse_value() {
    if (++depth_ > 200) fail("nesting too deep");
    skip_space();
    if (at_ >= s_.size()) fail("unexpected end");
    Json v;
    const char c = s_[at_];
    if (c == '{') {
      v.type = Json::kObject;
      ++at_;
      skip_space();
      if (at_ < s_.size() && s_[at_] == '}') {
        ++at_;
      } else {
        for (;;) {
          skip_space();
          if (at_ >= s_.size() || s_[at_] != '"') fail("expected a key");
          std::string key = parse_string();
          skip_space();
          if (at_ >= s_.size() || s_[at_] != ':') fail("expected ':'");
          ++at_;
          v.members.emplace_back(std::move(key), parse_value());
          skip_space();
          if (at_ < s_.size() && s_[at_] == ',') { ++at_; continue; }
          if (at_ < s_.size() && s_[at_] == '}') { ++at_; break; }
          fail("expected ',' or '}'");
        }
      }
    } else if (c == '[') {
      v.type = Json::kArray;
      ++at_;
      skip_space();
      if (at_ < s_.size() && s_[at_] == ']') {
        ++at_;
      } else {
        for (;;) {
          v.items.push_back(parse_value());
          skip_space();
          if (at_ < s_.size() && s_[at_] == ',') { ++at_; continue; }
          if (at_ < s_.size() && s_[at_] == ']') { ++at_; break; }
          fail("expected ',' or ']'");
        }
      }
    } else if (c == '"') {
      v.type = Json::kString;
      v.text = parse_string();
    } else if (take("true")) {
      v.type = Json::kBool;
      v.boolean = true;
    } else if (take("false")) {
      v.type = Json::kBool;
    } else if (take("null")) {
      v.type = Json::kNull;
    } else {
      const char* begin = s_.c_str() + at_;
      char* end = nullptr;
      v.number = std::strtod(begin, &end);
      if (end == begin) fail("unexpected character");
      v.type = Json::kNumber;
      at_ += size_t(end - begin);
    }
    --depth_;
    return v;
  }
  std::string parse_string() {
    ++at_;  // opening quote
    std::string out;
    while (at_ < s_.size() && s_[at_] != '"') {
      char c = s_[at_++];
      if (c == '\\') {
        if (at_ >= s_.size()) fail("unexpected end in a string");
        c = s_[at_++];
        switch (c) {
          case 'n': out += '\n'; break;
          case 't': out += '\t'; break;
          case 'r': out += '\r'; break;
          case 'b': out += '\b'; break;
          case 'f': out += '\f'; break;
          case 'u': {
            if (at_ + 4 > s_.size()) fail("bad \\u escape");
            const unsigned code = unsigned(std::stoul(s_.substr(at_, 4), nullptr, 16));
            at_ += 4;
            if (code < 0x80) {
              out += char(code);
            } else if (code < 0x800) {
              out += char(0xC0 | (code >> 6));
              out += char(0x80 | (code & 0x3F));
            } else {
              out += char(0xE0 | (code >> 12));
              out += char(0x80 | ((code >> 6) & 0x3F));
              out += char(0x80 | (code & 0x3F));
            }
            break;
          }
          default: out += c;
        }
      } else {
        out += c;
      }
    }
    if (at_ >= s_.size()) fail("unterminated string");
    ++at_;
    return out;
  }
  const std::string& s_;
  size_t at_ = 0;
  int depth_ = 0;
};

std::string json_escape(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof(buffer), "\\u%04x", unsigned(static_cast<unsigned char>(c)));
          out += buffer;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

// Writes a parsed value back (to carry report objects such as "conditioning" into results.json).
std::string json_write(const Json& v) {
  switch (v.type) {
    case Json::kNull: return "null";
    case Json::kBool: return v.boolean ? "true" : "false";
    case Json::kNumber: {
      if (!std::isfinite(v.number)) return "null";
      char buffer[40];
      std::snprintf(buffer, sizeof(buffer), "%.9g", v.number);
      return buffer;
    }
    case Json::kString: return json_escape(v.text);
    case Json::kArray: {
      std::string out = "[";
      for (size_t i = 0; i < v.items.size(); ++i) out += (i ? ", " : "") + json_write(v.items[i]);
      return out + "]";
    }
    case Json::kObject: {
      std::string out = "{";
      for (size_t i = 0; i < v.members.size(); ++i)
        out += (i ? ", " : "") + json_escape(v.members[i].first) + ": " + json_write(v.members[i].second);
      return out + "}";
    }
  }
  return "null";
}

std::string json_number(std::optional<double> x, const char* format = "%.6g") {
  if (!x || !std::isfinite(*x)) return "null";
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), format, *x);
  return buffer;
}

std::string read_whole_file(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
  std::string text;
  char buffer[65536];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof(buffer), f)) > 0) text.append(buffer, n);
  std::fclose(f);
  return text;
}

void write_whole_file(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp";
  FILE* f = std::fopen(temporary.c_str(), "wb");
  if (!f) throw std::runtime_error(path + ": cannot write: " + std::strerror(errno));
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) != 0 || !ok || std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw std::runtime_error(path + ": cannot write");
  }
}

// ------------------------------------------------------------------------------------------
// Options

struct Options {
  std::string cli;
  std::string out;
  std::string corpus = CAGEKIT_CORPUS_DIR;
  std::string classes = CAGEKIT_MESH_CLASSES;  // mesh_classes.txt of the source tree
  bool classes_given = false;                  // --classes: the file must exist
  std::vector<std::string> methods = {"simplify", "quad", "anisotropic"};
  int jobs = 2;
  double timeout = 120.0;
  double memory_mb = 4096.0;
  std::string list;
  std::vector<std::string> inputs;
  std::string baseline;
  std::string write_baseline;
  bool summary_only = false;
  bool thumbnails = false;  // --thumbnails: OUT/index.html, OUT/thumbnails/ (thumbnails.h)
  std::string command_line;
};

const char* kUsage =
    "usage: corpus_harness --cli PATH/cagekit --out DIR [--methods simplify,quad,anisotropic] [--jobs N]\n"
    "         [--timeout S] [--memory-mb M] [--corpus DIR] [--list FILE | MESH_OR_FOLDER...]\n"
    "         [--baseline FILE.json] [--write-baseline FILE.json] [--summary-only] [--classes FILE] [--thumbnails]\n"
    "  Inputs default to CORPUS/cgal and CORPUS/stl; --list names one mesh per line, relative to --corpus.\n"
    "  --classes: 'cad|organic PATH' per line (PATH relative to --corpus), default tests/corpus/mesh_classes.txt.\n"
    "  --thumbnails: also OUT/index.html (the table, each row linked to its picture) and OUT/thumbnails/\n"
    "    (one 240 x 200 PNG per mesh and method: the limit surface coloured by its two-sided distance to the\n"
    "    scan, titled with status and error; pages of 30). A picture that cannot be drawn is a placeholder.\n"
    "  Exit: 0 done (and no regression against --baseline), 1 regression against the baseline,\n"
    "        64 usage, 77 no corpus / no input to run (a skip for ctest).\n";

[[noreturn]] void usage_error(const std::string& message) {
  std::fprintf(stderr, "corpus_harness: %s\n%s", message.c_str(), kUsage);
  std::exit(64);
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 0; i < argc; ++i) o.command_line += (i ? " " : "") + std::string(argv[i]);
  auto value = [&](int& i) -> std::string {
    if (i + 1 >= argc) usage_error(std::string(argv[i]) + " needs a value");
    return argv[++i];
  };
  auto real = [&](int& i, double min, double max) {
    const std::string name = argv[i];
    const std::string text = value(i);
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !(x >= min && x <= max))
      usage_error(name + " must be a number in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
    return x;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--cli") o.cli = value(i);
    else if (a == "--out") o.out = value(i);
    else if (a == "--corpus") o.corpus = value(i);
    else if (a == "--list") o.list = value(i);
    else if (a == "--classes") o.classes = value(i), o.classes_given = true;
    else if (a == "--baseline") o.baseline = value(i);
    else if (a == "--write-baseline") o.write_baseline = value(i);
    else if (a == "--summary-only") o.summary_only = true;
    else if (a == "--thumbnails") o.thumbnails = true;
    else if (a == "--jobs") o.jobs = int(real(i, 1, 256));
    else if (a == "--timeout") o.timeout = real(i, 1, 86400);
    else if (a == "--memory-mb") o.memory_mb = real(i, 64, 1 << 20);
    else if (a == "--methods") {
      o.methods.clear();
      std::stringstream list(value(i));
      std::string m;
      while (std::getline(list, m, ',')) {
        if (m != "simplify" && m != "quad" && m != "anisotropic")
          usage_error("unknown method '" + m + "' (simplify, quad, anisotropic)");
        o.methods.push_back(m);
      }
      if (o.methods.empty()) usage_error("--methods is empty");
    } else if (a == "--help" || a == "-h") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (a.size() > 1 && a[0] == '-') {
      usage_error("unknown option " + a);
    } else {
      o.inputs.push_back(a);
    }
  }
  if (o.cli.empty()) usage_error("--cli is required");
  if (o.out.empty()) usage_error("--out is required");
  if (!o.list.empty() && !o.inputs.empty()) usage_error("give --list or meshes, not both");
  return o;
}

// ------------------------------------------------------------------------------------------
// Inputs

bool is_mesh_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".off" || ext == ".obj" || ext == ".ply" || ext == ".stl";
}

struct Input {
  std::string path;  // as given to the CLI
  std::string name;  // relative to the corpus folder when inside it ("cgal/bunny00.off")
};

std::string display_name(const fs::path& path, const fs::path& corpus) {
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(path, ec);
  const fs::path root = fs::weakly_canonical(corpus, ec);
  if (!ec) {
    const fs::path relative = canonical.lexically_relative(root);
    if (!relative.empty() && *relative.begin() != "..") return relative.generic_string();
  }
  return path.generic_string();
}

// Returns false when nothing could be found (corpus absent).
bool collect_inputs(const Options& o, std::vector<Input>* inputs) {
  std::vector<fs::path> paths;
  auto add_folder = [&](const fs::path& dir) {
    std::vector<fs::path> found;
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.is_regular_file() && is_mesh_file(entry.path())) found.push_back(entry.path());
    std::sort(found.begin(), found.end());
    paths.insert(paths.end(), found.begin(), found.end());
  };
  if (!o.list.empty()) {
    if (!fs::is_directory(o.corpus)) {
      std::printf("corpus_harness: the corpus folder %s is absent: skipped\n", o.corpus.c_str());
      return false;
    }
    std::stringstream lines(read_whole_file(o.list));
    std::string line;
    while (std::getline(lines, line)) {
      const size_t hash = line.find('#');
      if (hash != std::string::npos) line.erase(hash);
      while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
      size_t first = 0;
      while (first < line.size() && std::isspace(static_cast<unsigned char>(line[first]))) ++first;
      line.erase(0, first);
      if (line.empty()) continue;
      const fs::path p = fs::path(line).is_absolute() ? fs::path(line) : fs::path(o.corpus) / line;
      if (!fs::is_regular_file(p)) {
        std::fprintf(stderr, "corpus_harness: %s (from %s) is missing: skipped\n", p.string().c_str(), o.list.c_str());
        continue;
      }
      paths.push_back(p);
    }
  } else if (!o.inputs.empty()) {
    for (const std::string& in : o.inputs) {
      if (fs::is_directory(in)) add_folder(in);
      else if (fs::is_regular_file(in)) paths.emplace_back(in);
      else std::fprintf(stderr, "corpus_harness: %s does not exist: skipped\n", in.c_str());
    }
  } else {
    for (const char* sub : {"cgal", "stl"}) {
      const fs::path dir = fs::path(o.corpus) / sub;
      if (fs::is_directory(dir)) add_folder(dir);
      else std::printf("corpus_harness: %s is absent: skipped\n", dir.string().c_str());
    }
  }
  for (const fs::path& p : paths) inputs->push_back({p.string(), display_name(p, o.corpus)});
  return !inputs->empty();
}

// The CAD / organic split (issue 20): "cad PATH" or "organic PATH" per line, PATH as the harness
// names meshes (relative to --corpus, e.g. cgal/anchor.off); '#' starts a comment. A mesh not
// listed is unclassified. The default file may be absent (no classes); a given one must exist.
std::map<std::string, std::string> read_mesh_classes(const Options& o) {
  std::map<std::string, std::string> classes;
  if (o.classes.empty() || (!o.classes_given && !fs::is_regular_file(o.classes))) return classes;
  std::stringstream lines(read_whole_file(o.classes));
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::stringstream words(line);
    std::string cls, path, extra;
    if (!(words >> cls)) continue;
    if (!(words >> path) || (words >> extra) || (cls != "cad" && cls != "organic"))
      throw std::runtime_error(o.classes + ":" + std::to_string(number) + ": expected 'cad PATH' or 'organic PATH'");
    classes[fs::path(path).lexically_normal().generic_string()] = cls;
  }
  return classes;
}

// ------------------------------------------------------------------------------------------
// Records

enum class Status { good, clean_error, bad_but_ok, crash, timeout, oom };
const Status kAllStatus[] = {Status::good, Status::clean_error, Status::bad_but_ok,
                             Status::crash, Status::timeout, Status::oom};

const char* status_label(Status s) {
  switch (s) {
    case Status::good: return "good";
    case Status::clean_error: return "clean error";
    case Status::bad_but_ok: return "bad-but-OK";
    case Status::crash: return "crash";
    case Status::timeout: return "timeout";
    case Status::oom: return "out of memory";
  }
  return "?";
}

std::optional<Status> status_from_label(const std::string& label) {
  for (Status s : kAllStatus)
    if (label == status_label(s)) return s;
  return std::nullopt;
}

struct Record {
  std::string mesh, method;
  Status status = Status::crash;
  std::string message;              // first line of stderr, or why the result is not good
  std::vector<std::string> reasons; // every reason a result is not good
  std::string ended;                // how the pipeline child ended ("exit 0", "signal 11 (SIGSEGV)", ...)
  double seconds = 0.0, cpu_seconds = 0.0, peak_mb = 0.0, time_limit = 0.0;
  double deform_seconds = 0.0;
  std::optional<double> input_faces, faces, quads_pct, creases, scan_to_limit, limit_to_scan, holes_added,
      self_intersections, input_boundary_loops, cage_boundary_loops;
  // The scan's own self-intersections (the report counts them only when the limit has some; a
  // faithful surface inherits them).
  std::optional<double> scan_self_intersections;
  bool limit_to_scan_is_bound = false;  // limit_to_scan is an upper bound (hausdorff_rel)
  std::string digest;
  std::string conditioning_json;  // the report's "conditioning" object, when present
  // How the result was made (report keys "used_method", "fallback", "input_is_cage"): a good
  // quad / anisotropic result may be the simplify fallback's, which the tables say.
  std::string used_method;
  bool fallback = false, own_cage = false;
  // Crease figures (issue 20; README "Crease figures"), measured on exit 0 only.
  std::string mesh_class;  // "cad", "organic" or "" (mesh_classes.txt)
  bool creases_measured = false;
  std::optional<double> crease_precision_pct, crease_recall_pct, crease_density_pct;
  // Counts: input edges bending > 40 degrees; measured (interior) crease edges; crease tags on
  // boundary edges, left out of precision and recall.
  std::optional<double> sharp_input_edges, crease_edges, boundary_crease_edges;
  // Lengths relative to the scan's diagonal: measured creases (total, within tau of a sharp input
  // edge) and sharp input edges (total, within tau of a crease); summed over meshes for the pooled figures.
  double crease_length_rel = 0.0, crease_matched_rel = 0.0, sharp_length_rel = 0.0, sharp_matched_rel = 0.0;
  std::string crease_source;  // "limit.obj" or "cage.obj" (the fallback)
  std::string crease_note;    // why the fallback or why figures are missing
};

// Expected clean errors (inputs with no surface, corrupt files), told apart by their message:
// see README.md. Used only for the denominator of the good rate.
bool is_no_surface_error(const std::string& message) {
  std::string lower(message);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const char* key : {"no faces", "empty", "corrupt", "parse", "nothing left", "no surface"})
    if (lower.find(key) != std::string::npos) return true;
  // Reader errors name the file and the line: "path.off:12: ...", the form of a PARSE error.
  for (size_t colon = lower.find(':'); colon != std::string::npos; colon = lower.find(':', colon + 1)) {
    size_t digits = colon + 1;
    while (digits < lower.size() && std::isdigit(static_cast<unsigned char>(lower[digits]))) ++digits;
    if (digits > colon + 1 && digits < lower.size() && lower[digits] == ':') return true;
  }
  return false;
}

// ------------------------------------------------------------------------------------------
// C API helpers (one context per worker thread)

struct Context {
  cagekit_context handle = nullptr;
  Context() {
    cagekit_context_desc desc = CAGEKIT_CONTEXT_DESC_INIT;
    if (cagekit_context_create(&desc, &handle) != CAGEKIT_SUCCESS)
      throw std::runtime_error(std::string("cannot create a CageKit context: ") + cagekit_last_error_message(nullptr));
  }
  ~Context() { cagekit_context_release(handle); }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  std::string error() const { return cagekit_last_error_message(handle); }
};

template <class H, void (*Release)(H)>
struct Owned {
  H h = nullptr;
  Owned() = default;
  ~Owned() { if (h) Release(h); }
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  H* out() { if (h) Release(h); h = nullptr; return &h; }
};
using MeshHandle = Owned<cagekit_mesh, cagekit_mesh_release>;
using CageHandle = Owned<cagekit_cage, cagekit_cage_release>;

struct MeshData {
  std::vector<double> xyz;
  std::vector<uint32_t> sizes, indices;
};

bool mesh_data(cagekit_mesh mesh, MeshData* d) {
  uint32_t vertices = 0, faces = 0;
  uint64_t index_count = 0;
  if (cagekit_mesh_get_counts(mesh, &vertices, &faces, &index_count) != CAGEKIT_SUCCESS) return false;
  d->xyz.resize(3 * size_t(vertices));
  d->sizes.resize(faces);
  d->indices.resize(size_t(index_count));
  uint32_t got_v = 0, got_f = 0;
  uint64_t got_i = 0;
  return cagekit_mesh_get_positions(mesh, CAGEKIT_SCALAR_FLOAT64, vertices, &got_v, d->xyz.data()) == CAGEKIT_SUCCESS &&
         cagekit_mesh_get_faces(mesh, faces, &got_f, d->sizes.data(), index_count, &got_i, d->indices.data()) ==
             CAGEKIT_SUCCESS;
}

struct Tags {
  std::vector<uint32_t> crease_pairs, corners, holes;
  std::vector<float> crease_sharpness, corner_sharpness;
  cagekit_boundary_rule rule = CAGEKIT_BOUNDARY_EDGES_ONLY;
};

bool cage_tags(cagekit_cage cage, Tags* t) {
  uint32_t n = 0;
  if (cagekit_cage_get_creases(cage, 0, &n, nullptr, nullptr) != CAGEKIT_SUCCESS) return false;
  t->crease_pairs.resize(2 * size_t(n));
  t->crease_sharpness.resize(n);
  if (cagekit_cage_get_creases(cage, n, &n, t->crease_pairs.data(), t->crease_sharpness.data()) != CAGEKIT_SUCCESS)
    return false;
  if (cagekit_cage_get_corners(cage, 0, &n, nullptr, nullptr) != CAGEKIT_SUCCESS) return false;
  t->corners.resize(n);
  t->corner_sharpness.resize(n);
  if (cagekit_cage_get_corners(cage, n, &n, t->corners.data(), t->corner_sharpness.data()) != CAGEKIT_SUCCESS)
    return false;
  if (cagekit_cage_get_holes(cage, 0, &n, nullptr) != CAGEKIT_SUCCESS) return false;
  t->holes.resize(n);
  if (cagekit_cage_get_holes(cage, n, &n, t->holes.data()) != CAGEKIT_SUCCESS) return false;
  return cagekit_cage_get_boundary_rule(cage, &t->rule) == CAGEKIT_SUCCESS;
}

// 64-bit FNV-1a over the cage's geometry: counts, face sizes and indices, crease pairs (each as
// (min, max), sorted) with sharpness, corners, holes, the boundary rule, and vertex positions
// rounded to 1e-6 of the cage's bounding-box diagonal (so that last-bit noise does not change it).
class Fnv1a {
 public:
  void bytes(const void* data, size_t n) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) hash_ = (hash_ ^ p[i]) * 1099511628211ull;
  }
  void u64(uint64_t v) {
    unsigned char b[8];
    for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));  // little-endian everywhere
    bytes(b, 8);
  }
  std::string hex() const {
    char buffer[20];
    std::snprintf(buffer, sizeof(buffer), "%016llx", static_cast<unsigned long long>(hash_));
    return buffer;
  }

 private:
  uint64_t hash_ = 14695981039346656037ull;
};

std::string cage_digest(const MeshData& d, const Tags& t, double diagonal) {
  Fnv1a h;
  h.u64(d.xyz.size() / 3);
  h.u64(d.sizes.size());
  for (uint32_t s : d.sizes) h.u64(s);
  for (uint32_t i : d.indices) h.u64(i);
  std::vector<std::pair<std::pair<uint32_t, uint32_t>, int64_t>> creases;
  for (size_t c = 0; c < t.crease_sharpness.size(); ++c) {
    const uint32_t a = t.crease_pairs[2 * c], b = t.crease_pairs[2 * c + 1];
    creases.push_back({{std::min(a, b), std::max(a, b)}, std::llround(double(t.crease_sharpness[c]) * 1000.0)});
  }
  std::sort(creases.begin(), creases.end());
  h.u64(creases.size());
  for (const auto& c : creases) h.u64(c.first.first), h.u64(c.first.second), h.u64(uint64_t(c.second));
  std::vector<std::pair<uint32_t, int64_t>> corners;
  for (size_t c = 0; c < t.corners.size(); ++c)
    corners.push_back({t.corners[c], std::llround(double(t.corner_sharpness[c]) * 1000.0)});
  std::sort(corners.begin(), corners.end());
  h.u64(corners.size());
  for (const auto& c : corners) h.u64(c.first), h.u64(uint64_t(c.second));
  std::vector<uint32_t> holes = t.holes;
  std::sort(holes.begin(), holes.end());
  h.u64(holes.size());
  for (uint32_t f : holes) h.u64(f);
  h.u64(uint64_t(t.rule));
  const double step = diagonal > 0.0 && std::isfinite(diagonal) ? 1e-6 * diagonal : 1e-12;
  for (double x : d.xyz) h.u64(uint64_t(std::isfinite(x) ? std::llround(x / step) : INT64_MIN));
  return h.hex();
}

// The scan as the harness sees it (diagonal, faces, boundary loops).
struct ScanInfo {
  bool read = false;
  std::string error;
  cagekit_mesh_info info{};
  MeshData data;  // positions and faces, for the sharp input edges
  bool have_data = false;
};

ScanInfo scan_info(const Context& ctx, const std::string& path) {
  ScanInfo s;
  MeshHandle mesh;
  if (cagekit_mesh_read_file(ctx.handle, path.c_str(), CAGEKIT_FORMAT_AUTO, mesh.out()) != CAGEKIT_SUCCESS) {
    s.error = ctx.error();
    return s;
  }
  s.info.struct_size = sizeof(s.info);
  if (cagekit_mesh_get_info(mesh.h, &s.info) != CAGEKIT_SUCCESS) {
    s.error = ctx.error();
    return s;
  }
  s.read = true;
  s.have_data = mesh_data(mesh.h, &s.data);
  return s;
}

std::string first_line(const std::string& text) {
  // Progress bars use '\r'; the last segment of the first line is what a user sees.
  std::string line = text.substr(0, text.find('\n'));
  const size_t cr = line.find_last_of('\r');
  if (cr != std::string::npos) line = line.substr(cr + 1);
  if (line.rfind("cagekit: ", 0) == 0) line.erase(0, 9);  // the CLI's prefix
  return line;
}

// Messages name the mesh by its corpus name and the run folder as RUN, so that records do not
// depend on where the corpus, the checkout or --out are.
std::string portable(std::string message, const Input& input, const fs::path& dir) {
  const std::pair<std::string, std::string> swaps[] = {{input.path, input.name}, {dir.string(), "RUN"}};
  for (const auto& swap : swaps)
    for (size_t at = message.find(swap.first); !swap.first.empty() && at != std::string::npos;
         at = message.find(swap.first, at + swap.second.size()))
      message.replace(at, swap.first.size(), swap.second);
  return message;
}

// ------------------------------------------------------------------------------------------
// Crease figures (issue 20): do the cage's crease tags sit on the scan's sharp features?
//   sharp input edges: scan edges with two faces bending by more than 40 degrees (exact duplicate
//     positions welded, see crease_metrics.h);
//   crease edges: the crease-tagged interior edges of out/limit.obj (on the limit surface), or of
//     out/cage.obj when limit.obj is missing or has no crease tags (noted in the record);
//   precision: crease length within tau of a sharp input edge / crease length;
//   recall: sharp input length within tau of a crease edge / sharp input length;
//   tau = 1 % of the scan's bounding-box diagonal, samples every <= tau / 4 (crease_metrics.h).
// Crease density (crease edges / edges of cage.obj) is filled in by run_one.

const double kSharpAngleDegrees = 40.0;
const double kCreaseToleranceRel = 0.01;

// The crease-tagged interior edges of a cage as segments. Tags on boundary edges (one face) are
// left out and counted in *on_boundary: the boundary rule makes those edges sharp anyway, and the
// ground truth has no boundary edges (open CAD patches such as ALSTOM_TEST4 tag their whole
// boundary). Pairs outside the vertex range are skipped.
std::vector<cagekit_corpus::Segment> crease_segments(const MeshData& d, const Tags& t, size_t* on_boundary) {
  const size_t n = d.xyz.size() / 3;
  auto key = [](uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); };
  std::map<uint64_t, int> faces_of_edge;
  size_t at_index = 0;
  for (const uint32_t size : d.sizes) {
    if (at_index + size > d.indices.size()) break;
    for (uint32_t i = 0; i < size; ++i)
      ++faces_of_edge[key(d.indices[at_index + i], d.indices[at_index + (i + 1) % size])];
    at_index += size;
  }
  auto at = [&](uint32_t v) {
    return cagekit_corpus::Vec3{d.xyz[3 * size_t(v)], d.xyz[3 * size_t(v) + 1], d.xyz[3 * size_t(v) + 2]};
  };
  std::vector<cagekit_corpus::Segment> out;
  *on_boundary = 0;
  for (size_t c = 0; c + 1 < t.crease_pairs.size(); c += 2) {
    const uint32_t a = t.crease_pairs[c], b = t.crease_pairs[c + 1];
    if (a >= n || b >= n) continue;
    const auto e = faces_of_edge.find(key(a, b));
    if (e != faces_of_edge.end() && e->second == 1) ++*on_boundary;
    else out.push_back({at(a), at(b)});
  }
  return out;
}

// cage_data / cage_tags: cage.obj's, or null when it did not read as a cage.
void measure_creases(const Context& ctx, const ScanInfo& scan, const fs::path& out, const MeshData* cage_data,
                     const Tags* cage_tags_read, Record* rec) {
  const double diagonal = scan.read ? scan.info.bbox_diagonal : 0.0;
  if (!scan.have_data || !(diagonal > 0.0) || !std::isfinite(diagonal)) {
    rec->crease_note = "no crease figures: the scan did not read or has no extent";
    return;
  }
  // The crease edges: limit.obj's tags, else cage.obj's.
  std::vector<cagekit_corpus::Segment> creases;
  size_t on_boundary = 0;
  const std::string limit_path = (out / "limit.obj").string();
  std::string why_not_limit;
  CageHandle limit;
  MeshHandle limit_mesh;
  MeshData limit_data;
  Tags limit_tags;
  if (!fs::is_regular_file(limit_path)) {
    why_not_limit = "no limit.obj";
  } else if (cagekit_cage_read_file(ctx.handle, limit_path.c_str(), CAGEKIT_FORMAT_AUTO, limit.out()) !=
                 CAGEKIT_SUCCESS ||
             !cage_tags(limit.h, &limit_tags) ||
             cagekit_cage_get_mesh(limit.h, limit_mesh.out()) != CAGEKIT_SUCCESS ||
             !mesh_data(limit_mesh.h, &limit_data)) {
    why_not_limit = "limit.obj does not read as a cage: " + first_line(ctx.error());
  } else if (limit_tags.crease_sharpness.empty()) {
    why_not_limit = "limit.obj has no crease tags";
  }
  if (why_not_limit.empty()) {
    creases = crease_segments(limit_data, limit_tags, &on_boundary);
    rec->crease_source = "limit.obj";
  } else if (cage_data && cage_tags_read) {
    creases = crease_segments(*cage_data, *cage_tags_read, &on_boundary);
    rec->crease_source = "cage.obj";
    rec->crease_note = why_not_limit + ": creases of cage.obj";
  } else {
    rec->crease_note = "no crease figures: " + why_not_limit + " and cage.obj is not a readable cage";
    return;
  }

  const std::vector<cagekit_corpus::Segment> sharp =
      cagekit_corpus::sharp_input_edges(scan.data.xyz, scan.data.sizes, scan.data.indices, kSharpAngleDegrees);
  const cagekit_corpus::CreaseMatch m = cagekit_corpus::match_creases(creases, sharp, kCreaseToleranceRel * diagonal);
  rec->creases_measured = true;
  rec->sharp_input_edges = double(sharp.size());
  rec->crease_edges = double(creases.size());
  rec->boundary_crease_edges = double(on_boundary);
  rec->crease_length_rel = m.creases.total / diagonal;
  rec->crease_matched_rel = m.creases.matched / diagonal;
  rec->sharp_length_rel = m.sharp.total / diagonal;
  rec->sharp_matched_rel = m.sharp.matched / diagonal;
  if (m.creases.total > 0.0) rec->crease_precision_pct = 100.0 * m.creases.matched / m.creases.total;
  if (m.sharp.total > 0.0) rec->crease_recall_pct = 100.0 * m.sharp.matched / m.sharp.total;
}

// ------------------------------------------------------------------------------------------
// One (mesh, method)

struct Limits {
  double pipeline_seconds, deform_seconds;
};

void classify_failure(const cagekit_jobs::JobResult& r, const std::string& err, Record* rec) {
  rec->message = first_line(err);
  if (!r.started) {
    rec->status = Status::crash;
    rec->message = cagekit_jobs::describe(r);
  } else if (r.timed_out) {
    rec->status = Status::timeout;
    rec->message = cagekit_jobs::describe(r);
  } else if (cagekit_jobs::likely_out_of_memory(r, err)) {
    rec->status = Status::oom;
    if (rec->message.empty()) rec->message = cagekit_jobs::describe(r);
  } else if (r.signaled) {
    rec->status = Status::crash;
    rec->message = cagekit_jobs::describe(r) + (rec->message.empty() ? "" : ": " + rec->message);
  } else if (r.exit_code == 2) {
    rec->status = Status::clean_error;
  } else {
    // Not the CLI's error convention (exit 2, one line): an uncaught exception (exit 1) or
    // anything else counts as a crash.
    rec->status = Status::crash;
    rec->message = cagekit_jobs::describe(r) + (rec->message.empty() ? "" : ": " + rec->message);
  }
}

Record run_one(const Options& o, const Context& ctx, const Input& input, const std::string& method,
               const Limits& limits, const fs::path& dir) {
  Record rec;
  rec.mesh = input.name;
  rec.method = method;
  rec.time_limit = limits.pipeline_seconds;
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot create: " + ec.message());

  cagekit_jobs::JobSpec spec;
  spec.argv = {o.cli, "pipeline", input.path, (dir / "out").string()};
  if (method == "simplify") spec.argv.insert(spec.argv.end(), {"--faces", "60"});
  else spec.argv.insert(spec.argv.end(), {"--method", method});
  spec.argv.insert(spec.argv.end(), {"--quiet", "--json"});
  spec.stdout_path = (dir / "pipeline.stdout").string();
  spec.stderr_path = (dir / "pipeline.stderr").string();
  spec.timeout_seconds = limits.pipeline_seconds;
  spec.memory_limit_bytes = uint64_t(o.memory_mb * 1024.0 * 1024.0);
  const cagekit_jobs::JobResult run = cagekit_jobs::run_job(spec);
  rec.ended = cagekit_jobs::describe(run);
  rec.seconds = run.wall_seconds;
  rec.cpu_seconds = run.cpu_seconds;
  rec.peak_mb = run.peak_rss_mb;
  const std::string err = cagekit_jobs::read_file_head(spec.stderr_path, 1 << 16);
  if (!(run.started && run.exited && run.exit_code == 0)) {
    classify_failure(run, err, &rec);
    rec.message = portable(rec.message, input, dir);
    return rec;
  }

  // Exit 0: judge the result.
  const fs::path out = dir / "out";
  const ScanInfo scan = scan_info(ctx, input.path);
  auto bad = [&rec](const std::string& reason) { rec.reasons.push_back(reason); };
  double diagonal = 0.0;
  if (scan.read) {
    rec.input_faces = double(scan.info.faces);
    rec.input_boundary_loops = double(scan.info.boundary_loops);
    diagonal = scan.info.bbox_diagonal;
  } else {
    bad("the harness cannot read the scan: " + scan.error);
  }

  // The report (the lead's "quality" keys preferred, "limit.error" otherwise).
  Json report;
  bool have_report = false;
  try {
    report = JsonParser(read_whole_file((out / "report.json").string())).parse();
    have_report = true;
  } catch (const std::exception& e) {
    bad(std::string("report.json: ") + e.what());
  }
  if (have_report) {
    if (const Json* c = report.get("conditioning")) rec.conditioning_json = json_write(*c);
    if (const Json* u = report.get("used_method"); u && u->type == Json::kString) rec.used_method = u->text;
    if (const Json* f = report.get("fallback"); f && f->type == Json::kBool) rec.fallback = f->boolean;
    if (const Json* c = report.get("input_is_cage"); c && c->type == Json::kBool) rec.own_cage = c->boolean;
    const std::optional<double> s2l_q = report.number_at({"quality", "scan_to_limit_max_rel"});
    const std::optional<double> l2s_q = report.number_at({"quality", "limit_to_scan_max_rel"});
    const std::optional<double> h = report.number_at({"limit", "error", "hausdorff_rel"});
    const std::optional<double> hs = report.number_at({"limit", "error", "hausdorff_sym_rel"});
    rec.scan_to_limit = s2l_q ? s2l_q : h;
    if (l2s_q) {
      rec.limit_to_scan = l2s_q;
    } else if (h && hs) {
      // hausdorff_sym = max(scan->limit, limit->scan): above scan->limit it is limit->scan;
      // otherwise limit->scan is at most scan->limit (an upper bound, flagged as such).
      rec.limit_to_scan = *hs > *h ? *hs : *h;
      rec.limit_to_scan_is_bound = !(*hs > *h);
    }
    rec.self_intersections = report.number_at({"quality", "limit_self_intersections"});
    rec.scan_self_intersections = report.number_at({"quality", "scan_self_intersections"});
    rec.holes_added = report.number_at({"quality", "holes_added"});
  }

  // The cage, read back and checked through the C API.
  const std::string cage_path = (out / "cage.obj").string();
  MeshHandle cage_mesh;
  MeshData data;
  Tags tags;
  CageHandle cage;
  bool cage_ok = false;
  bool cage_read = false;  // cage.obj read as a cage, with its tags and data
  uint64_t cage_edges = 0;
  if (!fs::is_regular_file(cage_path)) {
    bad("no cage.obj");
  } else if (cagekit_mesh_read_file(ctx.handle, cage_path.c_str(), CAGEKIT_FORMAT_AUTO, cage_mesh.out()) !=
             CAGEKIT_SUCCESS) {
    bad("cage.obj does not read: " + first_line(ctx.error()));
  } else {
    cagekit_validation_report validation{};
    validation.struct_size = sizeof(validation);
    const cagekit_status valid = cagekit_mesh_validate(cage_mesh.h, &validation);
    const std::string validation_error = valid == CAGEKIT_SUCCESS ? "" : first_line(ctx.error());
    cagekit_mesh_info info{};
    info.struct_size = sizeof(info);
    cagekit_mesh_get_info(cage_mesh.h, &info);
    rec.faces = double(info.faces);
    cage_edges = info.edges;
    rec.quads_pct = info.faces ? 100.0 * double(info.quads) / double(info.faces) : 0.0;
    rec.cage_boundary_loops = double(info.boundary_loops);
    const bool mesh_ok = valid == CAGEKIT_SUCCESS && validation.valid && info.manifold && info.faces > 0;
    if (valid != CAGEKIT_SUCCESS || !validation.valid) bad("invalid cage: " + validation_error);
    else if (!info.manifold) bad("cage is not manifold");
    else if (info.faces == 0) bad("cage has no faces");
    // The cage with its tags; an invalid one is digested as a plain mesh (no tags).
    const bool tags_ok =
        cagekit_cage_read_file(ctx.handle, cage_path.c_str(), CAGEKIT_FORMAT_AUTO, cage.out()) == CAGEKIT_SUCCESS &&
        cage_tags(cage.h, &tags);
    if (!tags_ok && mesh_ok) bad("cage.obj is not a valid cage: " + first_line(ctx.error()));
    if (!mesh_data(cage_mesh.h, &data)) {
      bad("cannot read the cage's data: " + first_line(ctx.error()));
    } else {
      if (tags_ok) rec.creases = double(tags.crease_sharpness.size());
      cage_read = tags_ok;
      rec.digest = cage_digest(data, tags_ok ? tags : Tags{}, info.bbox_diagonal);
      cage_ok = mesh_ok && tags_ok;
    }
  }
  // Crease figures (reported, not judged: they do not change the status). The density is over
  // interior edges (two faces): a boundary edge is sharp by the boundary rule whatever the tags.
  if (cage_read && cage_edges > 0) {
    std::unordered_map<uint64_t, int> uses;
    size_t at = 0;
    for (uint32_t n : data.sizes) {
      for (uint32_t k = 0; k < n; ++k) {
        uint32_t a = data.indices[at + k], b = data.indices[at + (k + 1) % n];
        if (a > b) std::swap(a, b);
        ++uses[uint64_t(a) << 32 | b];
      }
      at += n;
    }
    size_t interior = 0, interior_creases = 0;
    for (const auto& [key, count] : uses) interior += count == 2;
    for (size_t c = 0; c + 1 < tags.crease_pairs.size(); c += 2) {
      uint32_t a = tags.crease_pairs[c], b = tags.crease_pairs[c + 1];
      if (a > b) std::swap(a, b);
      const auto it = uses.find(uint64_t(a) << 32 | b);
      interior_creases += it != uses.end() && it->second == 2;
    }
    if (interior > 0) rec.crease_density_pct = 100.0 * double(interior_creases) / double(interior);
  }
  measure_creases(ctx, scan, out, cage_read ? &data : nullptr, cage_read ? &tags : nullptr, &rec);
  rec.crease_note = portable(rec.crease_note, input, dir);

  // Holes the input did not have.
  if (!rec.holes_added && rec.cage_boundary_loops && rec.input_boundary_loops)
    rec.holes_added = std::max(0.0, *rec.cage_boundary_loops - *rec.input_boundary_loops);
  if (rec.holes_added && *rec.holes_added > 0)
    bad("holes added: " + std::to_string(int64_t(*rec.holes_added)));

  // Limit -> scan max <= max(5 % of the diagonal, 3 x scan -> limit max), waived under 1,000 input faces.
  if (rec.scan_to_limit && rec.limit_to_scan) {
    const double allowed = std::max(0.05, 3.0 * *rec.scan_to_limit);
    const bool waived = rec.input_faces && *rec.input_faces < 1000.0;
    if (!waived && *rec.limit_to_scan > allowed) {
      char buffer[160];
      std::snprintf(buffer, sizeof(buffer), "limit->scan %.3g > max(0.05, 3 x scan->limit %.3g) of the diagonal",
                    *rec.limit_to_scan, *rec.scan_to_limit);
      bad(buffer);
    }
  } else if (have_report) {
    bad("report.json has no two-sided limit error");
  }

  // The deform: control vertex 0 moved by 5 % of the scan's diagonal, along the fixed direction
  // (1, 2, 3) / sqrt(14): not along an axis, where on axis-aligned CAD cages the move can land
  // exactly on a neighbouring control point and make the edited cage degenerate.
  if (cage_ok && scan.read && !data.xyz.empty()) {
    MeshData edited = data;
    const double step = 0.05 * diagonal / std::sqrt(14.0);
    edited.xyz[0] += 1.0 * step;
    edited.xyz[1] += 2.0 * step;
    edited.xyz[2] += 3.0 * step;
    cagekit_mesh_desc desc = CAGEKIT_MESH_DESC_INIT;
    desc.vertex_count = uint32_t(edited.xyz.size() / 3);
    desc.positions = edited.xyz.data();
    desc.position_type = CAGEKIT_SCALAR_FLOAT64;
    desc.face_count = uint32_t(edited.sizes.size());
    desc.face_sizes = edited.sizes.data();
    desc.face_indices = edited.indices.data();
    MeshHandle edited_mesh;
    CageHandle edited_cage;
    const std::string edited_path = (dir / "edited.obj").string();
    const std::string deformed_path = (dir / "deformed.obj").string();
    bool written = cagekit_mesh_create(ctx.handle, &desc, edited_mesh.out()) == CAGEKIT_SUCCESS &&
                   cagekit_cage_create(edited_mesh.h, edited_cage.out()) == CAGEKIT_SUCCESS &&
                   cagekit_cage_set_creases(edited_cage.h, uint32_t(tags.crease_sharpness.size()),
                                            tags.crease_pairs.data(), tags.crease_sharpness.data()) == CAGEKIT_SUCCESS &&
                   cagekit_cage_set_corners(edited_cage.h, uint32_t(tags.corners.size()), tags.corners.data(),
                                            tags.corner_sharpness.data()) == CAGEKIT_SUCCESS &&
                   cagekit_cage_set_holes(edited_cage.h, uint32_t(tags.holes.size()), tags.holes.data()) ==
                       CAGEKIT_SUCCESS &&
                   cagekit_cage_set_boundary_rule(edited_cage.h, tags.rule) == CAGEKIT_SUCCESS &&
                   cagekit_cage_write_file(edited_cage.h, edited_path.c_str(), nullptr, nullptr) == CAGEKIT_SUCCESS;
    if (!written) {
      bad("cannot write the edited cage: " + first_line(ctx.error()));
    } else {
      cagekit_jobs::JobSpec deform;
      deform.argv = {o.cli, "deform", input.path, cage_path, edited_path, deformed_path, "--quiet"};
      deform.stdout_path = (dir / "deform.stdout").string();
      deform.stderr_path = (dir / "deform.stderr").string();
      deform.timeout_seconds = limits.deform_seconds;
      deform.memory_limit_bytes = spec.memory_limit_bytes;
      const cagekit_jobs::JobResult d = cagekit_jobs::run_job(deform);
      rec.deform_seconds = d.wall_seconds;
      rec.peak_mb = std::max(rec.peak_mb, d.peak_rss_mb);
      if (!(d.started && d.exited && d.exit_code == 0)) {
        const std::string derr = cagekit_jobs::read_file_head(deform.stderr_path, 1 << 16);
        bad("deform failed (" + cagekit_jobs::describe(d) + "): " + first_line(derr));
      } else if (!fs::is_regular_file(deformed_path)) {
        bad("deform wrote no output");
      }
    }
  } else {
    bad("deform not run (no valid cage or no readable scan)");
  }

  for (std::string& reason : rec.reasons) reason = portable(reason, input, dir);
  if (rec.reasons.empty()) {
    rec.status = Status::good;
  } else {
    rec.status = Status::bad_but_ok;
    rec.message = rec.reasons.front();
    for (size_t i = 1; i < rec.reasons.size(); ++i) rec.message += "; " + rec.reasons[i];
  }
  return rec;
}

// ------------------------------------------------------------------------------------------
// Summary, outputs, baseline

struct Summary {
  std::map<Status, int> count;
  int total = 0, no_surface = 0;
  int good_by_fallback = 0, good_own_cage = 0;  // good results made by the simplify fallback / tiny inputs
  // Good results whose level-2 limit self-intersects, and of those the ones whose scan does too.
  int good_self_intersecting = 0, good_self_intersecting_inherited = 0;
  double good_rate() const {
    const int with_surface = total - no_surface;
    return with_surface > 0 ? 100.0 * count.at(Status::good) / with_surface : 0.0;
  }
};

Summary summarize(const std::vector<Record>& records, const std::string& method) {
  Summary s;
  for (Status st : kAllStatus) s.count[st] = 0;
  for (const Record& r : records) {
    if (r.method != method) continue;
    ++s.total;
    ++s.count[r.status];
    if (r.status == Status::clean_error && is_no_surface_error(r.message)) ++s.no_surface;
    if (r.status == Status::good && r.fallback) ++s.good_by_fallback;
    if (r.status == Status::good && r.own_cage) ++s.good_own_cage;
    if (r.status == Status::good && r.self_intersections && *r.self_intersections > 0) {
      ++s.good_self_intersecting;
      if (r.scan_self_intersections && *r.scan_self_intersections > 0) ++s.good_self_intersecting_inherited;
    }
  }
  return s;
}

std::string summary_line(const std::string& method, const Summary& s) {
  char buffer[400];
  std::snprintf(buffer, sizeof(buffer),
                "%s: %d good, %d clean errors, %d bad-but-OK, %d crashes, %d timeouts, %d oom "
                "(good rate %.1f %% of %d meshes with a surface)",
                method.c_str(), s.count.at(Status::good), s.count.at(Status::clean_error),
                s.count.at(Status::bad_but_ok), s.count.at(Status::crash), s.count.at(Status::timeout),
                s.count.at(Status::oom), s.good_rate(), s.total - s.no_surface);
  std::string line = buffer;
  if (s.good_by_fallback || s.good_own_cage)
    line += "; of the good: " + std::to_string(s.good_by_fallback) + " by the simplify fallback, " +
            std::to_string(s.good_own_cage) + " tiny inputs as their own cage";
  line += "; limit self-intersections in " + std::to_string(s.good_self_intersecting) + " good results (" +
          std::to_string(s.good_self_intersecting_inherited) + " of them from a self-intersecting scan)";
  return line;
}

// Crease figures of one method over one class (README "Crease figures").
struct CreaseSummary {
  int meshes = 0;     // records of the class
  int measured = 0;   // of them, exit 0 with crease figures
  int good_fits = 0;  // good records with both one-sided errors (for the fit median)
  // Pooled over the measured records: summed matched length / summed length, each mesh's lengths
  // relative to its own diagonal (so that model units do not weigh meshes).
  std::optional<double> precision_pct, recall_pct;
  std::optional<double> precision_median_pct, recall_median_pct, density_median_pct, density_max_pct;
  std::optional<double> fit_median_pct;  // median of max(scan->limit, limit->scan) over good records, % of the diagonal
};

std::optional<double> median(std::vector<double> v) {
  if (v.empty()) return std::nullopt;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

CreaseSummary summarize_creases(const std::vector<Record>& records, const std::string& method, const std::string& cls) {
  CreaseSummary s;
  double crease = 0.0, crease_matched = 0.0, sharp = 0.0, sharp_matched = 0.0;
  std::vector<double> precisions, recalls, densities, fits;
  for (const Record& r : records) {
    if (r.method != method || r.mesh_class != cls) continue;
    ++s.meshes;
    if (r.status == Status::good && r.scan_to_limit && r.limit_to_scan) {
      ++s.good_fits;
      fits.push_back(100.0 * std::max(*r.scan_to_limit, *r.limit_to_scan));
    }
    if (!r.creases_measured) continue;
    ++s.measured;
    crease += r.crease_length_rel;
    crease_matched += r.crease_matched_rel;
    sharp += r.sharp_length_rel;
    sharp_matched += r.sharp_matched_rel;
    if (r.crease_precision_pct) precisions.push_back(*r.crease_precision_pct);
    if (r.crease_recall_pct) recalls.push_back(*r.crease_recall_pct);
    if (r.crease_density_pct) densities.push_back(*r.crease_density_pct);
  }
  if (crease > 0.0) s.precision_pct = 100.0 * crease_matched / crease;
  if (sharp > 0.0) s.recall_pct = 100.0 * sharp_matched / sharp;
  s.precision_median_pct = median(precisions);
  s.recall_median_pct = median(recalls);
  s.density_median_pct = median(densities);
  if (!densities.empty()) s.density_max_pct = *std::max_element(densities.begin(), densities.end());
  s.fit_median_pct = median(fits);
  return s;
}

std::string percent(std::optional<double> x, const char* format = "%.1f %%") {
  if (!x || !std::isfinite(*x)) return "n/a";
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), format, *x);
  return buffer;
}

std::string crease_line(const std::string& method, const std::string& cls, const CreaseSummary& s) {
  return method + " creases, " + (cls == "cad" ? "CAD" : cls) + ": " + std::to_string(s.meshes) + " meshes (" +
         std::to_string(s.measured) + " measured): precision " + percent(s.precision_pct) + " recall " +
         percent(s.recall_pct) + " (length-weighted; medians " + percent(s.precision_median_pct) + " / " +
         percent(s.recall_median_pct) + "), crease density median " + percent(s.density_median_pct) + " (max " +
         percent(s.density_max_pct) + "), fit two-sided median " + percent(s.fit_median_pct, "%.2f %%") + " (" +
         std::to_string(s.good_fits) + " good)";
}

std::string crease_summary_json(const CreaseSummary& s, const std::string& line) {
  return "{\"meshes\": " + std::to_string(s.meshes) + ", \"measured\": " + std::to_string(s.measured) +
         ", \"precision_pct\": " + json_number(s.precision_pct, "%.2f") +
         ", \"recall_pct\": " + json_number(s.recall_pct, "%.2f") +
         ", \"precision_median_pct\": " + json_number(s.precision_median_pct, "%.2f") +
         ", \"recall_median_pct\": " + json_number(s.recall_median_pct, "%.2f") +
         ", \"density_median_pct\": " + json_number(s.density_median_pct, "%.2f") +
         ", \"density_max_pct\": " + json_number(s.density_max_pct, "%.2f") +
         ", \"fit_two_sided_median_pct\": " + json_number(s.fit_median_pct, "%.3f") +
         ", \"good\": " + std::to_string(s.good_fits) + ", \"line\": " + json_escape(line) + "}";
}

const char* const kMeshClasses[] = {"cad", "organic"};

std::string record_json(const Record& r) {
  std::string reasons = "[";
  for (size_t i = 0; i < r.reasons.size(); ++i) reasons += (i ? ", " : "") + json_escape(r.reasons[i]);
  reasons += "]";
  return "{\"mesh\": " + json_escape(r.mesh) + ", \"method\": " + json_escape(r.method) +
         ", \"status\": " + json_escape(status_label(r.status)) + ", \"message\": " + json_escape(r.message) +
         ", \"reasons\": " + reasons + ", \"ended\": " + json_escape(r.ended) +
         ", \"seconds\": " + json_number(r.seconds, "%.3f") + ", \"cpu_seconds\": " + json_number(r.cpu_seconds, "%.3f") +
         ", \"deform_seconds\": " + json_number(r.deform_seconds, "%.3f") +
         ", \"time_limit\": " + json_number(r.time_limit, "%.1f") + ", \"peak_mb\": " + json_number(r.peak_mb, "%.1f") +
         ", \"input_faces\": " + json_number(r.input_faces, "%.0f") + ", \"faces\": " + json_number(r.faces, "%.0f") +
         ", \"quads_pct\": " + json_number(r.quads_pct, "%.1f") + ", \"creases\": " + json_number(r.creases, "%.0f") +
         ", \"scan_to_limit_max_rel\": " + json_number(r.scan_to_limit) +
         ", \"limit_to_scan_max_rel\": " + json_number(r.limit_to_scan) +
         ", \"limit_to_scan_is_upper_bound\": " + (r.limit_to_scan_is_bound ? "true" : "false") +
         ", \"input_boundary_loops\": " + json_number(r.input_boundary_loops, "%.0f") +
         ", \"cage_boundary_loops\": " + json_number(r.cage_boundary_loops, "%.0f") +
         ", \"holes_added\": " + json_number(r.holes_added, "%.0f") +
         ", \"limit_self_intersections\": " + json_number(r.self_intersections, "%.0f") +
         ", \"scan_self_intersections\": " + json_number(r.scan_self_intersections, "%.0f") +
         ", \"digest\": " + (r.digest.empty() ? "null" : json_escape(r.digest)) +
         ", \"used_method\": " + (r.used_method.empty() ? "null" : json_escape(r.used_method)) +
         ", \"fallback\": " + (r.fallback ? "true" : "false") + ", \"input_is_cage\": " +
         (r.own_cage ? "true" : "false") +
         ", \"conditioning\": " + (r.conditioning_json.empty() ? "null" : r.conditioning_json) +
         ", \"class\": " + json_escape(r.mesh_class) +
         ", \"crease_precision_pct\": " + json_number(r.crease_precision_pct, "%.2f") +
         ", \"crease_recall_pct\": " + json_number(r.crease_recall_pct, "%.2f") +
         ", \"crease_density_pct\": " + json_number(r.crease_density_pct, "%.2f") +
         ", \"crease_source\": " + (r.crease_source.empty() ? "null" : json_escape(r.crease_source)) +
         ", \"crease_note\": " + (r.crease_note.empty() ? "null" : json_escape(r.crease_note)) +
         ", \"crease_edges\": " + json_number(r.crease_edges, "%.0f") +
         ", \"boundary_crease_edges\": " + json_number(r.boundary_crease_edges, "%.0f") +
         ", \"sharp_input_edges\": " + json_number(r.sharp_input_edges, "%.0f") +
         ", \"crease_length_rel\": " + (r.creases_measured ? json_number(r.crease_length_rel) : "null") +
         ", \"crease_matched_rel\": " + (r.creases_measured ? json_number(r.crease_matched_rel) : "null") +
         ", \"sharp_length_rel\": " + (r.creases_measured ? json_number(r.sharp_length_rel) : "null") +
         ", \"sharp_matched_rel\": " + (r.creases_measured ? json_number(r.sharp_matched_rel) : "null") + "}";
}

std::string cell(std::optional<double> x, const char* format) {
  if (!x || !std::isfinite(*x)) return "n/a";
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), format, *x);
  return buffer;
}

std::string markdown_escape(std::string s) {
  for (size_t at = s.find('|'); at != std::string::npos; at = s.find('|', at + 2)) s.replace(at, 1, "\\|");
  if (s.size() > 160) s = s.substr(0, 157) + "...";
  return s;
}

std::string markdown(const std::vector<Record>& records, const std::vector<std::string>& methods,
                     const std::vector<std::string>& lines) {
  std::string md;
  for (const std::string& method : methods) {
    md += "### " + method + "\n\n";
    md += "| mesh | status | class | s | MB | faces | quads % | creases | crease density % | precision % | "
          "recall % | scan→limit | limit→scan | holes added | self-int. | digest | message |\n";
    md += "|---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|---|---|\n";
    for (const Record& r : records) {
      if (r.method != method) continue;
      char t[32], m[32];
      std::snprintf(t, sizeof(t), "%.1f", r.seconds + r.deform_seconds);
      std::snprintf(m, sizeof(m), "%.0f", r.peak_mb);
      const std::string how = r.fallback ? " (fallback: simplify)" : r.own_cage ? " (own cage)" : "";
      // Precision / recall from cage.obj's creases (limit.obj had none) are marked "(cage)".
      const std::string from_cage = r.crease_source == "cage.obj" ? " (cage)" : "";
      md += "| " + markdown_escape(r.mesh) + " | " + status_label(r.status) + how + " | " +
            (r.mesh_class.empty() ? "" : r.mesh_class) + " | " + t + " | " + m + " | " + cell(r.faces, "%.0f") +
            " | " + cell(r.quads_pct, "%.0f") + " | " + cell(r.creases, "%.0f") + " | " +
            cell(r.crease_density_pct, "%.1f") + " | " + cell(r.crease_precision_pct, "%.1f") + from_cage + " | " +
            cell(r.crease_recall_pct, "%.1f") + from_cage + " | " +
            cell(r.scan_to_limit, "%.3g") + " | " + (r.limit_to_scan_is_bound ? "≤ " : "") +
            cell(r.limit_to_scan, "%.3g") + " | " + cell(r.holes_added, "%.0f") + " | " +
            cell(r.self_intersections, "%.0f") +
            (r.scan_self_intersections && *r.scan_self_intersections > 0
                 ? " (scan " + cell(r.scan_self_intersections, "%.0f") + ")"
                 : std::string()) +
            " | " + (r.digest.empty() ? "n/a" : "`" + r.digest + "`") + " | " +
            markdown_escape(r.message) + " |\n";
    }
    md += "\n";
  }
  md += "Summary:\n\n";
  for (const std::string& l : lines) md += "- `" + l + "`\n";
  md += "\nCrease figures (tests/corpus/README.md): precision = interior crease length within 1 % of the diagonal "
        "of a scan edge bending > 40°, recall = that edge length within 1 % of a crease (creases of limit.obj; \"(cage)\": "
        "of cage.obj), crease density = crease edges / edges of cage.obj, both interior (two faces; boundary edges are sharp by the boundary rule); \"fit two-sided\" = max(scan→limit, "
        "limit→scan) of the good records.\n";
  return md;
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

struct BaselineEntry {
  Status status;
  double seconds = 0.0, deform_seconds = 0.0;
};

struct Baseline {
  std::map<std::pair<std::string, std::string>, BaselineEntry> records;  // (mesh, method)
  std::map<std::string, int> min_good, max_bad_but_ok, max_crashes;
};

Baseline read_baseline(const std::string& path) {
  Baseline b;
  const Json j = JsonParser(read_whole_file(path)).parse();
  if (const Json* methods = j.get("methods"))
    for (const auto& m : methods->members)
    {
      if (const std::optional<double> g = m.second.number_at({"min_good"})) b.min_good[m.first] = int(*g);
      if (const std::optional<double> n = m.second.number_at({"max_bad_but_ok"})) b.max_bad_but_ok[m.first] = int(*n);
      if (const std::optional<double> n = m.second.number_at({"max_crashes"})) b.max_crashes[m.first] = int(*n);
    }
  const Json* records = j.get("records");
  if (!records || records->type != Json::kArray) throw std::runtime_error(path + ": no \"records\" array");
  for (const Json& r : records->items) {
    const Json* mesh = r.get("mesh");
    const Json* method = r.get("method");
    const Json* status = r.get("status");
    if (!mesh || !method || !status) throw std::runtime_error(path + ": a record lacks mesh, method or status");
    const std::optional<Status> s = status_from_label(status->text);
    if (!s) throw std::runtime_error(path + ": unknown status '" + status->text + "'");
    BaselineEntry e{*s};
    e.seconds = r.number_at({"seconds"}).value_or(0.0);
    e.deform_seconds = r.number_at({"deform_seconds"}).value_or(0.0);
    b.records[{mesh->text, method->text}] = e;
  }
  return b;
}

std::string baseline_json(const std::vector<Record>& records, const std::vector<std::string>& methods,
                          const Options& o) {
  std::string json = "{\"format\": \"cagekit-corpus-baseline/1\",\n \"generated_utc\": " + json_escape(utc_now()) +
                     ",\n \"command\": " + json_escape(o.command_line) + ",\n \"methods\": {";
  for (size_t i = 0; i < methods.size(); ++i) {
    const Summary s = summarize(records, methods[i]);
    json += std::string(i ? ",\n  " : "\n  ") + json_escape(methods[i]) + ": {\"min_good\": " +
            std::to_string(s.count.at(Status::good)) +
            ", \"max_bad_but_ok\": " + std::to_string(s.count.at(Status::bad_but_ok)) +
            ", \"max_crashes\": " + std::to_string(s.count.at(Status::crash)) + ", \"known\": {";
    bool first = true;
    for (Status st : kAllStatus) {
      json += std::string(first ? "" : ", ") + json_escape(status_label(st)) + ": " + std::to_string(s.count.at(st));
      first = false;
    }
    json += "}}";
  }
  json += "},\n \"records\": [";
  for (size_t i = 0; i < records.size(); ++i) {
    const Record& r = records[i];
    json += std::string(i ? ",\n  " : "\n  ") + "{\"mesh\": " + json_escape(r.mesh) + ", \"method\": " +
            json_escape(r.method) + ", \"status\": " + json_escape(status_label(r.status)) +
            ", \"seconds\": " + json_number(r.seconds, "%.2f") +
            ", \"deform_seconds\": " + json_number(r.deform_seconds, "%.2f") +
            ", \"digest\": " + (r.digest.empty() ? "null" : json_escape(r.digest)) + "}";
  }
  return json + "\n ]}\n";
}

bool is_alarm(Status s) {
  return s == Status::crash || s == Status::bad_but_ok || s == Status::timeout || s == Status::oom;
}

// The CI rule (README.md): worse than the baseline fails, known problems warn.
int compare_with_baseline(const Baseline& b, const std::vector<Record>& records,
                          const std::vector<std::string>& methods) {
  std::vector<std::string> failures, warnings;
  for (const Record& r : records) {
    const auto it = b.records.find({r.mesh, r.method});
    const std::string what = r.mesh + " " + r.method + ": " + status_label(r.status) +
                             (r.message.empty() ? "" : " (" + r.message + ")");
    if (it == b.records.end()) {
      if (is_alarm(r.status)) failures.push_back("new " + what + " (not in the baseline)");
      continue;
    }
    const Status was = it->second.status;
    if (was == Status::good && r.status != Status::good) {
      failures.push_back("regression: " + what + ", was good");
    } else if (is_alarm(r.status) && r.status != was) {
      failures.push_back("new " + what + ", was " + status_label(was));
    } else if (is_alarm(r.status)) {
      warnings.push_back("KNOWN " + what);
    }
  }
  for (const std::string& method : methods) {
    const Summary s = summarize(records, method);
    const auto good = b.min_good.find(method);
    if (good != b.min_good.end() && s.count.at(Status::good) < good->second)
      failures.push_back(method + ": " + std::to_string(s.count.at(Status::good)) + " good, below the baseline's " +
                         std::to_string(good->second));
    const auto bad = b.max_bad_but_ok.find(method);
    if (bad != b.max_bad_but_ok.end() && s.count.at(Status::bad_but_ok) > bad->second)
      failures.push_back(method + ": " + std::to_string(s.count.at(Status::bad_but_ok)) +
                         " bad-but-OK, more than the baseline's " + std::to_string(bad->second));
    const auto crashes = b.max_crashes.find(method);
    if (crashes != b.max_crashes.end() && s.count.at(Status::crash) > crashes->second)
      failures.push_back(method + ": " + std::to_string(s.count.at(Status::crash)) +
                         " crashes, more than the baseline's " + std::to_string(crashes->second));
  }
  if (!warnings.empty()) {
    std::printf("\n!!!!!!!! WARNING: %zu known problem(s) of the baseline are still there (not a failure yet):\n",
                warnings.size());
    for (const std::string& w : warnings) std::printf("!!   %s\n", w.c_str());
  }
  if (!failures.empty()) {
    std::printf("\nFAILED: %zu result(s) worse than the baseline:\n", failures.size());
    for (const std::string& f : failures) std::printf("  %s\n", f.c_str());
    return 1;
  }
  std::printf("\nbaseline check passed: no result worse than the baseline\n");
  return 0;
}

std::string safe_name(const std::string& s) {
  std::string out;
  for (const char c : s) out += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' ? c : '_';
  return out;
}

// --thumbnails: one picture per record (through the render module, o.jobs at a time), then the
// pages and OUT/index.html in the tables' order (per method, then mesh). A picture that cannot be
// drawn is a placeholder with its reason; records are not changed.
void write_thumbnails(const Options& o, const std::vector<Input>& inputs, const std::vector<size_t>& jobs_input,
                      const std::vector<Record>& records, const std::vector<std::string>& summary) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<cagekit_corpus::Thumbnail> thumbs(records.size());
  std::atomic<size_t> next{0};
  auto worker = [&] {
    Context ctx;
    for (size_t j = next++; j < records.size(); j = next++) {
      const Record& r = records[j];
      const fs::path cage = fs::path(o.out) / "runs" / safe_name(r.mesh) / r.method / "out" / "cage.obj";
      std::string error = "n/a";
      if (r.scan_to_limit && r.limit_to_scan) {
        char text[32];
        std::snprintf(text, sizeof(text), "%.2g%%", 100.0 * std::max(*r.scan_to_limit, *r.limit_to_scan));
        error = text;
      }
      const std::string title = r.method + " " + status_label(r.status) + " " + error + " " +
                                fs::path(r.mesh).stem().string();
      // A record without a cage shows the scan; a failed pipeline's cage.obj is not looked at.
      const bool has_cage = r.status == Status::good || r.status == Status::bad_but_ok;
      thumbs[j] = cagekit_corpus::render_thumbnail(ctx.handle, inputs[jobs_input[j]].path,
                                                   has_cage ? cage.string() : std::string(), title);
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < std::max(1, std::min<int>(o.jobs, int(records.size()))); ++t) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
  std::vector<cagekit_corpus::SheetRow> rows;
  size_t drawn = 0;
  for (const std::string& method : o.methods)
    for (size_t j = 0; j < records.size(); ++j) {
      const Record& r = records[j];
      if (r.method != method) continue;
      cagekit_corpus::SheetRow row;
      row.mesh = r.mesh;
      row.method = r.method;
      row.status = status_label(r.status);
      row.error_text = r.scan_to_limit && r.limit_to_scan
                           ? cell(std::max(*r.scan_to_limit, *r.limit_to_scan) * 100.0, "%.3g %%")
                           : std::string("n/a");
      row.faces_text = cell(r.faces, "%.0f");
      row.message = r.message;
      row.thumbnail = &thumbs[j];
      drawn += thumbs[j].drawn;
      rows.push_back(row);
    }
  Context ctx;
  const size_t pages = cagekit_corpus::write_contact_sheet(ctx.handle, o.out, rows, summary);
  std::printf("corpus_harness: %zu thumbnails (%zu drawn, %zu placeholders) on %zu page%s in %.1f s: %s/index.html\n",
              rows.size(), drawn, rows.size() - drawn, pages, pages == 1 ? "" : "s",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), o.out.c_str());
  if (drawn < rows.size()) {
    for (const cagekit_corpus::Thumbnail& t : thumbs)
      if (!t.drawn) {
        std::printf("corpus_harness: first placeholder: %s\n", t.note.c_str());
        break;
      }
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse_options(argc, argv);
    std::vector<Input> inputs;
    if (!collect_inputs(o, &inputs)) {
      std::printf("corpus_harness: no mesh to run: skipped\n");
      return 77;
    }
    const std::map<std::string, std::string> classes = read_mesh_classes(o);
    Baseline baseline;
    if (!o.baseline.empty()) baseline = read_baseline(o.baseline);
    fs::create_directories(o.out);

    struct Job {
      size_t input;
      std::string method;
    };
    std::vector<Job> jobs;
    for (size_t i = 0; i < inputs.size(); ++i)
      for (const std::string& m : o.methods) jobs.push_back({i, m});
    std::vector<size_t> jobs_input;  // records[j]'s input
    for (const Job& job : jobs) jobs_input.push_back(job.input);
    std::vector<Record> records(jobs.size());
    std::atomic<size_t> next{0};
    std::atomic<size_t> done{0};
    std::mutex print;
    std::string worker_error;
    const auto start = std::chrono::steady_clock::now();
    if (!o.summary_only)
      std::printf("corpus_harness: %zu meshes x %zu methods, %d at a time\n", inputs.size(), o.methods.size(), o.jobs);
    auto worker = [&] {
      try {
        Context ctx;
        for (size_t j = next++; j < jobs.size(); j = next++) {
          const Input& input = inputs[jobs[j].input];
          const std::string& method = jobs[j].method;
          Limits limits{o.timeout, o.timeout};
          // With a baseline: the hang limit is max(10 x its time, 30 s) for meshes it has.
          const auto known = baseline.records.find({input.name, method});
          if (known != baseline.records.end()) {
            limits.pipeline_seconds = std::max(10.0 * known->second.seconds, 30.0);
            limits.deform_seconds = std::max(10.0 * known->second.deform_seconds, 30.0);
          }
          const fs::path dir = fs::path(o.out) / "runs" / safe_name(input.name) / method;
          records[j] = run_one(o, ctx, input, method, limits, dir);
          const auto cls = classes.find(fs::path(input.name).lexically_normal().generic_string());
          if (cls != classes.end()) records[j].mesh_class = cls->second;
          const size_t finished = ++done;
          if (!o.summary_only) {
            std::lock_guard<std::mutex> lock(print);
            const Record& r = records[j];
            std::printf("[%zu/%zu] %-40s %-11s %-13s %6.1f s %6.0f MB  %s\n", finished, jobs.size(), r.mesh.c_str(),
                        method.c_str(), status_label(r.status), r.seconds + r.deform_seconds, r.peak_mb,
                        r.message.c_str());
            std::fflush(stdout);
          }
        }
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(print);
        worker_error = e.what();
        next = jobs.size();  // stop the others
      }
    };
    std::vector<std::thread> threads;
    for (int t = 0; t < std::max(1, std::min<int>(o.jobs, int(jobs.size()))); ++t) threads.emplace_back(worker);
    for (std::thread& t : threads) t.join();
    if (!worker_error.empty()) throw std::runtime_error(worker_error);
    const double total_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::vector<std::string> lines;
    for (const std::string& m : o.methods) lines.push_back(summary_line(m, summarize(records, m)));
    // Per method: its summary line, then one crease line per class present in the run.
    std::vector<std::string> printed;
    std::vector<std::string> crease_json(o.methods.size());
    for (size_t i = 0; i < o.methods.size(); ++i) {
      printed.push_back(lines[i]);
      for (const char* cls : kMeshClasses) {
        const CreaseSummary c = summarize_creases(records, o.methods[i], cls);
        if (c.meshes == 0) continue;
        const std::string line = crease_line(o.methods[i], cls, c);
        printed.push_back(line);
        crease_json[i] += std::string(crease_json[i].empty() ? "" : ", ") + json_escape(cls) + ": " +
                          crease_summary_json(c, line);
      }
    }
    char took[96];
    std::snprintf(took, sizeof(took), "%zu runs in %.0f s with --jobs %d", jobs.size(), total_seconds, o.jobs);

    std::string json = "{\"generated_utc\": " + json_escape(utc_now()) + ",\n \"command\": " +
                       json_escape(o.command_line) + ",\n \"seconds\": " + json_number(total_seconds, "%.1f") +
                       ",\n \"summary\": {";
    for (size_t i = 0; i < o.methods.size(); ++i) {
      const Summary s = summarize(records, o.methods[i]);
      json += std::string(i ? ",\n  " : "\n  ") + json_escape(o.methods[i]) + ": {";
      for (Status st : kAllStatus) json += json_escape(status_label(st)) + ": " + std::to_string(s.count.at(st)) + ", ";
      json += "\"total\": " + std::to_string(s.total) + ", \"no_surface_errors\": " + std::to_string(s.no_surface) +
              ", \"good_rate_pct\": " + json_number(s.good_rate(), "%.1f") + ", \"line\": " + json_escape(lines[i]) +
              ", \"creases\": {" + crease_json[i] + "}}";
    }
    json += "},\n \"records\": [";
    for (size_t i = 0; i < records.size(); ++i) json += std::string(i ? ",\n  " : "\n  ") + record_json(records[i]);
    json += "\n ]}\n";
    write_whole_file((fs::path(o.out) / "results.json").string(), json);
    write_whole_file((fs::path(o.out) / "results.md").string(),
                     markdown(records, o.methods, printed) + "\n" + took + ".\n");
    if (!o.write_baseline.empty()) {
      write_whole_file(o.write_baseline, baseline_json(records, o.methods, o));
      std::printf("corpus_harness: baseline written to %s\n", o.write_baseline.c_str());
    }

    if (o.thumbnails) write_thumbnails(o, inputs, jobs_input, records, printed);

    for (const std::string& l : printed) std::printf("%s\n", l.c_str());
    std::printf("(%s; tables in %s/results.md)\n", took, o.out.c_str());
    if (!o.baseline.empty()) return compare_with_baseline(baseline, records, o.methods);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "corpus_harness: %s\n", e.what());
    return 2;
  }
}
