// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The corpus harness's contact sheet (issue 24, `corpus_harness --thumbnails`): one thumbnail per
// (mesh, method) drawn through the public C API's render module (cagekit_render_*), pages of
// thumbnails and an index.html whose table rows link to them. A thumbnail that cannot be drawn
// (the scan or the cage does not read, no EGL here) becomes a placeholder with the reason in the
// index; it never changes a record.
#include <cagekit/cagekit.h>

#include <cstdint>
#include <string>
#include <vector>

namespace cagekit_corpus {

constexpr uint32_t kThumbWidth = 240, kThumbHeight = 200;
constexpr uint32_t kPageColumns = 5, kPageRows = 6;  // 30 thumbnails per page (1200 x 1200)

struct Thumbnail {
  std::vector<uint8_t> rgba;  // kThumbWidth x kThumbHeight RGBA, rows top first
  bool drawn = false;         // false: a placeholder (see note)
  std::string note;           // what is shown, or why it is a placeholder
};

// The cage at cage_path (empty or unreadable: the scan alone) as its limit surface, coloured by
// its two-sided distance to the scan with a legend; `title` above it (truncated to fit).
Thumbnail render_thumbnail(cagekit_context context, const std::string& scan_path, const std::string& cage_path,
                           const std::string& title);

// One row of the contact sheet's table.
struct SheetRow {
  std::string mesh, method, status, error_text, faces_text, message;
  const Thumbnail* thumbnail = nullptr;
};

// Writes OUT/thumbnails/<n>.png (one per row), OUT/thumbnails/page-NN.png (kPageColumns x kPageRows
// per page, in the rows' order) and OUT/index.html (the table, every row linked to its thumbnail
// and its page; the pages below). `summary` lines go above the table. Returns the number of
// pages; throws std::runtime_error when a file cannot be written.
size_t write_contact_sheet(cagekit_context context, const std::string& out, const std::vector<SheetRow>& rows,
                           const std::vector<std::string>& summary);

}  // namespace cagekit_corpus
