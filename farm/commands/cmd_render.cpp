// rayfarm render: the timeline to an MP4, as one process or as an MPI farm. This file is the
// command's entry; one film (render_film.cpp: the scene shared, the job decided in
// render_decision.cpp, the farm run, its outcome in render_outcome.cpp) or a job of several
// (render_batch.cpp). Scheduling, messages, sinks and the loops live in farm/cluster/.
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "farm/cli/cli.h"
#include "farm/commands/commands.h"
#include "farm/commands/launch_command.h"
#include "farm/commands/render_batch.h"
#include "farm/commands/render_film.h"
#include "farm/commands/render_options.h"
#include "farm/cluster/transport.h"
#include "farm/process/interrupt.h"

namespace rf::cli {

using namespace rf::farm;
using Clock = std::chrono::steady_clock;

int runRender(const std::vector<std::string>& args) {
    for (const std::string& a : args)
        if (a == "--help" || a == "-h") {
            std::fputs(kRenderHelp, stdout);
            return 0;
        }
    const auto wallStart = Clock::now();
    MpiTransport t;
    installInterruptHandlers();
    if (t.size() > 1 || std::getenv("OMPI_COMM_WORLD_SIZE")) {  // under mpirun, -np 1 included
        // Read mpirun's options while it runs: a resume command printed after it ended keeps them.
        if (t.rank() == 0) (void)launcherPrefix(t.size());
        followLauncher(t.rank() == 0);  // a second Ctrl-C ends mpirun before its SIGTERM: interrupt.h
    }
    ArgParser p("render");
    declareRenderOptions(p);
    std::vector<RenderJob> jobs;
    try {
        p.parse(args);
        jobs = jobsFromOptions(p);
    } catch (...) {
        if (t.rank() == 0) throw;
        return 2;  // every rank parsed the same arguments; rank 0 reports
    }
    if (jobs.size() == 1) return renderFilm(t, p, args, jobs[0], wallStart, nullptr);
    return renderJobOfFilms(t, p, args, jobs);
}

}  // namespace rf::cli
