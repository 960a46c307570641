// SVG text (svg.h).
#include "svg.h"

#include <cstdio>

namespace qex::cli::svg {

std::string num(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1f", x);
    return b;
}

std::string escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else if (c == '&')
            out += "&amp;";
        else if (c == '"')
            out += "&quot;";
        else
            out += c;
    }
    return out;
}

std::string polygon(const std::vector<std::array<double, 2>>& p, const std::string& style) {
    std::string s = "<polygon points=\"";
    for (const std::array<double, 2>& q : p) s += num(q[0]) + "," + num(q[1]) + " ";
    return s + "\" " + style + "/>\n";
}

std::string text(double x, double y, const std::string& t, const std::string& style) {
    return "<text x=\"" + num(x) + "\" y=\"" + num(y) + "\" " + style + ">" + escape(t) + "</text>\n";
}

std::string circle(double x, double y, double r, const std::string& style) {
    return "<circle cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"" + num(r) + "\" " + style + "/>\n";
}

std::string svg_document(double w, double h, const std::string& body) {
    return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(w) +
           "\" height=\"" + num(h) + "\" viewBox=\"0 0 " + num(w) + " " + num(h) +
           "\" font-family=\"sans-serif\" font-size=\"13\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n" +
           body + "</svg>\n";
}

} // namespace qex::cli::svg
