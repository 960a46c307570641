// The report and the verdict as JSON, field for field what the CLI writes (`qex extract --report`,
// `qex check --json`); property_tests/report_json_test.cpp compares the two.
#include "qex/report.h"

#include <nlohmann/json.hpp>

namespace qex {
namespace {

/// Each violation: its kind, the element it names and that element's kind, its places.
nlohmann::json violations_json(const std::vector<Violation>& list) {
    static const char* const element_names[] = {"none", "face", "vertex", "input_vertex", "input_triangle"};
    nlohmann::json j = nlohmann::json::array();
    for (const auto& x : list) {
        nlohmann::json places = nlohmann::json::array();
        for (const auto& p : x.places) places.push_back({{"kind", to_string(p.kind)}, {"indices", p.indices}});
        j.push_back({{"kind", to_string(x.kind)},
                     {"element", x.element},
                     {"element_kind", element_names[static_cast<int>(element_kind(x.kind))]},
                     {"places", places},
                     {"message", x.message}});
    }
    return j;
}

nlohmann::json verify_object(const VerifyResult& v) {
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
                        {"coverage_difference", v.coverage_difference},
                        {"coverage",
                         {{"required_cells", v.coverage_cells},
                          {"uncovered_grid_points", v.uncovered_grid_points},
                          {"uncovered_cells", v.uncovered_cells},
                          {"skipped_triangles", v.coverage_skipped_triangles}}},
                        {"precision",
                         {{"position_digits", v.position_digits},
                          {"positions_float32", v.positions_float32},
                          {"surface_tolerance", v.surface_tolerance},
                          {"max_rounding_tolerance", v.max_rounding_tolerance}}}};
    if (v.located) {
        nlohmann::json regions = nlohmann::json::array();
        for (const auto& g : v.fold_regions)
            regions.push_back({{"triangles", g.triangles},
                               {"fold_triangles", g.fold_triangles},
                               {"first_triangle", g.first_triangle},
                               {"uv_area", g.uv_area},
                               {"fold_uv_area", g.fold_uv_area},
                               {"vertices", g.vertices},
                               {"off_grid_vertices", g.off_grid_vertices}});
        j["located"]["fold_regions"] = regions;
        j["located"]["fold_region_rings"] = kFoldRegionRings;
        j["located"]["surface_only_vertices"] = v.surface_only_vertices;
        j["located"]["surface_only_faces"] = v.surface_only_faces;
        j["located"]["off_grid_region_vertices"] = v.off_grid_region_vertices;
        j["located"]["max_region_grid_distance"] = v.max_region_grid_distance;
        j["located"]["singularities"] = {{"map_cones", v.map_cones},
                                         {"unread_cones", v.unread_cones},
                                         {"irregular_vertices", v.irregular_vertices},
                                         {"valences_judged", v.valences_judged},
                                         {"undecided_footprints", v.undecided_footprints},
                                         {"undecided_triangles", v.undecided_triangles},
                                         {"undecided_uv_area", v.undecided_uv_area}};
    }
    // Judged on a certificate that passed its check (qex check --certificate): the located
    // figures above are the certificate map's.
    if (v.on_certificate) j["certificate"] = {{"judged_on", true}, {"repaired_triangles", v.certificate_triangles}};
    j["input"] = {{"euler", v.input_euler},
                  {"boundary_loops", v.input_boundary_loops},
                  {"components", v.input_components},
                  {"signed_uv_area", v.input_signed_uv_area}};
    const UndecidedShare u = undecided_share(v);
    j["verdict_line"] = verdict_line(v);
    j["undecided_share"] = {
        {"checks", u.checks}, {"regions", u.regions}, {"triangles", u.triangles}, {"share", u.share}};
    j["undecided"] = violations_json(v.undecided);
    j["violations"] = violations_json(v.violations);
    return j;
}

nlohmann::json defect_json(const Defect& d) {
    nlohmann::json j = {{"kind", to_string(d.kind)},
                        {"input_element", d.input_element},
                        {"output_face", d.output_face},
                        {"grid", {d.grid[0], d.grid[1]}},
                        {"message", d.message}};
    if (d.violation) j["violation"] = to_string(*d.violation);
    return j;
}

nlohmann::json report_object(const Report& r) {
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
                  {"near_ghosts_cancelled", r.near_ghost_faces_cancelled},
                  {"non_quad", r.non_quad_faces}};
    j["fallback"] = {{"rung", r.rung},
                     {"rungs_tried", r.rungs_tried},
                     {"unplaced_vertices", r.unplaced_vertices},
                     {"grid_scale", r.grid_scale},
                     {"refinements_tried", r.refinements_tried},
                     {"coarsening", r.coarsening}};
    j["repair"] = {{"repaired_regions", r.repaired_regions},
                   {"repaired_triangles", r.repaired_triangles},
                   {"unrepaired_regions", r.unrepaired_regions},
                   {"flipped_after_repair", r.flipped_after_repair},
                   {"losses_proved", r.losses_proved},
                   {"losses_not_proved", r.losses_not_proved}};
    j["defects"] = nlohmann::json::array();
    for (const auto& d : r.defects) j["defects"].push_back(defect_json(d));
    j["explanations"] = nlohmann::json::array();
    for (const auto& d : r.explanations)
        j["explanations"].push_back({{"kind", to_string(d.kind)},
                                     {"input_element", d.input_element},
                                     {"grid", {d.grid[0], d.grid[1]}},
                                     {"message", d.message}});
    j["collapsed_handles"] = nlohmann::json::array();
    for (const auto& h : r.collapsed_handles)
        j["collapsed_handles"].push_back({{"vertex", h.vertex},
                                          {"triangles", h.triangles},
                                          {"signed_uv_area", h.signed_uv_area},
                                          {"absolute_uv_area", h.absolute_uv_area},
                                          {"genus", h.genus},
                                          {"rims", h.rims}});
    j["stage_seconds"] = nlohmann::json::object();
    for (const auto& [name, s] : r.stage_seconds) j["stage_seconds"][name] = s;
    return j;
}

