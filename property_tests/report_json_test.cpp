// qex::report_json equals the CLI's report: `report_json_test MAP REPORT` extracts MAP with the
// library and compares with REPORT, the file `qex extract MAP --report REPORT` wrote, every field
// but the wall times; the CLI's "quality" too, measured again here (the same bits: figures of the
// geometry alone). Exit code 0: equal.
#include <qex/qex.h>
#include <qex/report.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <iostream>

namespace {

// The fields that are wall times: they differ from run to run.
void drop_times(nlohmann::json& j) {
    j.erase("seconds");
    j.erase("stage_seconds");
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: report_json_test MAP REPORT\n";
        return 2;
    }
    qex::Input in;
    if (const auto e = qex::read_obj(argv[1], in); !e.ok()) {
        std::cerr << e.message << "\n";
        return 2;
    }
    std::ifstream file(argv[2]);
    nlohmann::json cli = nlohmann::json::parse(file, nullptr, false);
    if (cli.is_discarded()) {
        std::cerr << argv[2] << ": not JSON\n";
        return 2;
    }
    const qex::Result r = qex::extract(in);
    nlohmann::json lib = nlohmann::json::parse(qex::report_json(r, 0.0, 0.0, qex::mesh_quality(in, r.mesh), 0.0));
    // The stage names and their order are the same; only the times differ.
    bool same_stages = cli["stage_seconds"].size() == lib["stage_seconds"].size();
    for (auto it = cli["stage_seconds"].begin(); same_stages && it != cli["stage_seconds"].end(); ++it)
        same_stages = lib["stage_seconds"].contains(it.key());
    drop_times(cli);
    drop_times(lib);
    if (cli != lib || !same_stages) {
        std::cerr << "the library's report differs from the CLI's:\n" << nlohmann::json::diff(cli, lib).dump(2) << "\n";
        return 1;
    }
    // The verdict alone, as `qex check --json` prints it, is the report's "check".
    if (nlohmann::json::parse(qex::verify_json(r.check)) != lib["check"]) return 1;
    std::cout << "the library's report equals the CLI's (" << cli.size() << " sections)\n";
    return 0;
}
