// rayfarm: one executable, five commands (render, still, report, view, info).
#include <csignal>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include <malloc.h>

#include "farm/cli/cli.h"
#include "farm/commands/commands.h"
#include "farm/report/cmd_report.h"
#include "engine/util/errors.h"
#include "farm/process/interrupt.h"
#include "farm/process/load_watch.h"
#include "farm/process/usage_error.h"
#include "farm/process/version.h"
#ifdef RAYFARM_HAVE_VIEW
#include "farm/view/cmd_view.h"
#endif

namespace {

const char* kUsage =
    "usage: rayfarm COMMAND [options]\n"
    "\n"
    "commands:\n"
    "  render SCENE|MODEL -o out.mp4   render the timeline to video (under mpirun: a render farm)\n"
    "  still SCENE|MODEL -o out.png    render one frame to a PNG\n"
    "  report SCENE --out DIR          error against run time for the quality settings\n"
    "  view SCENE|MODEL                live window: orbit, key a camera path, save it\n"
    "  info MODEL [--json]             what a glTF file holds and its default turntable\n"
    "\n"
    "Run 'rayfarm COMMAND --help' for a command's options; 'rayfarm --version' prints the version.\n";

}  // namespace

int main(int argc, char** argv) {
    // Frames (0.7 MB at 640x360, 6 MB at 1080p) are allocated and freed every frame: the
    // assembler's buffer, the sinks' queued copies, the tiles. Above 128 KB glibc maps each one
    // afresh and every page of it faults in again (13,000 faults in the 31-frame Whitted film,
    // 5,900 with these); kept in the heap, and not trimmed back, they are reused instead.
    mallopt(M_MMAP_THRESHOLD, 256 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
        std::fputs(kUsage, args.empty() ? stderr : stdout);
        return args.empty() ? 2 : 0;
    }
    if (args[0] == "--version") {
        std::printf("rayfarm %s\n", rf::farm::rayfarmVersion());
        return 0;
    }
    const std::string cmd = args[0];
    args.erase(args.begin());
    try {
        if (cmd == "still") return rf::cli::runStill(args);
        if (cmd == "render") return rf::cli::runRender(args);
        if (cmd == "report") return rf::cli::runReport(args);
        if (cmd == "info") return rf::cli::runInfo(args);
        if (cmd == "view") {
#ifdef RAYFARM_HAVE_VIEW
            return rf::cli::runView(args);
#else
            rf::cli::printLine("error", "view: this rayfarm was built without Qt 6 (install qt6-base-dev and rebuild)");
            return 2;
#endif
        }
        const std::string near = rf::cli::closestMatch(cmd, {"render", "still", "report", "view", "info", "--help", "--version"});
        rf::cli::printLine("error", "unknown command \"" + cmd + "\"" + (near.empty() ? "" : "; did you mean " + near + "?") +
                                        " (expected render, still, report, view or info)");
        return 2;
    } catch (const rf::InputError& e) {
        rf::cli::printLine("error", e.what());
        return 2;
    } catch (const rf::UsageError& e) {
        rf::cli::printLine("error", e.what());
        return 2;
    } catch (const rf::LoadCancelled& c) {
        // A command without a load watch of its own (report, view) interrupted while loading.
        const int sig = c.signal ? c.signal : SIGTERM;
        rf::farm::writeStderrText(rf::farm::loadInterruptedLine(sig, c.file, c.step));
        return rf::farm::signalExitStatus(sig);
    } catch (const std::bad_alloc&) {
        // Loads name what they were doing (OutOfMemoryError); anything else says at least this.
        rf::cli::printLine("error", "out of memory while running '" + cmd + "'");
        return 1;
    } catch (const std::exception& e) {
        rf::cli::printLine("error", e.what());
        return 1;
    }
}
