// rayfarm: one executable, four commands (render, still, report, view).
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "cli.h"
#include "errors.h"

namespace {

const char* kUsage =
    "usage: rayfarm COMMAND [options]\n"
    "\n"
    "commands:\n"
    "  render SCENE|MODEL -o out.mp4   render the timeline to video (under mpirun: a render farm)\n"
    "  still SCENE|MODEL -o out.png    render one frame to a PNG\n"
    "  report SCENE --out DIR          error against run time for the quality settings\n"
    "  view SCENE|MODEL                live window: orbit, key a camera path, save it\n"
    "\n"
    "Run 'rayfarm COMMAND --help' for a command's options.\n";

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
        std::fputs(kUsage, args.empty() ? stderr : stdout);
        return args.empty() ? 2 : 0;
    }
    const std::string cmd = args[0];
    args.erase(args.begin());
    try {
        if (cmd == "still") return rf::cli::runStill(args);
        if (cmd == "render") return rf::cli::runRender(args);
        if (cmd == "report") return rf::cli::runReport(args);
        if (cmd == "view") {
#ifdef RAYFARM_HAVE_VIEW
            return rf::cli::runView(args);
#else
            std::cerr << "rayfarm: error: view: this rayfarm was built without Qt 6 (install qt6-base-dev and rebuild)\n";
            return 2;
#endif
        }
        std::cerr << "rayfarm: error: unknown command \"" << cmd << "\" (expected render, still, report or view)\n";
        return 2;
    } catch (const rf::InputError& e) {
        std::cerr << "rayfarm: error: " << e.what() << "\n";
        return 2;
    } catch (const rf::cli::UsageError& e) {
        std::cerr << "rayfarm: error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "rayfarm: error: " << e.what() << "\n";
        return 1;
    }
}
