// python/src/tool.cpp: varsym._tool, the command line run in-process: for varsym.call (any of
// the tool's commands) and the options of `varsym run` that the models layer's simulation does
// not take (Newton's tolerance and limit, statistics, checkpoints). A module of its own, so
// that varsym._core builds without the tool's engine (pip builds _tool only when
// VARSYM_PIP_TOOL=1).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <csignal>
#include <string>
#include <tuple>
#include <vector>

#include "interruptible.hpp"
#include "models/models.hpp"
#include "options/front_end.hpp"
#include "output/signals.hpp"

namespace py = pybind11;
using namespace varsym;

PYBIND11_MODULE(_tool, m) {
    m.doc() = "varsym's command line in-process; use the package varsym, not this module";
    m.def(
        "run_cli",
        [](const std::vector<std::string>& args) {
            int status = 0;
            std::string message;
            // In-process, the host's signal handlers stay (cli::set_embedded): Ctrl-C reaches
            // the command as a first SIGINT would (cli::request_stop), which stops after its
            // current step keeping what it wrote, and exits 130.
            cli::set_embedded(true);
            cli::clear_pending_signal();
            varsym_python::run_interruptible(
                [&] { // the failure's message and quietness are per thread
                    cli::set_quiet_failures(true);
                    cli::front_end fe;
                    status = fe.parse(args);
                    if (status < 0) status = fe.run();
                    if (status != 0) message = cli::last_failure();
                },
                [] { cli::request_stop(SIGINT); });
            cli::clear_pending_signal();
            return py::make_tuple(status, message);
        },
        py::arg("args"),
        "Runs the varsym command line in-process; returns (exit code, error message).");
    m.def("models", [] {
        std::vector<std::tuple<std::string, std::string, std::string>> out;
        for (const auto& mod : cli::make_models())
            out.emplace_back(mod.name, mod.summary, mod.description);
        return out;
    });
}
