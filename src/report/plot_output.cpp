// SVG/PNG output of Cairo drawings, with SVG ids made independent of the process's history.
#include "report/plot_output.hpp"

#include <cairo-svg.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace softmc::report {

namespace {

enum class Format { Svg, Png };

Format format_of(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == "svg") return Format::Svg;
  if (ext == "png") return Format::Png;
  throw std::runtime_error(fmt::format("plot {}: unknown format (use .svg or .png)", path));
}

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
};
struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

void check(cairo_status_t st, const std::string& path) {
  if (st != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(fmt::format("cannot write plot {}: {}", path, cairo_status_to_string(st)));
}

cairo_status_t append_to_string(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

// Cairo names SVG groups after a process-wide surface counter ("surface524"), so the same plot
// would differ with what the process drew before; renumber them in order of appearance.
std::string renumber_svg_surfaces(const std::string& svg) {
  static constexpr std::string_view kWord = "surface";
  std::string out;
  out.reserve(svg.size());
  std::vector<std::string_view> seen;
  std::size_t copied = 0;
  for (std::size_t at = svg.find(kWord); at != std::string::npos; at = svg.find(kWord, at + kWord.size())) {
    std::size_t end = at + kWord.size();
    while (end < svg.size() && std::isdigit(static_cast<unsigned char>(svg[end]))) ++end;
    // Only ids and references: id="surface7", href="#surface7".
    const bool is_id = at > 0 && (svg[at - 1] == '"' || svg[at - 1] == '#') && end > at + kWord.size();
    if (!is_id) continue;
    const std::string_view id(svg.data() + at, end - at);
    auto it = std::find(seen.begin(), seen.end(), id);
    if (it == seen.end()) it = seen.insert(seen.end(), id);
    out.append(svg, copied, at - copied);
    fmt::format_to(std::back_inserter(out), "surface{}", 1 + (it - seen.begin()));
    copied = end;
  }
  out.append(svg, copied);
  return out;
}

}  // namespace

void render_to_file(const std::string& path, double width_px, double height_px,
                    const std::function<void(cairo_t*)>& draw) {
  const Format kind = format_of(path);
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) throw std::runtime_error(fmt::format("cannot open plot {}: {}", path, std::strerror(errno)));

  std::string bytes;
  std::unique_ptr<cairo_surface_t, SurfaceDeleter> surface(
      kind == Format::Svg
          ? cairo_svg_surface_create_for_stream(append_to_string, &bytes, width_px, height_px)
          : cairo_image_surface_create(CAIRO_FORMAT_ARGB32, static_cast<int>(width_px), static_cast<int>(height_px)));
  check(cairo_surface_status(surface.get()), path);
  {
    std::unique_ptr<cairo_t, ContextDeleter> cr(cairo_create(surface.get()));
    draw(cr.get());
    check(cairo_status(cr.get()), path);
  }
  if (kind == Format::Png) check(cairo_surface_write_to_png_stream(surface.get(), append_to_string, &bytes), path);
  cairo_surface_finish(surface.get());
  check(cairo_surface_status(surface.get()), path);
  if (kind == Format::Svg) bytes = renumber_svg_surfaces(bytes);

  if (std::fwrite(bytes.data(), 1, bytes.size(), file.get()) != bytes.size() || std::fclose(file.release()) != 0)
    throw std::runtime_error(fmt::format("cannot write plot {}: {}", path, std::strerror(errno)));
}

}  // namespace softmc::report
