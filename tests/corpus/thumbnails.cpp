// SPDX-License-Identifier: GPL-3.0-or-later
#include "thumbnails.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace cagekit_corpus {

namespace fs = std::filesystem;

namespace {

// A light grey tile with a darker cross: "no picture" (the index says why).
std::vector<uint8_t> placeholder() {
  std::vector<uint8_t> rgba(4 * size_t(kThumbWidth) * kThumbHeight, 255);
  for (uint32_t y = 0; y < kThumbHeight; ++y)
    for (uint32_t x = 0; x < kThumbWidth; ++x) {
      uint8_t* px = &rgba[4 * (size_t(y) * kThumbWidth + x)];
      const int on_diagonal = std::abs(int(x * kThumbHeight) - int(y * kThumbWidth)) < int(2 * kThumbWidth) ||
                              std::abs(int((kThumbWidth - 1 - x) * kThumbHeight) - int(y * kThumbWidth)) <
                                  int(2 * kThumbWidth);
      px[0] = px[1] = px[2] = on_diagonal ? 170 : 232;
    }
  return rgba;
}

std::string error_of(cagekit_context context, const char* what) {
  return std::string(what) + ": " + cagekit_last_error_message(context);
}

struct Scene {
  cagekit_render_scene h = nullptr;
  ~Scene() { cagekit_render_scene_release(h); }
};
struct MeshRef {
  cagekit_mesh h = nullptr;
  ~MeshRef() { cagekit_mesh_release(h); }
};
struct CageRef {
  cagekit_cage h = nullptr;
  ~CageRef() { cagekit_cage_release(h); }
};

std::string html(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

std::string file_safe(const std::string& s) {
  std::string out;
  for (const char c : s) out += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' ? c : '_';
  return out;
}

void write_png(cagekit_context context, const std::vector<uint8_t>& rgba, uint32_t w, uint32_t h,
               const fs::path& path) {
  if (cagekit_render_encode_png(context, rgba.data(), w, h, path.string().c_str(), nullptr) != CAGEKIT_SUCCESS)
    throw std::runtime_error(path.string() + ": " + cagekit_last_error_message(context));
}

}  // namespace

Thumbnail render_thumbnail(cagekit_context context, const std::string& scan_path, const std::string& cage_path,
                           const std::string& title) {
  Thumbnail t;
  t.rgba = placeholder();
  MeshRef scan;
  if (cagekit_mesh_read_file(context, scan_path.c_str(), CAGEKIT_FORMAT_AUTO, &scan.h) != CAGEKIT_SUCCESS) {
    t.note = error_of(context, "the scan does not read");
    return t;
  }
  CageRef cage;
  std::string cage_problem;
  if (cage_path.empty() || !fs::exists(cage_path)) cage_problem = "no cage";
  else if (cagekit_cage_read_file(context, cage_path.c_str(), CAGEKIT_FORMAT_AUTO, &cage.h) != CAGEKIT_SUCCESS)
    cage_problem = error_of(context, "the cage does not read");
  Scene scene;
  if (cagekit_render_scene_create(context, &scene.h) != CAGEKIT_SUCCESS) {
    t.note = error_of(context, "render");
    return t;
  }
  cagekit_render_options options = CAGEKIT_RENDER_OPTIONS_INIT;
  options.width = kThumbWidth;
  options.height = kThumbHeight;
  cagekit_render_scene_set_options(scene.h, &options);
  // The title, truncated to the tile (5x7 glyphs, 6 pixels a character at this size).
  std::string text = title.substr(0, (kThumbWidth - 8) / 6);
  cagekit_render_item_options item = CAGEKIT_RENDER_ITEM_OPTIONS_INIT;
  item.title = text.c_str();
  if (cage.h != nullptr) {
    item.tessellation_level = 2;  // enough for 240 x 200 pixels, and quick to measure
    if (cagekit_render_scene_add_cage(scene.h, cage.h, &item, nullptr) != CAGEKIT_SUCCESS) {
      t.note = error_of(context, "the cage cannot be drawn");
      return t;
    }
    if (cagekit_render_scene_set_distance_to_scan(scene.h, 0, scan.h, nullptr) == CAGEKIT_SUCCESS)
      t.note = "limit surface (level 2) coloured by its two-sided distance to the scan";
    else
      t.note = "limit surface, uncoloured: " + error_of(context, "distance to the scan");
  } else {
    if (cagekit_render_scene_add_mesh(scene.h, scan.h, CAGEKIT_RENDER_ITEM_MESH, &item, nullptr) != CAGEKIT_SUCCESS) {
      t.note = error_of(context, "the scan cannot be drawn");
      return t;
    }
    t.note = "the scan (" + cage_problem + ")";
  }
  std::vector<uint8_t> rgba(4 * size_t(kThumbWidth) * kThumbHeight);
  uint32_t count = 0;
  if (cagekit_render_scene_draw(scene.h, kThumbWidth * kThumbHeight, &count, rgba.data()) != CAGEKIT_SUCCESS) {
    t.note = error_of(context, "not drawn");
    return t;
  }
  t.rgba.swap(rgba);
  t.drawn = true;
  return t;
}

size_t write_contact_sheet(cagekit_context context, const std::string& out, const std::vector<SheetRow>& rows,
                           const std::vector<std::string>& summary) {
  const fs::path dir = fs::path(out) / "thumbnails";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot create: " + ec.message());
  const size_t per_page = size_t(kPageColumns) * kPageRows;
  const size_t pages = (rows.size() + per_page - 1) / per_page;
  const uint32_t page_w = kPageColumns * kThumbWidth, page_h = kPageRows * kThumbHeight;
  std::vector<std::string> thumb_names(rows.size());
  for (size_t p = 0; p < pages; ++p) {
    std::vector<uint8_t> page(4 * size_t(page_w) * page_h, 255);
    for (size_t k = p * per_page; k < std::min(rows.size(), (p + 1) * per_page); ++k) {
      const std::vector<uint8_t>& rgba = rows[k].thumbnail->rgba;
      const uint32_t x0 = uint32_t((k - p * per_page) % kPageColumns) * kThumbWidth;
      const uint32_t y0 = uint32_t((k - p * per_page) / kPageColumns) * kThumbHeight;
      for (uint32_t y = 0; y < kThumbHeight; ++y) {
        std::memcpy(&page[4 * (size_t(y0 + y) * page_w + x0)], &rgba[4 * size_t(y) * kThumbWidth], 4 * kThumbWidth);
        // A one-pixel grey frame between tiles.
        for (uint32_t x : {x0, x0 + kThumbWidth - 1}) std::memset(&page[4 * (size_t(y0 + y) * page_w + x)], 200, 3);
      }
      for (uint32_t y : {y0, y0 + kThumbHeight - 1})
        for (uint32_t x = x0; x < x0 + kThumbWidth; ++x) std::memset(&page[4 * (size_t(y) * page_w + x)], 200, 3);
      char name[32];
      std::snprintf(name, sizeof(name), "%04zu-", k + 1);
      thumb_names[k] = name + file_safe(rows[k].mesh) + "." + file_safe(rows[k].method) + ".png";
      write_png(context, rgba, kThumbWidth, kThumbHeight, dir / thumb_names[k]);
    }
    char name[32];
    std::snprintf(name, sizeof(name), "page-%02zu.png", p + 1);
    write_png(context, page, page_w, page_h, dir / name);
  }

  std::string h =
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>CageKit corpus contact sheet</title>\n"
      "<style>body{font-family:sans-serif} table{border-collapse:collapse} td,th{border:1px solid #ccc;"
      "padding:2px 6px;font-size:13px} td.n{text-align:right}</style></head><body>\n"
      "<h1>CageKit corpus contact sheet</h1>\n<ul>\n";
  for (const std::string& line : summary) h += "<li><code>" + html(line) + "</code></li>\n";
  h += "</ul>\n<p>Each thumbnail: the method's cage as its limit surface (level 2) coloured by its two-sided "
       "distance to the scan (legend: absolute units); where no cage was made, the scan. Title: status, "
       "two-sided error (max of scan&rarr;limit and limit&rarr;scan, % of the diagonal), mesh.</p>\n";
  h += "<table>\n<tr><th>#</th><th>mesh</th><th>method</th><th>status</th><th>two-sided error</th><th>faces</th>"
       "<th>picture</th><th>page</th><th>message</th></tr>\n";
  for (size_t k = 0; k < rows.size(); ++k) {
    const SheetRow& r = rows[k];
    char page[32];
    std::snprintf(page, sizeof(page), "page-%02zu.png", k / per_page + 1);
    const std::string where = std::to_string(k / per_page + 1) + ", tile " + std::to_string(k % per_page + 1);
    h += "<tr id=\"r" + std::to_string(k + 1) + "\"><td class=\"n\">" + std::to_string(k + 1) + "</td><td>" +
         html(r.mesh) + "</td><td>" + html(r.method) + "</td><td>" + html(r.status) + "</td><td class=\"n\">" +
         html(r.error_text) + "</td><td class=\"n\">" + html(r.faces_text) + "</td><td><a href=\"thumbnails/" +
         html(thumb_names[k]) + "\" title=\"" + html(r.thumbnail->note) + "\">" +
         (r.thumbnail->drawn ? "picture" : "placeholder") + "</a>" +
         (r.thumbnail->drawn ? "" : " (" + html(r.thumbnail->note) + ")") + "</td><td><a href=\"thumbnails/" +
         page + "\">page " + where + "</a></td><td>" + html(r.message) + "</td></tr>\n";
  }
  h += "</table>\n";
  for (size_t p = 0; p < pages; ++p) {
    char page[32];
    std::snprintf(page, sizeof(page), "page-%02zu.png", p + 1);
    h += "<h2>Page " + std::to_string(p + 1) + "</h2>\n<p><img src=\"thumbnails/" + std::string(page) +
         "\" alt=\"page " + std::to_string(p + 1) + "\"></p>\n";
  }
  h += "</body></html>\n";
  const fs::path index = fs::path(out) / "index.html";
  std::ofstream f(index, std::ios::binary);
  f << h;
  if (!f) throw std::runtime_error(index.string() + ": cannot write");
  return pages;
}

}  // namespace cagekit_corpus
