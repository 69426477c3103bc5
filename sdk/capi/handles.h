// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The objects behind the C API's opaque handles. Each starts with a type tag (checked on every
// call, so a wrong or released handle is reported as CAGEKIT_ERROR_INVALID_HANDLE as far as
// that can be detected) and an atomic reference count.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include <cagekit/cagekit.h>

#include "core/cage.h"
#include "core/task_monitor.h"
#include "layout/simplify/face_merge_simplifier.h"
#include "subdiv/limit_bspline_surfaces.h"
#include "subdiv/limit_patches.h"
#include "subdiv/subdivision_surface.h"
#include "multires/cpu_deformer.h"
#include "multires/scan_binding.h"

namespace cagekit_capi {

enum class HandleType : uint32_t {
  context = 0x43544b31,  // "CTK1"
  mesh = 0x4d534831,     // "MSH1"
  cage = 0x43474531,     // "CGE1"
  surface = 0x53524631,  // "SRF1"
  blob = 0x424c4231,     // "BLB1"
  hierarchy = 0x48524331, // "HRC1"
  binding = 0x424e4431,   // "BND1"
  cpu_deformer = 0x43444631, // "CDF1"
  limit_patches = 0x4c505431, // "LPT1"
  limit_surfaces = 0x4c535231, // "LSR1"
  dead = 0xdeadbeef,
};

struct Handle {
  explicit Handle(HandleType t) : type(t) {}
  virtual ~Handle() { type = HandleType::dead; }
  std::atomic<HandleType> type;
  std::atomic<int> references{1};
};

}  // namespace cagekit_capi

struct cagekit_context_t : cagekit_capi::Handle {
  static constexpr cagekit_capi::HandleType kType = cagekit_capi::HandleType::context;
  cagekit_context_t() : Handle(kType) {}

  cagekit_log_fn log = nullptr;
  void* log_user_data = nullptr;
  cagekit_log_level log_level = CAGEKIT_LOG_WARNING;
  cagekit_progress_fn progress = nullptr;
  void* progress_user_data = nullptr;
  std::atomic<bool> cancel_requested{false};
  uint64_t memory_budget = 0;  // bytes per call, 0 = unlimited (set at creation, then read-only)

  std::mutex error_mutex;
  std::unordered_map<std::thread::id, std::string> last_error;  // nodes are stable: c_str() stays valid

  // Progress + cancellation + log forwarding for a long operation started now.
  cagekit::TaskMonitor monitor();
  void log_message(cagekit_log_level level, const std::string& message);
};

// Objects made by a context keep it alive.
struct ContextBound : cagekit_capi::Handle {
  ContextBound(cagekit_capi::HandleType t, cagekit_context c);
  ~ContextBound() override;
  cagekit_context context;
};

struct cagekit_mesh_t : ContextBound {
  static constexpr cagekit_capi::HandleType kType = cagekit_capi::HandleType::mesh;
  cagekit_mesh_t(cagekit_context c, cagekit::PolygonMesh m) : ContextBound(kType, c), mesh(std::move(m)) {}
  cagekit::PolygonMesh mesh;
};

struct cagekit_cage_t : ContextBound {
  static constexpr cagekit_capi::HandleType kType = cagekit_capi::HandleType::cage;
  cagekit_cage_t(cagekit_context c, cagekit::Cage g) : ContextBound(kType, c), cage(std::move(g)) {}
  cagekit::Cage cage;
};

struct cagekit_surface_t : ContextBound {
  static constexpr cagekit_capi::HandleType kType = cagekit_capi::HandleType::surface;
  cagekit_surface_t(cagekit_context c, cagekit::SubdivisionSurface s)
      : ContextBound(kType, c), surface(std::move(s)) {}
  cagekit::SubdivisionSurface surface;
};

struct cagekit_limit_patches_t : ContextBound {
  static constexpr cagekit_capi::HandleType kType = cagekit_capi::HandleType::limit_patches;
  cagekit_limit_patches_t(cagekit_context c, cagekit::LimitPatches p) : ContextBound(kType, c), patches(std::move(p)) {}
  const cagekit::LimitPatches patches;
};

struct cagekit_limit_surfaces_t : ContextBound {
  static constexpr cagekit_capi::HandleType kType = cagekit_capi::HandleType::limit_surfaces;
  cagekit_limit_surfaces_t(cagekit_context c, cagekit::LimitBSplineSurfaces s)
      : ContextBound(kType, c), surfaces(std::move(s)) {}
  const cagekit::LimitBSplineSurfaces surfaces;
};

struct cagekit_hierarchy_t : ContextBound {
  static constexpr cagekit_capi::HandleType kType = cagekit_capi::HandleType::hierarchy;
  cagekit_hierarchy_t(cagekit_context c, cagekit::SimplificationHierarchy h, std::vector<uint64_t> locked)
      : ContextBound(kType, c), hierarchy(std::move(h)), level(hierarchy.extract()), sharp_edges(std::move(locked)) {}
  cagekit::SimplificationHierarchy hierarchy;
  cagekit::PolygonalLevel level;  // extract() of the current level, refreshed by set_level
  std::vector<uint64_t> sharp_edges;  // the host's, locked in the hierarchy: creases of its cages
};

struct cagekit_binding_t : ContextBound {
  static constexpr cagekit_capi::HandleType kType = cagekit_capi::HandleType::binding;
  cagekit_binding_t(cagekit_context c, cagekit::ScanBinding b, cagekit::Cage g, cagekit::BindOptions o)
      : ContextBound(kType, c), binding(std::move(b)), cage(std::move(g)), options(std::move(o)) {}
  // Immutable once made: shared by deformers.
  const cagekit::ScanBinding binding;
  const cagekit::Cage cage;            // the cage it was bound to (saved with it)
  const cagekit::BindOptions options;  // the options it was made with (saved with it)
};

// Keeps its binding alive (a reference) for as long as it exists.
struct cagekit_cpu_deformer_t : ContextBound {
  static constexpr cagekit_capi::HandleType kType = cagekit_capi::HandleType::cpu_deformer;
  cagekit_cpu_deformer_t(cagekit_context c, cagekit_binding_t* b, int threads);
  ~cagekit_cpu_deformer_t() override;
  cagekit_binding_t* binding;
  cagekit::CpuDeformer deformer;
  std::vector<cagekit::Vec3> control;  // the caller's control points of the last call
  bool deformed = false, exact = false;
};

struct cagekit_blob_t : cagekit_capi::Handle {
  static constexpr cagekit_capi::HandleType kType = cagekit_capi::HandleType::blob;
  explicit cagekit_blob_t(std::vector<uint8_t> b) : Handle(kType), bytes(std::move(b)) {}
  std::vector<uint8_t> bytes;
};
