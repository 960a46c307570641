// Names of the checker's violation kinds, for messages and JSON reports, and what each kind's
// Violation::element indexes.
#include "qex/verify.h"

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

} // namespace qex
