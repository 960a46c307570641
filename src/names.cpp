// Names of the public enumerations, for messages and JSON reports.
#include "qex/qex.h"

namespace qex {

const char* to_string(ErrorCode c) {
    switch (c) {
        case ErrorCode::None: return "None";
        case ErrorCode::EmptyMesh: return "EmptyMesh";
        case ErrorCode::IndexOutOfRange: return "IndexOutOfRange";
        case ErrorCode::UvCountMismatch: return "UvCountMismatch";
        case ErrorCode::NonFiniteValue: return "NonFiniteValue";
        case ErrorCode::CoordinateTooLarge: return "CoordinateTooLarge";
        case ErrorCode::DegenerateTriangle: return "DegenerateTriangle";
        case ErrorCode::NonManifoldEdge: return "NonManifoldEdge";
        case ErrorCode::InconsistentOrientation: return "InconsistentOrientation";
        case ErrorCode::NonManifoldVertex: return "NonManifoldVertex";
        case ErrorCode::IsolatedVertex: return "IsolatedVertex";
        case ErrorCode::ValenceCountMismatch: return "ValenceCountMismatch";
        case ErrorCode::BadFeatureEdge: return "BadFeatureEdge";
        case ErrorCode::InconsistentMap: return "InconsistentMap";
        case ErrorCode::MapTooLarge: return "MapTooLarge";
        case ErrorCode::CollapseFailed: return "CollapseFailed";
    }
    return "Unknown";
}

const char* to_string(DefectKind k) {
    switch (k) {
        case DefectKind::NonQuadFace: return "NonQuadFace";
        case DefectKind::TraceFailed: return "TraceFailed";
        case DefectKind::UnmatchedPort: return "UnmatchedPort";
        case DefectKind::PortConflict: return "PortConflict";
        case DefectKind::OpenFaceWalk: return "OpenFaceWalk";
        case DefectKind::PortlessQVertex: return "PortlessQVertex";
        case DefectKind::CheckerViolation: return "CheckerViolation";
        case DefectKind::FaceCollapsed: return "FaceCollapsed";
        case DefectKind::BoundaryFaceDiscarded: return "BoundaryFaceDiscarded";
        case DefectKind::GhostFacesCancelled: return "GhostFacesCancelled";
    }
    return "Unknown";
}

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
