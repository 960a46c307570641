// Names of the checker's violation kinds, for messages and JSON reports, what each kind's
// Violation::element indexes, and the verdict in one line with what it left undecided.
#include "qex/verify.h"

#include <cstdio>
#include <string>

namespace qex {

const char* to_string(ViolationKind k) {
    switch (k) {
        case ViolationKind::NotQuad: return "NotQuad";
        case ViolationKind::BadIndex: return "BadIndex";
        case ViolationKind::RepeatedVertex: return "RepeatedVertex";
        case ViolationKind::NonManifoldEdge: return "NonManifoldEdge";
        case ViolationKind::InconsistentOrientation: return "InconsistentOrientation";
        case ViolationKind::NonManifoldVertex: return "NonManifoldVertex";
        case ViolationKind::UnreferencedVertex: return "UnreferencedVertex";
        case ViolationKind::NonFinitePosition: return "NonFinitePosition";
        case ViolationKind::BoundaryMismatch: return "BoundaryMismatch";
        case ViolationKind::EulerMismatch: return "EulerMismatch";
        case ViolationKind::ComponentMismatch: return "ComponentMismatch";
        case ViolationKind::TooLarge: return "TooLarge";
        case ViolationKind::LocalUvNotUnitSquare: return "LocalUvNotUnitSquare";
        case ViolationKind::EmptyMesh: return "EmptyMesh";
        case ViolationKind::MapNotIntegerGrid: return "MapNotIntegerGrid";
        case ViolationKind::NotOnGridPoint: return "NotOnGridPoint";
        case ViolationKind::SingularityOffGrid: return "SingularityOffGrid";
        case ViolationKind::RepairNotCertified: return "RepairNotCertified";
        case ViolationKind::OffSurface: return "OffSurface";
        case ViolationKind::FaceNotGridCell: return "FaceNotGridCell";
        case ViolationKind::CoverageMismatch: return "CoverageMismatch";
        case ViolationKind::GridPointNotCovered: return "GridPointNotCovered";
        case ViolationKind::GridCellNotCovered: return "GridCellNotCovered";
        case ViolationKind::ValenceMismatch: return "ValenceMismatch";
        case ViolationKind::SingularityNotCarried: return "SingularityNotCarried";
        case ViolationKind::Hole: return "Hole";
        case ViolationKind::MissingComponent: return "MissingComponent";
        case ViolationKind::CertificateMismatch: return "CertificateMismatch";
    }
    return "Unknown";
}

const char* to_string(PlaceKind k) {
    switch (k) {
        case PlaceKind::Vertex: return "vertex";
        case PlaceKind::Edge: return "edge";
        case PlaceKind::Face: return "face";
        case PlaceKind::Loop: return "loop";
        case PlaceKind::InputVertex: return "input_vertex";
        case PlaceKind::InputTriangle: return "input_triangle";
        case PlaceKind::GridCell: return "grid_cell";
        case PlaceKind::GridPoint: return "grid_point";
    }
    return "unknown";
}

ViolationElement element_kind(ViolationKind k) {
    switch (k) {
        case ViolationKind::NotQuad:
        case ViolationKind::BadIndex:
        case ViolationKind::RepeatedVertex:
        case ViolationKind::NonManifoldEdge:
        case ViolationKind::InconsistentOrientation:
        case ViolationKind::LocalUvNotUnitSquare:
        case ViolationKind::FaceNotGridCell: return ViolationElement::OutputFace;
        case ViolationKind::NonManifoldVertex:
        case ViolationKind::UnreferencedVertex:
        case ViolationKind::NonFinitePosition:
        case ViolationKind::NotOnGridPoint:
        case ViolationKind::ValenceMismatch:
        case ViolationKind::Hole:
        case ViolationKind::OffSurface: return ViolationElement::OutputVertex;
        case ViolationKind::SingularityOffGrid:
        case ViolationKind::SingularityNotCarried: return ViolationElement::InputVertex;
        case ViolationKind::MissingComponent:
        case ViolationKind::CertificateMismatch:
        case ViolationKind::MapNotIntegerGrid:
        case ViolationKind::RepairNotCertified:
        case ViolationKind::GridPointNotCovered:
        case ViolationKind::GridCellNotCovered: return ViolationElement::InputTriangle;
        case ViolationKind::BoundaryMismatch:
        case ViolationKind::EulerMismatch:
        case ViolationKind::ComponentMismatch:
        case ViolationKind::EmptyMesh:
        case ViolationKind::CoverageMismatch:
        case ViolationKind::TooLarge: return ViolationElement::None;
    }
    return ViolationElement::None;
}

UndecidedShare undecided_share(const VerifyResult& v) {
    UndecidedShare u;
    u.checks = static_cast<std::int64_t>(v.undecided.size());
    if (u.checks == 0) return u;
    u.regions = static_cast<std::int64_t>(v.fold_regions.size());
    for (const FoldRegion& g : v.fold_regions) u.triangles += g.triangles;
    if (v.input_triangles > 0) u.share = static_cast<double>(u.triangles) / static_cast<double>(v.input_triangles);
    return u;
}

std::string verdict_line(const VerifyResult& v) {
    std::string line = v.valid ? "VALID" : "INVALID";
    if (!v.valid) {
        const std::size_t n = v.violations.size();
        line += " (" + std::to_string(n) + (n == 1 ? " violation)" : " violations)");
    }
    const UndecidedShare u = undecided_share(v);
    if (u.checks == 0) return line;
    line += ", " + std::to_string(u.checks) + (u.checks == 1 ? " check" : " checks") + " undecided";
    if (u.regions == 0) return line;
    char share[32];
    std::snprintf(share, sizeof share, "%.1f%%", 100.0 * u.share);
    line += " in " + std::to_string(u.regions) + (u.regions == 1 ? " fold-over region (" : " fold-over regions (") +
            std::to_string(u.triangles) + " triangles, " + share + " of the map)";
    return line;
}

} // namespace qex
