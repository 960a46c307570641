// The oracle's one entry for judging any extractor's quad mesh against a map: `qex check`,
// `qex draw --quads`, the C API's qex_check and Python's qex.check all call check_mesh, so the
// same mesh gets the same verdict everywhere, with the same defaults (VerifyOptions: fold-over
// regions judged on the surface, positions read to 6 significant digits; grid scale 1), or on
// the certificate qex extract wrote beside the mesh.
#pragma once

#include "qex/extract.h"
#include "qex/verify.h"

namespace qex {

/// The map's validation (Error: what extraction would reject it for) and, when it passes, the
/// checker's verdict on the mesh.
struct MeshCheck {
    Error error;
    VerifyResult verdict;
    bool map_ok() const { return error.code == ErrorCode::None; }
};

/// Judges `mesh` (its positions and faces; provenance, local UVs and a map it carries are
/// judged too) against `map` as `qex check --param` does: a map extraction would reject judges
/// nothing (MeshCheck::error), otherwise verify() with `options` at `grid_scale` (a power of
/// two: the mesh was extracted from the map with its UVs multiplied by it).
inline MeshCheck check_mesh(const Input& map, QuadMesh mesh, int grid_scale = 1, const VerifyOptions& options = {}) {
    MeshCheck c;
    c.error = validate(map);
    if (!c.map_ok()) return c;
    mesh.grid_scale = grid_scale;
    c.verdict = verify(map, mesh, options);
    return c;
}

/// Judges `mesh` on qex's certificate (`qex check --param MAP --certificate CERT`): the map
/// validated as above, then the certificate checked against it and the mesh judged in located
/// mode on the certificate's map at its grid scale (verify with a Certificate, qex/verify.h). A
/// certificate that fails makes the verdict invalid with CertificateMismatch violations.
inline MeshCheck check_mesh(const Input& map, const QuadMesh& mesh, const Certificate& certificate,
                            const VerifyOptions& options = {}) {
    MeshCheck c;
    c.error = validate(map);
    if (!c.map_ok()) return c;
    c.verdict = verify(map, mesh, certificate, options);
    return c;
}

/// qex's own result `mesh` (extracted from `map`, carrying its map) judged on the certificate
/// `qex extract --certificate` would write beside it, as `qex check --param MAP --certificate`
/// will judge the two files: the mesh's positions and faces only (both files keep the doubles
/// exactly). `certificate` is make_certificate(map, mesh). A certificate written is one this
/// accepts (beside a valid mesh) or that holds against the map (VerifyResult::on_certificate).
inline MeshCheck check_own_certificate(const Input& map, const QuadMesh& mesh, const Certificate& certificate,
                                       const VerifyOptions& options = {}) {
    QuadMesh written;
    written.positions = mesh.positions;
    written.faces = mesh.faces;
    return check_mesh(map, written, certificate, options);
}

} // namespace qex
