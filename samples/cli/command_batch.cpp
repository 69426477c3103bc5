// SPDX-License-Identifier: GPL-3.0-or-later
// cagekit batch IN_DIR|LIST OUT_DIR ...: `cagekit pipeline` on every scan of a folder or a list,
// each scan in its own child process (job_runner.h: wall-time and address-space limits, exit or
// signal, peak memory), N at a time. A crash, a timeout or an out-of-memory ends only its scan.
// OUT_DIR/<scan>/ holds the scan's pipeline outputs and result.json (its row, written last, with
// a temporary name then a rename: a scan with a result.json is complete); OUT_DIR/results.csv and
// results.json hold the table (one row per scan). --resume skips the scans that have a result
// made with the same pipeline options; --retry-failed too, but runs the failed ones again.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli_context.h"
#include "job_runner.h"
#include "pipeline.h"

namespace cli {

namespace {

namespace fs = std::filesystem;

constexpr const char* kResultFormat = "cagekit-batch-result/1";
constexpr const char* kTableFormat = "cagekit-batch/1";

const IntegerOption kJobs{"--jobs", 1, 1, 256, "N",
                          "scans run at once, each in its own child process; with N > 1 each child runs with "
                          "--threads 1 unless --threads is given"};
const RealOption kTimeout{"--timeout", 0.0, 0.0, 1e7, "S",
                          "wall-time limit of one scan in seconds: past it its child is killed, status timeout "
                          "(0: none)"};
const IntegerOption kMemoryLimit{"--memory-limit", 0, 0, 16777216, "MB",
                                 "address-space limit of one scan's child in MiB (RLIMIT_AS): past it the scan "
                                 "fails, status oom (0: none)"};
const FlagOption kResume{"--resume",
                         "skip the scans that already have a complete result (OUT_DIR/<scan>/result.json) made "
                         "with the same pipeline options; delete a result.json to run its scan again"};
const FlagOption kRetryFailed{"--retry-failed",
                              "--resume, except that the scans whose earlier result is not ok (failed, timeout, "
                              "crash, oom) run again; the ok ones are kept"};
const FlagOption kThumbnails{"--thumbnails",
                             "also OUT_DIR/<scan>/thumbnail.png for each ok scan (`cagekit render`: the limit "
                             "surface coloured by its two-sided distance to the scan; needs the render module)"};
const TextOption kOrder{"--order", "largest", "largest|input",
                        "which scans start first: 'largest' (by estimated work: the file's size over its "
                        "format's bytes per triangle; the longest scans do not end the batch alone) or "
                        "'input' (folder or list order); the tables stay in input order either way"};
const FlagOption kBatchJson{"--json", "print results.json on stdout (the summary line then goes to stderr)"};

// Set by SIGINT / SIGTERM while a batch runs: no new scan starts, the running children are killed.
std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler stores into it");

extern "C" void on_interrupt(int) { g_interrupted.store(true); }

struct Scan {
  std::string path;  // as given (folder entries: IN_DIR/name)
  std::string name;  // its folder in OUT_DIR
};

struct Row {
  std::string file, scan, status, message, ended, used_method, thumbnail;
  double seconds = 0.0, peak_mb = 0.0;
  std::optional<double> faces, error, scan_to_limit, limit_to_scan;
  std::optional<bool> fallback;
  bool resumed = false;
};

bool is_mesh_file(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".off" || ext == ".obj" || ext == ".ply" || ext == ".stl" || ext == ".drc";
}

std::string trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

// The scans of IN: a folder's mesh files (.off .obj .ply .stl .drc, not its subfolders) in name
// order, or a list file's paths (one a line; blank lines and '#' lines skipped; relative paths are
// relative to the list's folder; an optional name after a tab names the scan's output folder).
// Output folder names: the file's stem, made unique in input order (stem, then file name, then
// stem-2, stem-3, ...).
std::vector<Scan> collect_scans(const std::string& in) {
  std::vector<std::pair<std::string, std::string>> entries;  // path, requested name
  std::error_code ec;
  if (fs::is_directory(in, ec)) {
    std::vector<fs::path> found;
    for (const auto& entry : fs::directory_iterator(in, ec))
      if (entry.is_regular_file(ec) && is_mesh_file(entry.path())) found.push_back(entry.path());
    if (ec) throw Failure(kExitBadInput, in + ": cannot list the folder: " + ec.message());
    std::sort(found.begin(), found.end());
    for (const fs::path& p : found) entries.emplace_back(p.string(), "");
  } else if (fs::is_regular_file(in, ec)) {
    if (is_mesh_file(in))
      throw Failure(kExitBadInput, in + ": a mesh file; give a folder of scans or a list file (one path a line)");
    std::ifstream list(in);
    if (!list) throw Failure(kExitBadInput, in + ": cannot read the list");
    const fs::path base = fs::path(in).parent_path();
    std::string line;
    while (std::getline(list, line)) {
      std::string name;
      const size_t tab = line.find('\t');
      if (tab != std::string::npos) {
        name = trim(line.substr(tab + 1));
        line = line.substr(0, tab);
      }
      line = trim(line);
      if (line.empty() || line[0] == '#') continue;
      const fs::path p(line);
      entries.emplace_back(p.is_absolute() || base.empty() ? p.string() : (base / p).string(), name);
    }
  } else {
    throw Failure(kExitBadInput, in + ": no such folder or list file");
  }

  std::set<std::string> taken = {"results.csv", "results.json", "results.csv.tmp", "results.json.tmp"};
  auto clean = [](std::string name) {
    for (char& c : name)
      if (c == '/' || c == '\\' || static_cast<unsigned char>(c) < 32) c = '_';
    if (name.empty() || name == "." || name == "..") name = "scan";
    return name;
  };
  std::vector<Scan> scans;
  for (const auto& [path, requested] : entries) {
    const fs::path p(path);
    std::string name;
    if (!requested.empty()) {
      name = clean(requested);
      if (taken.count(name)) throw Failure(kExitBadInput, in + ": the scan name '" + requested + "' is used twice");
    } else {
      name = clean(p.stem().string());
      if (taken.count(name)) name = clean(p.filename().string());
      for (int k = 2; taken.count(name); ++k) name = clean(p.stem().string()) + "-" + std::to_string(k);
    }
    taken.insert(name);
    scans.push_back({path, name});
  }
  return scans;
}

// A scan's estimated work: its file size over its format's typical bytes per triangle (binary STL
// 50; ASCII STL ~250; OFF/OBJ ~45 for a vertex line per two faces and a face line; PLY ~25, as it is
// binary or ASCII; Draco ~3). Only the order of scans depends on it.
double estimated_work(const std::string& path) {
  std::error_code ec;
  const uintmax_t bytes = fs::file_size(path, ec);
  if (ec) return 0.0;
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  double per_face = 45.0;
  if (ext == ".stl") {
    std::ifstream f(path, std::ios::binary);
    char head[5] = {};
    f.read(head, 5);
    per_face = std::string(head, 5) == "solid" && bytes % 50 != 84 % 50 ? 250.0 : 50.0;
  } else if (ext == ".ply") {
    per_face = 25.0;
  } else if (ext == ".drc") {
    per_face = 3.0;
  }
  return double(bytes) / per_face;
}

std::vector<std::string> split_words(const std::string& text) {
  std::vector<std::string> words;
  std::istringstream in(text);
  std::string w;
  while (in >> w) words.push_back(w);
  return words;
}

std::string self_executable() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw Failure(kExitBadInput, "cannot find the cagekit executable (/proc/self/exe): " + ec.message());
  return self.string();
}

// The first non-empty line of a child's stderr, without the CLI's "cagekit: " prefix.
std::string first_line(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    line = trim(line);
    if (line.rfind("cagekit: ", 0) == 0) line = line.substr(9);
    if (!line.empty()) return line.size() > 400 ? line.substr(0, 400) + "..." : line;
  }
  return "";
}

