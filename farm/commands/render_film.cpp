#include "farm/commands/render_film.h"

#include <algorithm>
#include <cstdlib>
#include <sched.h>

#include "engine/integrators/bounce_cache.h"
#include "engine/util/errors.h"
#include "engine/util/load_control.h"
#include "engine/util/parallel.h"
#include "farm/commands/launch_command.h"
#include "farm/commands/render_decision.h"
#include "farm/commands/render_options.h"
#include "farm/commands/render_outcome.h"
#include "farm/commands/worker_head_start.h"
#include "farm/cluster/launcher_reaper.h"
#include "farm/cluster/master.h"
#include "farm/cluster/master_watch.h"
#include "farm/cluster/run_farm.h"
#include "farm/cluster/scene_broadcast.h"
#include "farm/cluster/worker.h"
#include "farm/output/output_lock.h"
#include "farm/process/interrupt.h"
#include "farm/process/load_watch.h"
#include "farm/process/progress.h"
#include "anim/timeline.h"

namespace rf::cli {

using namespace rf::farm;
using Clock = std::chrono::steady_clock;

namespace {

/// CPUs this process may run on: mpirun binds each rank to one core when it starts two or
/// fewer, to a socket beyond that, and nothing when --bind-to none.
int cpusAllowed() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) return hardwareThreads();
    return std::max(1, CPU_COUNT(&set));
}

/// Threads this rank renders with: --threads; else the cores mpirun bound it to; else (not
/// bound) the node's cores shared among the ranks on it.
int threadsForRank(const RenderJob& job, const Transport& t) {
    if (job.threads > 0) return job.threads;
    const int allowed = cpusAllowed();
    if (allowed < hardwareThreads()) return allowed;
    return std::max(1, hardwareThreads() / std::max(1, t.ranksOnThisNode()));
}

/// "2 render thread(s) on rank 0 (bound by mpirun to 1 of 2 CPUs)", for the plan line.
std::string describeThreads(const RenderJob& job, const Transport& t) {
    std::string s = std::to_string(threadsForRank(job, t)) + " render thread(s) on rank 0";
    if (cpusAllowed() < hardwareThreads())
        s += " (bound by mpirun to " + std::to_string(cpusAllowed()) + " of " + std::to_string(hardwareThreads()) + " CPUs)";
    return s;
}

/// Rank 0 after the scene is shared: runFarm with the job's sinks, then the outcome's lines. It
/// takes the MPI transport for abort(): a lost worker cannot be stopped any other way.
int runRank0(MpiTransport& t, const RenderJob& job, SharedScene& shared, const std::vector<std::string>& args,
             Clock::time_point wallStart, const std::string& progressLabel, std::vector<OutputLock>& locks, bool moreFilms) {
    for (const std::string& note : shared.scene.notes) printLine("note", note);  // one write() a line: mpirun interleaves ranks by write
    if (const std::string keep = keepAliveNote(t.size()); !keep.empty()) printLine("note", keep);
    if (bounceLeftOutForMotion(shared.scene, job.settings))
        printLine("note", "bounce light left out: the model's geometry moves over the film, and its bounce cache would be "
                          "built again for every frame (--bounce N keeps it, at that cost)");
    FarmOptions opts;
    opts.threads = threadsForRank(job, t);
    opts.liveProgress = stderrIsTerminal();
    opts.wallStart = wallStart;
    opts.progressLabel = progressLabel;
    int code = 0;
    opts.onEnd = [&](const FarmOutcome& o) {
        // A resume typed as soon as the line shows waits for this run instead of being refused.
        if (o.end != FarmEnd::Done)
            for (OutputLock& l : locks) l.markEnding();
        code = reportOutcome(t.size(), job, o, args);
    };
    opts.onLastWords = [&locks] {
        for (OutputLock& l : locks) l.release();
    };
    StopWorkersOnThrow setUp(t);  // opening the video can fail (a full disk), after the workers started
    const anim::Timeline timeline = anim::Timeline::fromScene(shared, job.fpsOption);
    FarmSinks sinks = sinksForJob(job, [timeline](int f) { return timeline.frameTime(f); });
    setUp.dismiss();  // runFarm guards its own set-up
    FarmOutcome o;
    try {
        o = runFarm(t, job, shared, std::move(sinks), opts);
    } catch (const std::exception& e) {
        // A failed write (a full disk) keeps the frames done so far: say how to go on.
        if (job.framesDir.empty()) throw;
        // An extra output that failed (--stats /dev/full) would fail the resume again: left out.
        const std::string what = e.what();
        std::string failed;
        for (const auto& [option, path] : renderOutputs(job))
            if (option != "-o" && option != "--frames-dir" && !path.empty() && what.rfind(path + ":", 0) == 0) failed = option;
        throw std::runtime_error(what + "; finished frames are in " + job.framesDir + "; to resume" +
                                 (failed.empty() ? "" : " without the " + failed + " that could not be written") + ": " +
                                 resumeCommand(args, t.size(), failed));
    }
    if (o.abortRanks) t.abort(code);
    if (o.lostWorkers > 0) {
        // Every film of a job starts with a broadcast to every rank: the ranks left cannot start
        // the next one without the lost rank, so the job ends with this film.
        if (moreFilms) {
            printLine("error", "a worker was lost during this film: the films after it are not started (the ranks left "
                               "cannot start one without it); run them again");
            if (code == 0) code = 1;
        }
        // A rank given up on may still run (stopped, hung, cut off): MPI_Finalize would wait for
        // it. Without --enable-recovery Open MPI would also end the job when rank 0 leaves
        // without it, with a failure: MPI_Abort with the run's status ends the ranks left and
        // mpirun returns that status. (With --enable-recovery MPI_Abort ends rank 0 alone.)
        if (!launcherKeepsJobAlive()) {
            for (OutputLock& l : locks) l.release();
            t.abort(code);
        }
        // Open MPI 4.1.4's mpirun --enable-recovery still waits for a daemon on a host cut off
        // (minutes, its keepalive's): it is ended if it outlives rank 0 by a few seconds.
        armLauncherReaper(MpiTransport::kLauncherGraceSeconds);
        t.skipFinalize();
        if (moreFilms) {
            for (OutputLock& l : locks) l.release();
            t.flush(1.0);
            std::_Exit(code);
        }
    }  // a lost worker cannot be stopped politely, and mpirun waits for it
    return code;
}

}  // namespace

