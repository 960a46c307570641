// The JSON of the extractor's report and of the checker's verdict (`qex extract --report`,
// `qex check --json`), and the checker's violations in words.
#pragma once

#include "qex/qex.h"

#include <nlohmann/json.hpp>

#include <cstddef>

namespace qex::cli {

nlohmann::json to_json(const VerifyResult& v);
nlohmann::json to_json(const Defect& d);
/// The report's counts, stage by stage, its fallback rung, repair, defects, explanations and times.
nlohmann::json to_json(const Report& r);
/// The first `limit` violations and undecided checks, on stderr.
void print_violations(const VerifyResult& v, std::size_t limit = 20);

} // namespace qex::cli
