#include "farm/process/progress.h"

#include <utility>

#include <unistd.h>

#include "farm/process/interrupt.h"

namespace rf::farm {

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

Progress::Progress(int total, bool live, std::FILE* out, std::string label)
    : total_(total), live_(live), label_(std::move(label)), out_(out), start_(std::chrono::steady_clock::now()), last_(start_) {}

std::string Progress::line(int done, int total, double seconds, int doneAtStart, const std::vector<int>& rankFrames) {
    char buf[160];
    const int rendered = done - doneAtStart;
    const double fps = seconds > 0.0 ? rendered / seconds : 0.0;
    std::string eta = "--";
    if (fps > 0.0) {
        const int s = int((total - done) / fps + 0.5);
        std::snprintf(buf, sizeof buf, "%d:%02d", s / 60, s % 60);
        eta = buf;
    }
    std::snprintf(buf, sizeof buf, "rayfarm: %d/%d frames  %.1f fps  ETA %s  ranks:", done, total, fps, eta.c_str());
    std::string s = buf;
    const size_t shown = std::min<size_t>(rankFrames.size(), 16);
    for (size_t r = 0; r < shown; ++r) {
        s += ' ';
        s += rankFrames[r] < 0 ? std::string("-") : std::to_string(rankFrames[r]);
    }
    if (shown < rankFrames.size()) s += " …";
    return s;
}

void Progress::update(int done, const std::vector<int>& rankFrames) {
    const auto now = std::chrono::steady_clock::now();
    if (doneAtStart_ < 0) {
        doneAtStart_ = done;
        start_ = now;
    }
    const double sinceLast = std::chrono::duration<double>(now - last_).count();
    if (sinceLast < (live_ ? 0.25 : 5.0)) return;
    last_ = now;
    std::string s = label_.empty() ? std::string() : label_ + ": ";
    s += line(done, total_, std::chrono::duration<double>(now - start_).count(), doneAtStart_, rankFrames);
    const std::string text = live_ ? "\r\033[K" + s : s + "\n";
    if (out_ == stderr) {
        writeStderrText(text);  // a broken stderr (| head -1) ends the run as SIGPIPE would
    } else {
        std::fputs(text.c_str(), out_);
        std::fflush(out_);
    }
    printed_ = true;
}

void Progress::finish() {
    if (live_ && printed_) {
        if (out_ == stderr) writeStderrText("\r\033[K");
        else std::fputs("\r\033[K", out_);
    }
    std::fflush(out_);
}

}  // namespace rf::farm