std::optional<double> number_at(const nlohmann::json& j, std::initializer_list<const char*> keys) {
  const nlohmann::json* at = &j;
  for (const char* k : keys) {
    if (!at->is_object() || !at->contains(k)) return std::nullopt;
    at = &(*at)[k];
  }
  if (!at->is_number()) return std::nullopt;
  return at->get<double>();
}

// Faces of an OBJ file ('f' lines), when the report does not say.
std::optional<double> obj_faces(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  double faces = 0;
  std::string line;
  while (std::getline(in, line))
    if (line.size() > 1 && line[0] == 'f' && (line[1] == ' ' || line[1] == '\t')) ++faces;
  return faces;
}

nlohmann::ordered_json optional_json(const std::optional<double>& x) {
  return x ? json_number(*x) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json row_json(const Row& r) {
  nlohmann::ordered_json j;
  j["file"] = r.file;
  j["scan"] = r.scan;
  j["status"] = r.status;
  j["message"] = r.message;
  j["seconds"] = json_rounded(r.seconds, "%.3f");
  j["peak_mb"] = json_rounded(r.peak_mb, "%.1f");
  j["faces"] = optional_json(r.faces);
  j["two_sided_error"] = optional_json(r.error);
  j["scan_to_limit"] = optional_json(r.scan_to_limit);
  j["limit_to_scan"] = optional_json(r.limit_to_scan);
  j["used_method"] = r.used_method.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.used_method);
  j["fallback"] = r.fallback ? nlohmann::ordered_json(*r.fallback) : nlohmann::ordered_json(nullptr);
  j["ended"] = r.ended;
  j["thumbnail"] = r.thumbnail;
  j["resumed"] = r.resumed;
  return j;
}

