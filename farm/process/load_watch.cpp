#include "farm/process/load_watch.h"

#include <csignal>

#include "engine/util/errors.h"
#include "farm/process/interrupt.h"

namespace rf::farm {

std::string loadInterruptedLine(int sig, const std::string& file, const std::string& step) {
    std::string line = "rayfarm: interrupted (" + signalName(sig) + ") while loading " + printable(file);
    if (!step.empty()) line += " (" + step + ")";
    line += "; nothing was rendered\n";
    return line;
}

LoadWatch::LoadWatch(std::string file, bool speak, std::function<void()> beforeExit)
    : file_(std::move(file)), speak_(speak), beforeExit_(std::move(beforeExit)),
      deadline_(speak_ ? kGraceSeconds : kQuietGraceSeconds, [this] { return lastWords(); }) {}

void LoadWatch::done() {
    if (!deadline_.claim()) deadline_.waitForEnd();
}

int LoadWatch::interrupted(const LoadCancelled& c) {
    if (!deadline_.claim()) deadline_.waitForEnd();
    const int sig = c.signal ? c.signal : SIGTERM;
    if (speak_) writeStderrText(loadInterruptedLine(sig, c.file.empty() ? file_ : c.file, c.step));
    return signalExitStatus(sig);
}

int LoadWatch::lastWords() {
    const int sig = interruptSignal() ? interruptSignal() : SIGTERM;
    // The step the load stopped in, if it is unwinding from there (freeing a large scene), else
    // the one it is in.
    if (speak_) writeStderrText(loadInterruptedLine(sig, file_, lastFailedStep()));
    if (beforeExit_) beforeExit_();
    return signalExitStatus(sig);
}

}  // namespace rf::farm