/// The quality figures (qex/quality.h); the distances are fractions of "diagonal".
nlohmann::json quality_object(const MeshQuality& q) {
    return {{"computed", q.computed},
            {"quads", q.quads},
            {"other_faces", q.other_faces},
            {"scaled_jacobian",
             {{"min", q.min_scaled_jacobian}, {"p5", q.p5_scaled_jacobian}, {"mean", q.mean_scaled_jacobian}}},
            {"vertices", q.vertices},
            {"irregular_vertices", q.irregular_vertices},
            {"irregular_vertex_share", q.irregular_vertex_share},
            {"diagonal", q.diagonal},
            {"distance", {{"input_to_mesh", q.distance_input_to_mesh}, {"mesh_to_input", q.distance_mesh_to_input}}}};
}

/// The report, the verdict under "check", and the wall times under "seconds".
nlohmann::json report_document(const Result& result, double read_seconds, double extract_seconds) {
    nlohmann::json j = report_object(result.report);
    j["check"] = verify_object(result.check);
    j["seconds"] = {{"read", read_seconds}, {"extract_and_check", extract_seconds}};
    return j;
}

// Messages name elements of the user's files; invalid UTF-8 in them is replaced, never thrown on.
std::string dump(const nlohmann::json& j, int indent) {
    return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

} // namespace

std::string verify_json(const VerifyResult& verdict, int indent) { return dump(verify_object(verdict), indent); }

std::string verify_json(const VerifyResult& verdict, const MeshQuality& quality, int indent) {
    nlohmann::json j = verify_object(verdict);
    j["quality"] = quality_object(quality);
    return dump(j, indent);
}

std::string report_json(const Result& result, double read_seconds, double extract_seconds, int indent) {
    return dump(report_document(result, read_seconds, extract_seconds), indent);
}

std::string report_json(const Result& result, double read_seconds, double extract_seconds, const MeshQuality& quality,
                        double quality_seconds, int indent) {
    nlohmann::json j = report_document(result, read_seconds, extract_seconds);
    j["quality"] = quality_object(quality);
    j["seconds"]["quality"] = quality_seconds;
    return dump(j, indent);
}

} // namespace qex
