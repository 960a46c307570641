// Names of the checker's violation kinds, for messages and JSON reports.
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
        case ViolationKind::OffSurface: return "OffSurface";
        case ViolationKind::FaceNotGridCell: return "FaceNotGridCell";
        case ViolationKind::CoverageMismatch: return "CoverageMismatch";
    }
    return "Unknown";
}

} // namespace qex
