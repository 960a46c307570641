// The layout as JSON (qex::layout_json), as `qex layout` writes it.
#include "qex/layout.h"

#include <nlohmann/json.hpp>

namespace qex {

std::string layout_json(const Layout& layout, int indent) {
    nlohmann::ordered_json j;
    j["valid"] = layout.valid;
    j["error"] = layout.error;
    j["notes"] = layout.notes;
    j["special_vertices"] = layout.special_vertices;
    nlohmann::ordered_json seps = nlohmann::ordered_json::array();
    for (const Separatrix& s : layout.separatrices)
        seps.push_back({{"start", to_string(s.start)}, {"end", to_string(s.end)}, {"vertices", s.vertices}});
    j["separatrices"] = seps;
    nlohmann::ordered_json patches = nlohmann::ordered_json::array();
    for (const Patch& p : layout.patches)
        patches.push_back({{"kind", to_string(p.kind)},
                           {"u", p.u},
                           {"v", p.v},
                           {"corners", p.corners},
                           {"face_count", p.faces.size()},
                           {"faces", p.faces}});
    j["patches"] = patches;
    j["face_patch"] = layout.face_patch;
    nlohmann::ordered_json adjacency = nlohmann::ordered_json::array();
    for (const PatchAdjacency& a : layout.adjacency)
        adjacency.push_back({{"a", a.a}, {"b", a.b}, {"shared_edges", a.shared_edges}});
    j["adjacency"] = adjacency;
    return j.dump(indent);
}

} // namespace qex
