#include "farm/commands/render_batch.h"

#include <chrono>

#include "engine/util/errors.h"
#include "farm/commands/formatted.h"
#include "farm/commands/render_film.h"
#include "farm/cluster/worker.h"
#include "farm/process/interrupt.h"
#include "farm/process/usage_error.h"

namespace rf::cli {

using namespace rf::farm;
using Clock = std::chrono::steady_clock;

int renderJobOfFilms(MpiTransport& t, const ArgParser& p, const std::vector<std::string>& args, const std::vector<RenderJob>& jobs) {
    const int n = int(jobs.size());
    std::vector<std::string> failed;
    bool onlyInputErrors = true;
    int written = 0;
    for (int i = 0; i < n; ++i) {
        const RenderJob& job = jobs[size_t(i)];
        if (t.rank() == 0)
            writeStderrText(formatted("rayfarm: film %d of %d: %s -> %s\n", i + 1, n, job.scenePath.c_str(), job.output.c_str()));
        const FilmInJob film{i, n};
        int code = 0;
        try {
            code = renderFilm(t, p, args, job, Clock::now(), &film);
        } catch (const InputError& e) {
            printLine("error", e.what());
            code = 2;
        } catch (const UsageError& e) {
            printLine("error", e.what());
            code = 2;
        } catch (const std::exception& e) {
            printLine("error", e.what());
            code = 1;
        }
        if (t.rank() != 0) {
            if (code == 130) return code;  // a signal: the job ends
            // A failure this rank told rank 0 of: rank 0's word to stop that film comes next.
            if (code == 1) awaitStop(t, std::max(4.0, 2.0 * job.workerTimeout));
            continue;
        }
        if (code == 0) {
            ++written;
            continue;
        }
        if (code > 128) {  // interrupted: the films after it were not started
            writeStderrText(formatted("rayfarm: job interrupted in film %d of %d (%s); %d written before it\n", i + 1, n,
                                      job.scenePath.c_str(), written));
            return code;
        }
        failed.push_back(job.scenePath);
        onlyInputErrors = onlyInputErrors && code == 2;
    }
    if (t.rank() != 0) return 0;
    std::string summary = formatted("rayfarm: job of %d films: %d written", n, written);
    if (!failed.empty()) {
        summary += "; failed: ";
        for (size_t i = 0; i < failed.size(); ++i) {
            if (i) summary += ", ";
            summary += failed[i];
        }
    }
    writeStderrText(summary + "\n");
    return failed.empty() ? 0 : onlyInputErrors ? 2 : 1;
}

}  // namespace rf::cli
