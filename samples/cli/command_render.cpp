// SPDX-License-Identifier: GPL-3.0-or-later
// cagekit render: a PNG of meshes, cages (their limit surfaces, optionally with the control
// edges and creases) and deformed scans side by side, one column per item in the order given,
// one row per view (one item: a near-square grid of views); with --error SCAN every cage's limit
// surface is coloured by its two-sided distance to SCAN, with a legend. Drawn headless by the
// SDK's render module (cagekit::RenderScene): no display needed.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_context.h"

namespace cli {

namespace {

const TextOption kViews{"--views", "iso", "LIST", "views, comma-separated: front, side, top, iso (one row each)"};
const TextOption kSize{"--size", "", "WxH",
                       "image size in pixels, each 1..16384 (default: 400 x 400 per tile)"};
const TextOption kError{"--error", "", "SCAN",
                        "colour each cage's limit surface by its two-sided distance to SCAN, with a legend"};
const TextOption kColormap{"--colormap", "viridis", "MAP", "colour map of --error: viridis or diverging"};
const IntegerOption kLevel{"--level", 0, 0, 6, "L",
                           "refinement levels of the cages' limit surfaces (0: automatic, up to 4)"};
const FlagOption kWire{"--wire", "draw the cages' control edges (without --cage: the meshes' edges)"};
const FlagOption kCreases{"--creases", "draw the cages' crease edges (in magenta-red)"};

struct ItemSpec {
  enum Kind { mesh, cage, deformed } kind;
  std::string path;
};

std::string base_name(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::vector<cagekit_render_view> parse_views(const std::string& text) {
  std::vector<cagekit_render_view> views;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    const std::string name = text.substr(start, comma - start);
    if (name == "front") views.push_back(CAGEKIT_RENDER_VIEW_FRONT);
    else if (name == "side") views.push_back(CAGEKIT_RENDER_VIEW_SIDE);
    else if (name == "top") views.push_back(CAGEKIT_RENDER_VIEW_TOP);
    else if (name == "iso") views.push_back(CAGEKIT_RENDER_VIEW_ISO);
    else throw Failure(kExitUsage, "--views: unknown view '" + name + "' (front, side, top, iso)");
    start = comma + 1;
  }
  if (views.size() > 64) throw Failure(kExitUsage, "--views: at most 64 views");
  return views;
}

// "WxH" with each side in 1..16384.
void parse_size(const std::string& text, uint32_t* width, uint32_t* height) {
  const size_t x = text.find_first_of("xX");
  auto side = [&](const std::string& part) {
    size_t used = 0;
    long value = 0;
    try {
      value = std::stol(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (part.empty() || used != part.size() || value < 1 || value > 16384)
      throw Failure(kExitUsage, "--size must be WxH with each side in 1..16384, not '" + text + "'");
    return uint32_t(value);
  };
  if (x == std::string::npos) side("");
  *width = side(text.substr(0, x));
  *height = side(text.substr(x + 1));
}

int command_render(const Options& args, const CLI::Option* mesh_option, const CLI::Option* cage_option,
                   const CLI::Option* deformed_option, const CLI::Option* title_option) {
  const bool quiet = args.quiet();
  const std::string out = args.positional("OUT");
  const std::vector<cagekit_render_view> views = parse_views(args.text(kViews));
  const std::string error_scan = args.text(kError);
  const std::string colormap = args.text(kColormap);
  const int level = args.integer(kLevel);
  if (colormap != "viridis" && colormap != "diverging")
    throw Failure(kExitUsage, "--colormap must be viridis or diverging, not '" + colormap + "'");
  if (args.given("--colormap") && error_scan.empty()) throw Failure(kExitUsage, "--colormap applies to --error");
  if (out.size() < 4 || out.compare(out.size() - 4, 4, ".png") != 0)
    throw Failure(kExitUsage, "the output must be a .png file, not '" + out + "'");

  // The items in the order given on the command line, across --mesh, --cage and --deformed.
  std::vector<ItemSpec> items;
  size_t next[3] = {0, 0, 0};
  const CLI::Option* kinds[3] = {mesh_option, cage_option, deformed_option};
  for (const CLI::Option* option : args.app()->parse_order())
    for (int k = 0; k < 3; ++k)
      if (option == kinds[k]) items.push_back({ItemSpec::Kind(k), kinds[k]->results().at(next[k]++)});
  if (items.empty()) throw Failure(kExitUsage, "render needs at least one --mesh, --cage or --deformed FILE");
  const size_t cages = size_t(std::count_if(items.begin(), items.end(), [](const ItemSpec& i) {
    return i.kind == ItemSpec::cage;
  }));
  if (!error_scan.empty() && cages == 0) throw Failure(kExitUsage, "--error colours the cages' limit surfaces: give --cage");
  if (args.given("--level") && cages == 0) throw Failure(kExitUsage, "--level applies to --cage");
  if (args.flag(kCreases) && cages == 0) throw Failure(kExitUsage, "--creases applies to --cage");
  const std::vector<std::string> titles = title_option->results();
  if (titles.size() > items.size())
    throw Failure(kExitUsage, std::to_string(titles.size()) + " --title for " + std::to_string(items.size()) + " items");

  uint32_t width = 0, height = 0;
  if (args.given("--size")) {
    parse_size(args.text(kSize), &width, &height);
  } else {
    // 400 x 400 per tile: items in columns and views in rows, one item: the views' grid.
    uint32_t columns = uint32_t(items.size()), rows = uint32_t(views.size());
    if (items.size() == 1 && views.size() > 1) {
      columns = uint32_t(std::ceil(std::sqrt(double(views.size())) - 1e-9));
      rows = uint32_t((views.size() + columns - 1) / columns);
    }
    width = std::min<uint32_t>(16384, 400 * columns);
    height = std::min<uint32_t>(16384, 400 * rows);
  }

  Session session(quiet);
  const cagekit::Context& context = session.context();
  const auto start = std::chrono::steady_clock::now();
  cagekit::Mesh scan;
  if (!error_scan.empty()) scan = session.run(error_scan, [&] { return context.read_mesh(error_scan); });
  std::vector<cagekit::Mesh> meshes(items.size());
  std::vector<cagekit::Cage> cage_handles(items.size());
  for (size_t i = 0; i < items.size(); ++i) {
    const std::string& path = items[i].path;
    if (items[i].kind == ItemSpec::cage)
      cage_handles[i] = session.run(path, [&] { return context.read_cage(path); });
    else
      meshes[i] = session.run(path, [&] { return context.read_mesh(path); });
  }
  const double read_seconds = seconds_since(start);

  const auto render_start = std::chrono::steady_clock::now();
  cagekit::RenderScene scene = session.run("render", [&] { return context.create_render_scene(); });
  cagekit_render_options options = cagekit::defaults<cagekit_render_options>();
  options.width = width;
  options.height = height;
  session.run("render", [&] {
    scene.set_options(options);
    std::vector<cagekit_render_camera> cameras;
    for (cagekit_render_view v : views) {
      cagekit_render_camera camera = cagekit::defaults<cagekit_render_camera>();
      camera.view = v;
      cameras.push_back(camera);
    }
    scene.set_views(cagekit::View<const cagekit_render_camera>(cameras.data(), cameras.size()));
  });
  std::vector<std::string> error_lines;
  for (size_t i = 0; i < items.size(); ++i) {
    cagekit_render_item_options item = cagekit::defaults<cagekit_render_item_options>();
    const std::string title = i < titles.size() ? titles[i] : base_name(items[i].path);
    item.title = title.c_str();
    // A dense scan's edges hide its surface: with cages in the picture the wire is theirs.
    item.wireframe = args.flag(kWire) && (items[i].kind == ItemSpec::cage || cages == 0) ? 1 : 0;
    const std::string& path = items[i].path;
    if (items[i].kind == ItemSpec::cage) {
      item.creases = args.flag(kCreases) ? 1 : 0;
      item.tessellation_level = uint32_t(level);
      const uint32_t index = session.run(path, [&] { return scene.add_cage(cage_handles[i], item); });
      if (scan) {
        cagekit_render_scalar_options scalar = cagekit::defaults<cagekit_render_scalar_options>();
        scalar.colormap = colormap == "diverging" ? CAGEKIT_RENDER_COLORMAP_BLUE_WHITE_RED : CAGEKIT_RENDER_COLORMAP_VIRIDIS;
        session.run(path, [&] { scene.set_distance_to_scan(index, scan, scalar); });
        const cagekit_render_item_info info = session.run(path, [&] { return scene.item_info(index); });
        char line[512];
        std::snprintf(line, sizeof(line), "cagekit: %s: two-sided distance to %s: max %.4g (level %u limit surface)",
                      path.c_str(), error_scan.c_str(), info.scalar_max, info.tessellation_level);
        error_lines.push_back(line);
      }
    } else {
      const cagekit_render_item_kind kind =
          items[i].kind == ItemSpec::deformed ? CAGEKIT_RENDER_ITEM_DEFORMED_SCAN : CAGEKIT_RENDER_ITEM_MESH;
      session.run(path, [&] { scene.add_mesh(meshes[i], kind, item); });
    }
  }
  // No EGL display or context here: the SDK's message (UNSUPPORTED_FEATURE), exit 2.
  session.run(out, [&] { scene.write_png(out); });
  const double render_seconds = seconds_since(render_start);
  session.finish_progress();
  if (!quiet) {
    for (const std::string& line : error_lines) std::fprintf(stderr, "%s\n", line.c_str());
    std::fprintf(stderr, "cagekit: wrote %s (%u x %u, %zu item%s, %zu view%s; read %.2f s, render %.2f s)\n",
                 out.c_str(), width, height, items.size(), items.size() == 1 ? "" : "s", views.size(),
                 views.size() == 1 ? "" : "s", read_seconds, render_seconds);
  }
  return kExitOk;
}

}  // namespace

Command add_render(CLI::App& cagekit) {
  CLI::App* app = cagekit.add_subcommand(
      "render", "draw meshes, cages (limit surfaces) and error maps side by side into a PNG (headless)");
  auto options = std::make_shared<Options>(app);
  options->add_positional("OUT", "output image (.png)");
  // Repeatable, one file per occurrence; the items keep the command line's order (parse_order).
  auto files = std::make_shared<std::vector<std::vector<std::string>>>(4);
  auto repeatable = [&](const char* name, std::vector<std::string>& into, const char* value_name, const char* help) {
    return app->add_option(name, into, help)->type_name(value_name)->allow_extra_args(false)->take_all();
  };
  CLI::Option* mesh = repeatable("--mesh", (*files)[0], "FILE", "a mesh (a scan), drawn shaded; repeatable");
  CLI::Option* cage = repeatable("--cage", (*files)[1], "FILE", "a cage, drawn as its limit surface; repeatable");
  CLI::Option* deformed =
      repeatable("--deformed", (*files)[2], "FILE", "a deformed scan, drawn in its own colour; repeatable");
  options->add(kError);
  options->add(kViews);
  options->add(kSize);
  options->add(kWire);
  options->add(kCreases);
  options->add(kLevel);
  options->add(kColormap);
  CLI::Option* title = repeatable("--title", (*files)[3], "TEXT", "the items' titles, in order (default: file names)");
  options->add_quiet();
  return {app, [options, files, mesh, cage, deformed, title] {
            return command_render(*options, mesh, cage, deformed, title);
          }};
}

}  // namespace cli