std::optional<double> optional_number(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? std::optional<double>(j[key].get<double>()) : std::nullopt;
}

std::string text_at(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
}

Row row_from_json(const nlohmann::json& j) {
  Row r;
  r.file = text_at(j, "file");
  r.scan = text_at(j, "scan");
  r.status = text_at(j, "status");
  r.message = text_at(j, "message");
  r.ended = text_at(j, "ended");
  r.used_method = text_at(j, "used_method");
  r.thumbnail = text_at(j, "thumbnail");
  r.seconds = optional_number(j, "seconds").value_or(0.0);
  r.peak_mb = optional_number(j, "peak_mb").value_or(0.0);
  r.faces = optional_number(j, "faces");
  r.error = optional_number(j, "two_sided_error");
  r.scan_to_limit = optional_number(j, "scan_to_limit");
  r.limit_to_scan = optional_number(j, "limit_to_scan");
  if (j.contains("fallback") && j["fallback"].is_boolean()) r.fallback = j["fallback"].get<bool>();
  return r;
}

// What one run needs, fixed before the scans start.
struct Plan {
  std::vector<std::string> worker;   // argv before SCAN OUTDIR: {cagekit, "pipeline"} or --worker's words
  std::vector<std::string> options;  // the pipeline options given, forwarded to every child
  bool single_thread = false;        // add --threads 1 (--jobs > 1, no --threads given)
  std::string out, self;
  double timeout = 0.0;
  uint64_t memory_limit_bytes = 0;
  bool thumbnails = false;
};

void remove_quietly(const fs::path& p) {
  std::error_code ec;
  fs::remove(p, ec);
}

// Whether OUT_DIR/<scan> may be emptied for a new run: absent, an empty folder, or a folder with a
// file this command or the pipeline writes (an earlier run's). Anything else (OUT_DIR inside the
// scans' folder next to a folder of the same name, a file) is left alone.
bool ours_or_absent(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(dir, ec))) return true;
  if (!fs::is_directory(fs::symlink_status(dir, ec))) return false;
  if (fs::is_empty(dir, ec)) return true;
  for (const char* marker : {"result.json", "pipeline.stderr", "pipeline.stdout"})
    if (fs::exists(dir / marker, ec)) return true;
  return false;
}