int renderFilm(MpiTransport& t, const ArgParser& p, const std::vector<std::string>& args, RenderJob job,
               Clock::time_point wallStart, const FilmInJob* film) {
    const std::string threadsNote = describeThreads(job, t);
    SharedScene shared;
    // The film's bounce cache: the head start and the metering fill it, the frames use it.
    const auto bounceSlot = std::make_shared<SceneCacheSlot>();
    std::vector<OutputLock> locks;  // rank 0's, until the film ends
    locks.reserve(2);               // never moved: the load watch may release them from its thread
    // Rank 0 lost (killed, its host gone): a worker that sees rank 0's process end (the same
    // machine) leaves at once. One that cannot see it leaves once rank 0 has been silent for
    // twice --timeout, 4 s at least. Not sooner: on a host whose link is cut, a worker that
    // exits makes Open MPI's daemon there report it to mpirun over the dead link, and with data
    // unacknowledged TCP stops the keepalive that would end the daemon: it then lingers for the
    // retransmission timeout (minutes; tests/multihost, --timeout 3: the worker gone at 2.9 s
    // left the daemon running past 39 s; at 6 s the daemon's keepalive ended it and the host was
    // empty in 7.1 s).
    const double silentLimit = std::max(4.0, 2.0 * job.workerTimeout);
    try {
        // A signal while loading ends the run within a second (load_watch.h).
        LoadWatch watch(job.scenePath, t.rank() == 0, [&locks] {
            for (OutputLock& l : locks) l.release();
        });
        try {
            shared = shareScene(
                t, job.scenePath, [&] { claimOutputs(job, p, locks); },
                [&](LoadedScene& loaded, const FileBundle& inputs) {
                    std::vector<std::string> read;
                    for (const auto& [path, bytes] : inputs.files) read.push_back(path);
                    checkOutputPaths(renderOutputs(job), read);  // the model's buffers and textures too
                    decideJob(job, p, loaded, bounceSlot, inputs, t.size(), threadsNote, film != nullptr);
                    return encodeWorkerJob(job);
                },
                sceneOptions(p),
                [&](LoadedScene& loaded) { workerHeadStart(loaded, *bounceSlot, p, job, threadsForRank(job, t)); }, bounceSlot,
                silentLimit);
        } catch (const LoadCancelled& c) {
            const int code = watch.interrupted(c);
            // A worker gets here only when rank 0 loaded and waits for it: say why it will not hear.
            if (t.rank() != 0) reportWorkerError(t, "interrupted (" + signalName(c.signal) + ") while loading its scene");
            return code;
        }
        watch.done();
    } catch (const MasterLost&) {
        std::_Exit(1);  // it said why; MPI_Finalize would wait for rank 0 forever
    } catch (const PeerFailed& e) {
        // Rank 0 failed (and said why), or was interrupted while loading as this rank was.
        if (loadCancelSignal()) return signalExitStatus(loadCancelSignal());
        return e.code();
    } catch (const std::exception& e) {
        if (t.rank() == 0) throw;
        reportWorkerError(t, std::string("loading the broadcast scene: ") + e.what());
        return 1;
    }
    if (t.rank() != 0) {
        // Rank 0 lost: as while the scene came (silentLimit above). Before rank 0's first word
        // (it may be checking a resumed film's kept frames) a silence may last longer.
        const int code = runFarmWorker(t, shared, job.fpsOption, threadsForRank(job, t), silentLimit,
                                       std::max(24.0, 12.0 * job.workerTimeout));
        // A silent master: leave now, as MPI_Finalize would wait for rank 0 forever.
        if (code == kMasterSilentExit) std::_Exit(1);
        // Rank 0 went on without a lost rank. With a launcher that keeps the job alive, leave
        // now: MPI_Finalize would wait for the lost rank. Plain mpirun takes a rank leaving
        // without MPI_Finalize for a failure and ends the job: this rank waits in MPI_Finalize
        // instead until rank 0 ends the job (MPI_Abort with the run's status, runRank0).
        if (code == kStopAfterLossExit) {
            if (!launcherKeepsJobAlive()) return 0;
            t.flush(1.0);
            std::_Exit(0);
        }
        return code;
    }
    std::string label;
    if (film) label = "film " + std::to_string(film->index + 1) + " of " + std::to_string(film->count) + ", " + filmName(job.scenePath);
    return runRank0(t, job, shared, args, wallStart, label, locks, film && film->index + 1 < film->count);
}

}  // namespace rf::cli
