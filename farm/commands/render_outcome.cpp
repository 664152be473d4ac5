#include "farm/commands/render_outcome.h"

#include <csignal>
#include <fstream>

#include "farm/commands/formatted.h"
#include "farm/commands/launch_command.h"
#include "engine/util/errors.h"
#include "farm/output/png_sink.h"
#include "farm/output/run_stats.h"
#include "farm/output/video_options.h"
#include "farm/process/interrupt.h"

namespace rf::cli {

using namespace rf::farm;

namespace {

/// How this executable was invoked (argv[0]), for the resume hint.
std::string invokedAs() {
    std::ifstream f("/proc/self/cmdline", std::ios::binary);
    std::string arg0;
    std::getline(f, arg0, '\0');
    return arg0.empty() ? "rayfarm" : arg0;
}

/// An interrupted run's ending, beside the outputs: the lines in the frames directory's log, and
/// the stats file (if asked for) with what was done, the signal and the resume command.
void recordInterruption(const RenderJob& job, const FarmOutcome& o, int sig, const std::string& resume, const std::string& lines) {
    if (!job.framesDir.empty()) appendFramesLog(job.framesDir, lines);
    if (job.statsPath.empty()) return;
    RunStats s = o.stats;
    s.width = job.settings.width;
    s.height = job.settings.height;
    if (s.mode.empty()) s.mode = job.mode == Mode::Pixel ? "pixel" : "frame";
    s.extraText["interrupted"] = signalName(sig);
    s.extraText["video"] = o.videoHolds;
    if (!resume.empty()) s.extraText["resume"] = resume;
    try {
        writeStatsJson(job.statsPath, s);
    } catch (const std::exception& e) {
        writeStderrText(std::string("rayfarm: error: ") + e.what() + "\n");
    }
}

}  // namespace

std::string resumeCommand(const std::vector<std::string>& args, int ranks, const std::string& leaveOut) {
    // Under mpirun, mpirun's own options (--oversubscribe, --hostfile, --mca ...) come along.
    const std::string launcher = launcherPrefix(ranks);
    std::string cmd = (launcher.empty() ? std::string() : launcher + " ") + shellQuote(invokedAs()) + " render";
    bool hasResume = false;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--overwrite") continue;  // it would throw away the frames the resume keeps
        if (!leaveOut.empty() && a == leaveOut) {  // "--stats FILE": the option and its value
            ++i;
            continue;
        }
        if (!leaveOut.empty() && a.rfind(leaveOut + "=", 0) == 0) continue;
        cmd += ' ';
        cmd += shellQuote(a);
        hasResume = hasResume || a == "--resume";
    }
    return hasResume ? cmd : cmd + " --resume";
}

int reportOutcome(int ranks, const RenderJob& job, const FarmOutcome& o, const std::vector<std::string>& args) {
    if (o.end == FarmEnd::WorkerLost) {
        std::string lines = "rayfarm: error: " + o.error + "; " + o.videoHolds + " (playable)\n";
        if (!job.framesDir.empty())
            lines += "rayfarm: finished frames are in " + job.framesDir + "; to resume: " + resumeCommand(args, ranks) + "\n";
        writeStderrText(lines);
        if (!job.framesDir.empty()) appendFramesLog(job.framesDir, lines);
        return 1;
    }
    if (o.end != FarmEnd::Done) {
        // Both lines in one write, before runFarm tells the workers (mpirun's SIGKILL is near).
        const int sig = o.signal ? o.signal : SIGTERM;
        std::string lines = "rayfarm: interrupted (" + signalName(sig) + "): " + o.videoHolds + " (playable)\n";
        if (!job.framesDir.empty()) lines += "rayfarm: to resume: " + resumeCommand(args, ranks) + "\n";
        writeStderrText(lines);
        // Also where it can be read when stderr is gone (a hang-up, a closed pipe).
        recordInterruption(job, o, sig, job.framesDir.empty() ? "" : resumeCommand(args, ranks), lines);
        return signalExitStatus(sig);
    }
    const RunStats& s = o.stats;
    // The video's own size: encoders that need even sizes repeat the last column or row.
    int videoW = s.width, videoH = s.height;
    mp4EncodedSize(s.width, s.height, job.mp4, videoW, videoH, job.output);
    std::string lines = formatted("rayfarm: wrote %s: %d frames %dx%d at %.4g fps; %.1f fps sustained over %.2f s (wall %.2f s); "
                                  "encoder busy %.2f s (%.0f%%)\n",
                                  printable(job.output).c_str(), s.frames, videoW, videoH, job.mp4.fps, s.sustainedFps, s.renderSeconds,
                                  s.wallSeconds, s.encodeSeconds, s.renderSeconds > 0 ? 100.0 * s.encodeSeconds / s.renderSeconds : 0.0);
    if (s.rays.nonFinite)
        lines += "rayfarm: note: " + std::to_string((unsigned long long)s.rays.nonFinite) + " non-finite samples replaced by black\n";
    writeStderrText(lines);
    if (!job.framesDir.empty()) appendFramesLog(job.framesDir, lines);
    return 0;
}

}  // namespace rf::cli