// Runs one scan in a child and writes OUT_DIR/<scan>/result.json last. Returns its row; a
// cancelled scan (interrupted batch) returns status "cancelled" and writes no result.
Row run_scan(const Plan& plan, const Scan& scan) {
  Row row;
  row.file = scan.path;
  row.scan = scan.name;
  const fs::path dir = fs::path(plan.out) / scan.name;
  std::error_code ec;
  if (!ours_or_absent(dir)) {
    row.status = "failed";
    row.message = dir.string() + " exists and is not a scan folder of cagekit batch: left as it is";
    return row;  // no result.json written into someone else's folder
  }
  fs::remove_all(dir, ec);  // earlier outputs of this scan (result.json first among them) go
  fs::create_directories(dir, ec);
  if (ec) throw Failure(kExitBadInput, dir.string() + ": cannot create the folder: " + ec.message());

  cagekit_jobs::JobSpec spec;
  spec.argv = plan.worker;
  spec.argv.push_back(scan.path);
  spec.argv.push_back(dir.string());
  spec.argv.insert(spec.argv.end(), plan.options.begin(), plan.options.end());
  if (plan.single_thread) spec.argv.insert(spec.argv.end(), {"--threads", "1"});
  spec.argv.push_back("--quiet");
  spec.stdout_path = (dir / "pipeline.stdout").string();
  spec.stderr_path = (dir / "pipeline.stderr").string();
  spec.timeout_seconds = plan.timeout;
  spec.memory_limit_bytes = plan.memory_limit_bytes;
  spec.cancel = &g_interrupted;
  const cagekit_jobs::JobResult run = cagekit_jobs::run_job(spec);
  row.ended = cagekit_jobs::describe(run);
  row.seconds = run.wall_seconds;
  row.peak_mb = run.peak_rss_mb;
  if (run.cancelled) {
    row.status = "cancelled";
    return row;
  }
  const std::string err = cagekit_jobs::read_file_head(spec.stderr_path, 1 << 16);
  const std::string said = first_line(err);
  if (!run.started) {
    row.status = "failed";
    row.message = row.ended;
  } else if (run.timed_out) {
    row.status = "timeout";
    row.message = row.ended;
  } else if (cagekit_jobs::likely_out_of_memory(run, err)) {
    row.status = "oom";
    row.message = said.empty() ? row.ended : said;
  } else if (run.signaled) {
    row.status = "crash";
    row.message = row.ended + (said.empty() ? "" : ": " + said);
  } else if (run.exit_code == kExitBadInput || run.exit_code == kExitUsage) {
    row.status = "failed";  // the CLI's error convention: one line on stderr
    row.message = said.empty() ? row.ended : said;
  } else if (run.exit_code != 0) {
    row.status = "crash";  // exit 1: an uncaught exception; anything else is no CLI convention
    row.message = row.ended + (said.empty() ? "" : ": " + said);
  } else {
    // Exit 0: complete only with its outputs.
    const fs::path report_path = dir / "report.json";
    nlohmann::json report;
    std::string missing;
    try {
      std::ifstream in(report_path);
      if (!in) throw std::runtime_error("missing");
      report = nlohmann::json::parse(in);
    } catch (const std::exception& e) {
      missing = std::string("report.json: ") + e.what();
    }
    if (missing.empty() && !fs::is_regular_file(dir / "cage.obj", ec)) missing = "no cage.obj";
    if (missing.empty() && !fs::is_regular_file(dir / "limit.obj", ec)) missing = "no limit.obj";
    if (!missing.empty()) {
      row.status = "failed";
      row.message = "exit 0 but " + missing;
    } else {
      row.status = "ok";
      if (report.contains("used_method") && report["used_method"].is_string())
        row.used_method = report["used_method"].get<std::string>();
      if (report.contains("fallback") && report["fallback"].is_boolean()) row.fallback = report["fallback"].get<bool>();
      row.faces = number_at(report, {"simplify", "cage_faces"});
      if (!row.faces) row.faces = number_at(report, {"remesh", "faces"});
      if (!row.faces) row.faces = obj_faces((dir / "cage.obj").string());
      row.error = number_at(report, {"limit", "error", "hausdorff_sym_rel"});
      row.scan_to_limit = number_at(report, {"quality", "scan_to_limit_max_rel"});
      if (!row.scan_to_limit) row.scan_to_limit = number_at(report, {"limit", "error", "hausdorff_rel"});
      row.limit_to_scan = number_at(report, {"quality", "limit_to_scan_max_rel"});
      if (!row.error && row.scan_to_limit && row.limit_to_scan)
        row.error = std::max(*row.scan_to_limit, *row.limit_to_scan);
    }
  }

  if (plan.thumbnails && row.status == "ok" && !g_interrupted.load()) {
    cagekit_jobs::JobSpec render;
    const std::string png = (dir / "thumbnail.png").string();
    render.argv = {plan.self, "render", png, "--cage", (dir / "cage.obj").string(), "--error", scan.path,
                   "--size", "320x240", "--title", scan.name, "--quiet"};
    render.stderr_path = (dir / "thumbnail.stderr").string();
    render.timeout_seconds = plan.timeout > 0.0 ? plan.timeout : 300.0;
    render.memory_limit_bytes = plan.memory_limit_bytes;
    render.cancel = &g_interrupted;
    const cagekit_jobs::JobResult drawn = cagekit_jobs::run_job(render);
    if (drawn.started && drawn.exited && drawn.exit_code == 0 && fs::is_regular_file(png, ec)) {
      row.thumbnail = "thumbnail.png";
      remove_quietly(render.stderr_path);
    } else if (drawn.cancelled) {
      row.status = "cancelled";
      return row;
    } else {
      // A missing picture never changes the scan's status; why it is missing stays in thumbnail.stderr.
      remove_quietly(png);
    }
  }

  nlohmann::ordered_json result;
  result["format"] = kResultFormat;
  result["options"] = plan.options;
  result["command"] = spec.argv;
  result.update(row_json(row));
  result.erase("resumed");
  write_text_file((dir / "result.json").string(), json_text(result) + "\n");
  return row;
}

