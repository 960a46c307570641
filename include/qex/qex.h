// qex — robust quad mesh extraction from relaxed integer-grid maps (QEx, Ebke et al. 2013).
//
// One entry point, plain structs:
//   qex::Input in = ...;                       // positions, triangles, per-corner UVs
//   qex::Result r = qex::extract(in);          // never throws, never aborts, never prints
//   if (!r.ok()) { r.error.message ... }       // bad input: what and where
//   r.mesh  (quads, local UVs, provenance)     // r.report: counts, defects, timings
//   qex::VerifyResult v = qex::verify(in, r.mesh);   // independent exact checker
//
// The headers by concern: qex/mesh.h (the data), qex/extract.h (the extractor), qex/verify.h
// (the checker, library qex::verify), qex/check.h (the oracle's entry for any extractor's mesh),
// qex/quality.h (the mesh's quality figures, measured by qex::verify), qex/io.h (files),
// qex/openmesh.h (OpenMesh adapter).
#pragma once

#include "qex/check.h"
#include "qex/extract.h"
#include "qex/io.h"
#include "qex/mesh.h"
#include "qex/quality.h"
#include "qex/verify.h"
