// The extraction report and the checker's verdict as JSON: the document `qex extract --report`
// writes, for programs that embed qex (the Python package's `Result.report`, the C API's
// qex_result_report_json). Never throws (std::bad_alloc aside), never prints.
#pragma once

#include "qex/extract.h"
#include "qex/quality.h"
#include "qex/verify.h"

#include <string>

namespace qex {

/// The checker's verdict as JSON: counts, the input's invariants, violations and undecided
/// checks with their kinds, elements and messages.
std::string verify_json(const VerifyResult& verdict, int indent = 2);

/// The verdict as above, and the mesh's quality figures (mesh_quality, qex/quality.h) under
/// "quality": what `qex check --json` prints.
std::string verify_json(const VerifyResult& verdict, const MeshQuality& quality, int indent = 2);

/// The report of `result` as JSON: the counts per stage, "fallback", "repair", "defects",
/// "explanations", "stage_seconds", the checker's verdict under "check", and "seconds" {"read",
/// "extract_and_check"} with the given wall times.
std::string report_json(const Result& result, double read_seconds, double extract_seconds, int indent = 2);

/// The report as above, and the mesh's quality figures under "quality", the time they took in
/// "seconds" as "quality": what `qex extract --report` writes. The C API and the Python package
/// return the report without them: measuring the distances takes time an extraction need not spend.
std::string report_json(const Result& result, double read_seconds, double extract_seconds, const MeshQuality& quality,
                        double quality_seconds, int indent = 2);

} // namespace qex