// Options as (name, value) pairs in name order ("" for a flag): the same options given in another
// order are the same.
std::vector<std::pair<std::string, std::string>> option_pairs(const std::vector<std::string>& words) {
  std::vector<std::pair<std::string, std::string>> pairs;
  for (size_t k = 0; k < words.size(); ++k) {
    if (k + 1 < words.size() && words[k + 1].rfind("--", 0) != 0) {
      pairs.emplace_back(words[k], words[k + 1]);
      ++k;
    } else {
      pairs.emplace_back(words[k], "");
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

// The earlier result of `scan` when --resume may keep it: result.json of this file, made with the
// same pipeline options (in any order).
std::optional<Row> earlier_result(const Plan& plan, const Scan& scan) {
  const fs::path path = fs::path(plan.out) / scan.name / "result.json";
  std::ifstream in(path);
  if (!in) return std::nullopt;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (!j.is_object() || text_at(j, "format") != kResultFormat || text_at(j, "file") != scan.path ||
        !j.contains("options") || !j["options"].is_array())
      return std::nullopt;
    std::vector<std::string> options;
    for (const nlohmann::json& w : j["options"]) {
      if (!w.is_string()) return std::nullopt;
      options.push_back(w.get<std::string>());
    }
    if (option_pairs(options) != option_pairs(plan.options)) return std::nullopt;
    Row row = row_from_json(j);
    if (row.status.empty()) return std::nullopt;
    row.scan = scan.name;
    row.resumed = true;
    return row;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

std::string csv_number(const std::optional<double>& x, const char* format) {
  if (!x) return "";
  char buffer[48];
  std::snprintf(buffer, sizeof(buffer), format, *x);
  return buffer;
}

std::string csv_table(const std::vector<const Row*>& rows) {
  std::string csv =
      "file,scan,status,message,seconds,peak_mb,faces,two_sided_error,scan_to_limit,limit_to_scan,used_method,"
      "fallback,ended,thumbnail,resumed\n";
  for (const Row* r : rows) {
    const std::vector<std::string> fields = {
        csv_field(r->file), csv_field(r->scan), r->status, csv_field(r->message), csv_number(r->seconds, "%.3f"),
        csv_number(r->peak_mb, "%.1f"), csv_number(r->faces, "%.0f"), csv_number(r->error, "%.6g"),
        csv_number(r->scan_to_limit, "%.6g"), csv_number(r->limit_to_scan, "%.6g"), csv_field(r->used_method),
        r->fallback ? (*r->fallback ? "true" : "false") : "", csv_field(r->ended), csv_field(r->thumbnail),
        r->resumed ? "true" : "false"};
    for (size_t k = 0; k < fields.size(); ++k) csv += (k ? "," : "") + fields[k];
    csv += "\n";
  }
  return csv;
}

std::string duration_text(double seconds) {
  char buffer[32];
  const long s = long(seconds + 0.5);
  if (s >= 3600) std::snprintf(buffer, sizeof(buffer), "%ldh%02ldm", s / 3600, (s / 60) % 60);
  else if (s >= 60) std::snprintf(buffer, sizeof(buffer), "%ldm%02lds", s / 60, s % 60);
  else std::snprintf(buffer, sizeof(buffer), "%lds", s);
  return buffer;
}

// Progress on stderr: one redrawn line on a terminal, else one line per finished scan.
class Progress {
 public:
  Progress(bool quiet, size_t total, size_t resumed, size_t resumed_failed)
      : quiet_(quiet), terminal_(isatty(fileno(stderr)) != 0), total_(total), done_(resumed),
        failed_(resumed_failed), resumed_(resumed), start_(std::chrono::steady_clock::now()) {}

  void started() {
    std::lock_guard<std::mutex> lock(mutex_);
    ++running_;
  }
  void finished(const Row& row) {
    std::lock_guard<std::mutex> lock(mutex_);
    --running_;
    if (row.status == "cancelled") return;
    ++done_;
    if (row.status != "ok") ++failed_;
    if (quiet_) return;
    if (terminal_) {
      draw_locked();
    } else {
      std::fprintf(stderr, "cagekit batch: [%zu/%zu] %s: %s (%.1f s)%s%s | %s\n", done_, total_, row.scan.c_str(),
                   row.status.c_str(), row.seconds, row.message.empty() ? "" : ": ", row.message.c_str(),
                   counts_locked().c_str());
    }
  }
  void tick() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!quiet_ && terminal_) draw_locked();
  }
  void end() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!quiet_ && terminal_ && drawn_) std::fputc('\n', stderr);
    drawn_ = false;
  }

 private:
  std::string counts_locked() const {
    const size_t ran = done_ - resumed_, left = total_ - done_;
    const double elapsed = seconds_since(start_);
    std::string eta = left == 0 ? "0s" : ran == 0 ? "?" : duration_text(elapsed / double(ran) * double(left));
    char buffer[160];
    std::snprintf(buffer, sizeof(buffer), "%zu/%zu done, %zu failed, %zu running, ETA %s", done_, total_, failed_,
                  running_, eta.c_str());
    return buffer;
  }
  void draw_locked() {
    std::fprintf(stderr, "\rcagekit batch: %-70s", counts_locked().c_str());
    std::fflush(stderr);
    drawn_ = true;
  }

  std::mutex mutex_;
  const bool quiet_, terminal_;
  const size_t total_;
  size_t done_, failed_, resumed_, running_ = 0;
  bool drawn_ = false;
  const std::chrono::steady_clock::time_point start_;
};

