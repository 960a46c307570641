// The conformance room of the binding: qex.conform's cases, its judge and reproducers, and its
// table, from the library's qex::conform (qex/conform.h), so that Python's run gives the CLI's
// summary rows and folders. Cases and rows cross as JSON text.
#include "bindings.h"

#include "qex/conform.h"

#include <pybind11/stl.h>

#include <string>
#include <vector>

namespace qex_python {

namespace py = pybind11;

void bind_conform(py::module_& m) {
    m.def(
        "conform_cases",
        [](const std::vector<std::string>& sets, int count, std::uint64_t seed) {
            std::string error;
            const std::vector<qex::ConformCase> cases = qex::conform_cases(sets, count, seed, &error);
            if (!error.empty()) throw py::value_error(error);
            std::vector<std::string> out;
            for (const qex::ConformCase& c : cases) out.push_back(qex::conform_case_json(c));
            return out;
        },
        "The cases of `sets` (known, hostile, a folder or list of maps) as JSON texts (qex::conform_cases).",
        py::arg("sets"), py::arg("count"), py::arg("seed"));
    m.def(
        "conform_map_text", [](const std::string& c) { return qex::conform_map_text(qex::conform_case_from_json(c)); },
        "A generated case's map file, OBJ text (malformed on purpose for some hostile cases).", py::arg("case"));
    m.def(
        "conform_judge",
        [](const std::string& case_json, const std::string& map_path, const std::string& out_path,
           const std::string& stderr_path, int exit_code, int signal, bool timed_out, double seconds,
           const std::string& out_dir, const std::string& replay_command, const std::string& checker) {
            const qex::ConformCase c = qex::conform_case_from_json(case_json);
            qex::ConformOptions o;
            o.out_dir = out_dir, o.replay_command = replay_command, o.checker = checker;
            py::gil_scoped_release unlocked;
            qex::ConformResult r = qex::conform_judge(c, map_path, out_path, {exit_code, signal, timed_out, seconds});
            if (!r.right) r.folder = qex::write_reproducer(r, map_path, out_path, stderr_path, o);
            return qex::conform_summary_line(r);
        },
        "Judges one run (qex::conform_judge), writes its reproducer when it is not right; its summary row as JSON.",
        py::arg("case"), py::arg("map_path"), py::arg("out_path"), py::arg("stderr_path"), py::arg("exit_code"),
        py::arg("signal"), py::arg("timed_out"), py::arg("seconds"), py::arg("out_dir"), py::arg("replay_command"),
        py::arg("checker"));
    m.def("conform_table", &qex::conform_table, "The table per family of summary rows (JSON texts).",
          py::arg("rows"));
}

} // namespace qex_python
