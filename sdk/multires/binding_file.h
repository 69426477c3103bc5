// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The saved scan binding (`.ckb`, issue #5: `cagekit bind SCAN CAGE OUT.ckb`): a binding is
// expensive to make (one exact closest-point search per scan vertex, §7.4) and cheap to
// rebuild from what the search found, so the file keeps only
//   - the cage it was bound to (OBJ text with OpenSubdiv tags, 17 significant digits: exact),
//   - the options that shape the limit surface and the binding,
//   - per scan vertex: the foot point (ptex face, u, v), its distance, the displacement D (and
//     in local-frame mode the tangent offsets), the normal coefficients (8.11)-(8.12) (and with
//     exact normals the displacement gradient),
// and reading rebuilds the limit surface, the basis rows (8.3) and the compact deformer table
// from them — bit-identical to the binding that was saved (tested).
//
// Layout (all integers and doubles little-endian): "CAGEKITB" magic, u32 format version (1),
// u32 section count, then sections {u32 tag, u64 payload bytes, payload}: "CAGE" (OBJ text),
// "OPTS" (options and summary figures), "VERT" (u64 vertex count, then the per-vertex arrays),
// and with a sector split "SECT" (the scan vertex count, each bound vertex's source vertex, the
// faces over the bound vertices).
// Unknown sections are skipped (later versions may add some); every section must appear once.
//
// The reader treats the bytes as hostile (the fuzz harness tests/fuzz/fuzz_binding.cpp): sizes
// that do not fit the remaining bytes, counts above the limits, non-finite numbers, foot points
// outside [0,1]^2 or on no limit surface, option values out of range, a cage the OBJ reader or
// the subdivision layer refuses — each is an Error(parse_error / limit_exceeded /
// invalid_mesh) naming the byte offset or the field.
#include <cstdint>
#include <string>
#include <vector>

#include "core/cage.h"
#include "core/task_monitor.h"
#include "multires/scan_binding.h"

CAGEKIT_NAMESPACE_BEGIN

struct SavedBinding {
  Cage cage;            // the cage the scan was bound to
  BindOptions options;  // mode, exact_normals, surface, patch_table, compact_table (threads: 0)
  ScanBinding binding;
};

// Encodes `binding`, made by bind_scan_to_cage(cage, scan, options).
std::vector<uint8_t> write_binding(const ScanBinding& binding, const Cage& cage, const BindOptions& options);

// Decodes and rebuilds; `threads` (0 = all cores) for the rebuild. `source_name` for messages.
SavedBinding read_binding(const uint8_t* data, size_t size, const std::string& source_name, int threads = 0,
                          const TaskMonitor& monitor = {});

CAGEKIT_NAMESPACE_END