// SIGINT / SIGTERM handlers while the batch runs; the earlier ones come back after.
class InterruptGuard {
 public:
  InterruptGuard() {
    g_interrupted.store(false);
    struct sigaction action {};
    action.sa_handler = on_interrupt;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
  }
  ~InterruptGuard() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

int command_batch(const Options& args, const std::vector<std::string>& pipeline_names, const std::string& worker) {
  const bool quiet = args.quiet();
  const bool json = args.flag(kBatchJson);
  Plan plan;
  const int jobs = args.integer(kJobs);
  plan.timeout = args.real(kTimeout);
  plan.memory_limit_bytes = uint64_t(args.integer(kMemoryLimit)) * 1024u * 1024u;
  plan.thumbnails = args.flag(kThumbnails);
  plan.out = args.positional("OUT_DIR");
  const std::string in = args.positional("IN");
  const std::string order = args.text(kOrder);
  if (order != "largest" && order != "input")
    throw Failure(kExitUsage, "--order must be 'largest' or 'input', not '" + order + "'");

  // The pipeline options given, in declaration order, forwarded as the child's arguments.
  const std::string method =
      args.given("--method") ? args.app()->get_option("--method")->results().back() : std::string("simplify");
  if (method != "simplify" && method != "quad" && method != "anisotropic")
    throw Failure(kExitUsage, "--method must be 'simplify', 'anisotropic' or 'quad', not '" + method + "'");
  if (method == "simplify" && !args.given("--faces") && !args.given("--vertices"))
    throw Failure(kExitUsage, "batch --method simplify needs one of --faces N or --vertices N");
  for (const std::string& name : pipeline_names) {
    const CLI::Option* o = args.app()->get_option(name);
    if (o->count() == 0) continue;
    if (o->get_expected_max() == 0) {  // a flag
      plan.options.push_back(name);
    } else {
      for (const std::string& value : o->results()) plan.options.insert(plan.options.end(), {name, value});
    }
  }
  plan.single_thread = jobs > 1 && !args.given("--threads");

  plan.self = self_executable();
  std::string worker_text = worker;
  if (worker_text.empty()) {
    const char* env = std::getenv("CAGEKIT_BATCH_WORKER");
    if (env) worker_text = env;
  }
  plan.worker = split_words(worker_text);
  if (plan.worker.empty()) plan.worker = {plan.self, "pipeline"};

  const std::vector<Scan> scans = collect_scans(in);
  if (scans.empty()) throw Failure(kExitBadInput, in + ": no scans (.off .obj .ply .stl .drc)");
  make_directories(plan.out);

  std::vector<Row> rows(scans.size());
  std::vector<char> have(scans.size(), 0);
  std::vector<size_t> queue;
  size_t resumed = 0, resumed_failed = 0, retried = 0;
  const bool retry_failed = args.flag(kRetryFailed);
  for (size_t i = 0; i < scans.size(); ++i) {
    std::optional<Row> earlier =
        args.flag(kResume) || retry_failed ? earlier_result(plan, scans[i]) : std::nullopt;
    if (earlier && retry_failed && earlier->status != "ok") {
      earlier.reset();
      ++retried;
    }
    if (earlier) {
      rows[i] = *earlier;
      have[i] = 1;
      ++resumed;
      resumed_failed += earlier->status != "ok";
    } else {
      queue.push_back(i);
    }
  }

  if (order == "largest") {
    std::vector<double> work(scans.size(), 0.0);
    for (size_t i : queue) work[i] = estimated_work(scans[i].path);
    std::stable_sort(queue.begin(), queue.end(), [&](size_t a, size_t b) { return work[a] > work[b]; });
  }

  const auto start = std::chrono::steady_clock::now();
  Progress progress(quiet, scans.size(), resumed, resumed_failed);
  std::string fatal;  // a problem of the batch itself (OUT_DIR not writable): stops it
  {
    InterruptGuard guard;
    std::atomic<size_t> next{0};
    std::mutex mutex;
    std::condition_variable ended;
    size_t threads_left = std::min(size_t(jobs), queue.size());
    std::vector<std::thread> threads;
    for (size_t t = 0, n = threads_left; t < n; ++t) {
      threads.emplace_back([&] {
        for (;;) {
          const size_t k = next++;
          if (k >= queue.size() || g_interrupted.load()) break;
          const size_t i = queue[k];
          progress.started();
          Row row;
          try {
            row = run_scan(plan, scans[i]);
          } catch (const std::exception& e) {
            row.status = "cancelled";
            std::lock_guard<std::mutex> lock(mutex);
            if (fatal.empty()) fatal = e.what();
            g_interrupted.store(true);
          }
          progress.finished(row);
          if (row.status != "cancelled") {
            std::lock_guard<std::mutex> lock(mutex);
            rows[i] = row;
            have[i] = 1;
          }
        }
        std::lock_guard<std::mutex> lock(mutex);
        --threads_left;
        ended.notify_all();
      });
    }
    std::unique_lock<std::mutex> lock(mutex);
    while (threads_left > 0) {
      ended.wait_for(lock, std::chrono::milliseconds(250));
      lock.unlock();
      progress.tick();
      lock.lock();
    }
    lock.unlock();
    for (std::thread& t : threads) t.join();
    progress.end();
  }
  const bool interrupted = g_interrupted.load();
  g_interrupted.store(false);
  if (!fatal.empty()) throw Failure(kExitBadInput, fatal);
  const double seconds = seconds_since(start);

  // The tables: every scan with a result, in input order.
  std::vector<const Row*> table;
  size_t ok = 0, failed = 0, timeout = 0, crash = 0, oom = 0;
  for (size_t i = 0; i < scans.size(); ++i) {
    if (!have[i]) continue;
    const Row& r = rows[i];
    table.push_back(&r);
    ok += r.status == "ok";
    failed += r.status == "failed";
    timeout += r.status == "timeout";
    crash += r.status == "crash";
    oom += r.status == "oom";
  }
  const size_t missing = scans.size() - table.size();
  nlohmann::ordered_json j;
  j["format"] = kTableFormat;
  j["input"] = in;
  j["method"] = method;
  j["options"] = plan.options;
  j["worker"] = plan.worker;
  j["jobs"] = jobs;
  j["order"] = order;
  j["timeout"] = json_number(plan.timeout);
  j["memory_limit_mb"] = args.integer(kMemoryLimit);
  nlohmann::ordered_json& s = j["summary"];
  s["scans"] = scans.size();
  s["ok"] = ok;
  s["failed"] = failed;
  s["timeout"] = timeout;
  s["crash"] = crash;
  s["oom"] = oom;
  s["resumed"] = resumed;
  s["retried"] = retried;
  s["not_run"] = missing;
  s["seconds"] = json_rounded(seconds, "%.3f");
  nlohmann::ordered_json& list = j["rows"];
  list = nlohmann::ordered_json::array();
  for (const Row* r : table) list.push_back(row_json(*r));
  const std::string json_path = (fs::path(plan.out) / "results.json").string();
  const std::string csv_path = (fs::path(plan.out) / "results.csv").string();
  const std::string json_report = json_text(j, ",\n ") + "\n";
  write_text_file(csv_path, csv_table(table));
  write_text_file(json_path, json_report);

  if (json) std::fputs(json_report.c_str(), stdout);
  if (!quiet) {
    std::FILE* out = json ? stderr : stdout;
    std::fprintf(out, "cagekit batch: %zu scans: %zu ok, %zu failed, %zu timeout, %zu crash, %zu oom", scans.size(),
                 ok, failed, timeout, crash, oom);
    if (resumed || retried) {
      std::fprintf(out, " (");
      if (resumed) std::fprintf(out, "%zu resumed%s", resumed, retried ? ", " : "");
      if (retried) std::fprintf(out, "%zu failed before, run again", retried);
      std::fprintf(out, ")");
    }
    if (missing) std::fprintf(out, ", %zu not run (interrupted: --resume goes on)", missing);
    std::fprintf(out, " in %.1f s; %s\n", seconds, csv_path.c_str());
  }
  if (interrupted) return 130;
  return ok == scans.size() ? kExitOk : kExitBadInput;
}

}  // namespace

