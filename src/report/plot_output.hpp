// A Cairo drawing rendered into an SVG or PNG file chosen by the file's extension, deterministically.
#pragma once

#include <cairo.h>

#include <functional>
#include <string>

namespace softmc::report {

// Opens `path` first (a bad path fails before any drawing), calls `draw` on a width × height px
// surface and writes the file. Throws std::runtime_error for an extension other than .svg/.png
// (either case) and for any file or Cairo error.
void render_to_file(const std::string& path, double width_px, double height_px,
                    const std::function<void(cairo_t*)>& draw);

}  // namespace softmc::report
