// Names of the extractor's public enumerations, for messages and JSON reports.
#include "qex/extract.h"

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
        case DefectKind::FoldOverNotRepaired: return "FoldOverNotRepaired";
        case DefectKind::MapRefined: return "MapRefined";
        case DefectKind::MapCoarsened: return "MapCoarsened";
        case DefectKind::HoleClosed: return "HoleClosed";
        case DefectKind::SheetsSeparated: return "SheetsSeparated";
        case DefectKind::RefinementFailed: return "RefinementFailed";
        case DefectKind::MapCollapsesHandle: return "MapCollapsesHandle";
        case DefectKind::BestEffortMesh: return "BestEffortMesh";
        case DefectKind::RimShortOfSingularity: return "RimShortOfSingularity";
        case DefectKind::FoldPinnedBySingularities: return "FoldPinnedBySingularities";
        case DefectKind::AnglesLeaveNoRoom: return "AnglesLeaveNoRoom";
        case DefectKind::RegionAreaNotPositive: return "RegionAreaNotPositive";
        case DefectKind::HoleFilled: return "HoleFilled";
        case DefectKind::SeamRounded: return "SeamRounded";
        case DefectKind::SingularitiesMerged: return "SingularitiesMerged";
        case DefectKind::GhostFacesCancelled: return "GhostFacesCancelled";
    }
    return "Unknown";
}

} // namespace qex
