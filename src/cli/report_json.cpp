// The JSON of reports and verdicts (report_json.h).
#include "report_json.h"

#include <iostream>

namespace qex::cli {

nlohmann::json to_json(const qex::VerifyResult& v) {
    nlohmann::json j;
    j["valid"] = v.valid;
    j["faces"] = v.faces;
    j["vertices"] = v.vertices;
    j["edges"] = v.edges;
    j["euler"] = v.euler;
    j["boundary_loops"] = v.boundary_loops;
    j["components"] = v.components;
    j["map_displacement"] = {{"max", v.max_map_displacement}, {"sum", v.sum_map_displacement}};
    j["map_singularities"] = v.map_singularities;
    if (v.located)
        j["located"] = {{"max_grid_distance", v.max_grid_distance},
                        {"max_surface_distance", v.max_surface_distance},
                        {"map_flipped_triangles", v.map_flipped_triangles},
                        {"coverage_difference", v.coverage_difference}};
    j["input"] = {{"euler", v.input_euler},
                  {"boundary_loops", v.input_boundary_loops},
                  {"components", v.input_components},
                  {"signed_uv_area", v.input_signed_uv_area}};
    j["undecided"] = nlohmann::json::array();
    for (const auto& x : v.undecided)
        j["undecided"].push_back({{"kind", qex::to_string(x.kind)}, {"element", x.element}, {"message", x.message}});
    j["violations"] = nlohmann::json::array();
    for (const auto& x : v.violations)
        j["violations"].push_back({{"kind", qex::to_string(x.kind)}, {"element", x.element}, {"message", x.message}});
    return j;
}

nlohmann::json to_json(const qex::Defect& d) {
    nlohmann::json j = {{"kind", qex::to_string(d.kind)},
                        {"input_element", d.input_element},
                        {"output_face", d.output_face},
                        {"grid", {d.grid[0], d.grid[1]}},
                        {"message", d.message}};
    if (d.violation) j["violation"] = qex::to_string(*d.violation);
    return j;
}

namespace {

/// The report's counts, stage by stage.
nlohmann::json counts_json(const qex::Report& r) {
    nlohmann::json j;
    j["input"] = {{"vertices", r.input_vertices},
                  {"triangles", r.input_triangles},
                  {"flipped_triangles", r.flipped_triangles},
                  {"degenerate_triangles", r.degenerate_triangles},
                  {"collapsed_edges", r.collapsed_edges},
                  {"singularities", r.singularities},
                  {"signed_uv_area", r.signed_uv_area}};
    j["sanitization"] = {{"max_displacement", r.max_sanitization_displacement},
                         {"sum_displacement", r.sum_sanitization_displacement}};
    j["qvertices"] = {{"on_vertices", r.qvertices_on_vertices},
                      {"on_edges", r.qvertices_on_edges},
                      {"in_faces", r.qvertices_in_faces}};
    j["ports"] = r.ports;
    j["traces"] = {{"started", r.traces},
                   {"connected", r.traces_connected},
                   {"into_boundary", r.traces_into_boundary},
                   {"failed", r.traces_failed},
                   {"orientation_flips_crossed", r.orientation_flips_crossed}};
    j["faces"] = {{"traced", r.faces_traced},
                  {"boundary_discarded", r.boundary_faces_discarded},
                  {"open_walks", r.open_face_walks},
                  {"recovered_edges", r.recovered_edges},
                  {"merged_qvertices", r.merged_qvertices},
                  {"collapsed", r.collapsed_faces},
                  {"ghosts_cancelled", r.ghost_faces_cancelled},
                  {"non_quad", r.non_quad_faces}};
    return j;
}

} // namespace

nlohmann::json to_json(const qex::Report& r) {
    nlohmann::json j = counts_json(r);
    j["fallback"] = {{"rung", r.rung}, {"rungs_tried", r.rungs_tried}, {"unplaced_vertices", r.unplaced_vertices}};
    j["repair"] = {{"repaired_regions", r.repaired_regions},
                   {"repaired_triangles", r.repaired_triangles},
                   {"unrepaired_regions", r.unrepaired_regions},
                   {"flipped_after_repair", r.flipped_after_repair}};
    j["defects"] = nlohmann::json::array();
    for (const auto& d : r.defects) j["defects"].push_back(to_json(d));
    j["explanations"] = nlohmann::json::array();
    for (const auto& d : r.explanations)
        j["explanations"].push_back({{"kind", qex::to_string(d.kind)},
                                     {"input_element", d.input_element},
                                     {"grid", {d.grid[0], d.grid[1]}},
                                     {"message", d.message}});
    j["stage_seconds"] = nlohmann::json::object();
    for (const auto& [name, s] : r.stage_seconds) j["stage_seconds"][name] = s;
    return j;
}

void print_violations(const qex::VerifyResult& v, std::size_t limit) {
    for (std::size_t i = 0; i < v.violations.size() && i < limit; ++i)
        std::cerr << "  " << qex::to_string(v.violations[i].kind) << ": " << v.violations[i].message << "\n";
    if (v.violations.size() > limit) std::cerr << "  ... and " << v.violations.size() - limit << " more\n";
    for (std::size_t i = 0; i < v.undecided.size() && i < limit; ++i)
        std::cerr << "  undecided: " << qex::to_string(v.undecided[i].kind) << ": " << v.undecided[i].message << "\n";
    if (v.undecided.size() > limit) std::cerr << "  ... and " << v.undecided.size() - limit << " more undecided\n";
}

} // namespace qex::cli
