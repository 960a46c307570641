// SVG text for the pictures of `qex draw` and `qex check --svg` (draw_map.cpp, draw_mesh.cpp,
// draw.cpp): written here, no dependency. Coordinates are printed with one decimal.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace qex::cli::svg {

/// `x` with one decimal.
std::string num(double x);
/// `s` with the characters XML reserves escaped.
std::string escape(const std::string& s);
/// A polygon through the points `p`, with the attributes `style`.
std::string polygon(const std::vector<std::array<double, 2>>& p, const std::string& style);
/// The text `t` (escaped) at (x, y), with the attributes `style`.
std::string text(double x, double y, const std::string& t, const std::string& style = "");
/// A circle of radius r around (x, y), with the attributes `style`.
std::string circle(double x, double y, double r, const std::string& style);
/// The SVG document of size w by h around `body`, on white.
std::string svg_document(double w, double h, const std::string& body);

} // namespace qex::cli::svg