Command add_batch(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand(
      "batch", "`cagekit pipeline` on every scan of a folder or a list, each in its own child process (a crash, "
               "timeout or out-of-memory ends only its scan); writes OUT_DIR/<scan>/ and OUT_DIR/results.csv, "
               "results.json (exit 2 when a scan is not ok, 130 when interrupted)");
  auto options = std::make_shared<Options>(app);
  options->add_positional("IN", "a folder of scans (.off .obj .ply .stl .drc) or a list file (one path a line, "
                                "relative to the list's folder; 'PATH<TAB>NAME' names its output folder)");
  options->add_positional("OUT_DIR", "output folder (created with its parents)");
  std::vector<std::string> before;
  for (const CLI::Option* o : app->get_options()) before.push_back(o->get_name());
  add_pipeline_options(*options);
  auto pipeline_names = std::make_shared<std::vector<std::string>>();
  for (const CLI::Option* o : app->get_options())
    if (std::find(before.begin(), before.end(), o->get_name()) == before.end())
      pipeline_names->push_back(o->get_name());
  app->get_option("--method")->description("the pipeline's method; it and the other pipeline options given are "
                                           "forwarded to each scan's `cagekit pipeline`");
  options->add(kJobs);
  options->add(kTimeout);
  options->add(kMemoryLimit);
  options->add(kResume);
  options->add(kRetryFailed);
  options->add(kThumbnails);
  options->add(kOrder);
  options->add(kBatchJson);
  options->add_quiet();
  // Hidden: another program in place of `cagekit pipeline` (its words, split at spaces; it gets
  // SCAN OUTDIR and the options), for tests of the isolation; env CAGEKIT_BATCH_WORKER too.
  auto worker = std::make_shared<std::string>();
  app->add_option("--worker", *worker, "the child command instead of `cagekit pipeline`")->group("");
  return {app, [options, pipeline_names, worker] { return command_batch(*options, *pipeline_names, *worker); }};
}

}  // namespace cli
