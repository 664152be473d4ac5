#include "farm/process/progress.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

#include <sys/ioctl.h>
#include <unistd.h>

#include "farm/process/interrupt.h"

namespace rf::farm {

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

int stderrColumns() {
    winsize ws{};
    if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) return int(ws.ws_col);
    return 80;
}

void RateWindow::add(double t, int done) {
    now_ = t;
    if (samples_.empty() || samples_.back().second != done) samples_.emplace_back(t, done);
    // Keep one sample at or before the window's start, so the window spans all of it, and at
    // least minFrames_ frames: workers that finish together (a farm of equal frames) come in
    // bursts, and a window holding only the last frames of one burst would see their tiny gap.
    while (samples_.size() > 2 && samples_[1].first <= t - seconds_ && done - samples_[1].second >= minFrames_)
        samples_.pop_front();
}

double RateWindow::rate() const {
    if (samples_.size() < 2) return 0.0;
    const auto& [t0, d0] = samples_.front();
    const auto& [t1, d1] = samples_.back();
    const int n = d1 - d0;
    const double span = t1 - t0;
    if (n <= 0 || !(span > 0.0)) return 0.0;
    // Frames arrive one by one: up to one average gap after the last, the rate is that of the
    // arrivals; a longer wait lowers it, as the frame that has not come yet would.
    const double gap = span / n;
    return n / std::max(span, now_ - t0 - gap);
}

double RateWindow::eta(int total) const {
    const double r = rate();
    if (!(r > 0.0)) return -1.0;
    const auto& [t0, d0] = samples_.front();
    const auto& [t1, d1] = samples_.back();
    const double gap = (t1 - t0) / (d1 - d0);
    // Counted down between arrivals (for up to a gap), so that it falls smoothly, not a frame's
    // time at once when a frame comes back.
    return std::max(0.0, std::max(0, total - d1) / r - std::min(now_ - t1, gap));
}

Progress::Progress(int total, bool live, std::FILE* out, std::string label)
    : total_(total), live_(live), label_(std::move(label)), out_(out), interval_(live ? 0.25 : 5.0) {
    if (const char* e = std::getenv("RAYFARM_PROGRESS_SECONDS")) {
        char* end = nullptr;
        const double v = std::strtod(e, &end);
        if (end != e && std::isfinite(v) && v >= 0.0) interval_ = v;
    }
    start_ = last_ = std::chrono::steady_clock::now();
}

std::string Progress::text(const ProgressCounts& c, int total, double fps, double eta) {
    char buf[64];
    std::string e = "--";
    if (eta >= 0.0) {
        const long s = std::lround(std::min(eta, 1e8));
        if (s >= 3600) std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
        else std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
        e = buf;
    }
    char line[200];
    std::snprintf(line, sizeof line, "%d/%d rendered, %d encoded, %.1f fps, ETA %s, %d/%d workers busy", c.rendered, total,
                  c.encoded, fps, e.c_str(), c.busy, c.alive);
    return line;
}

std::string Progress::bar(const ProgressCounts& c, int total, int width) {
    const auto cells = [&](int frames) {
        if (total <= 0) return 0;
        return int(std::clamp<long long>((long long)frames * width / total, 0, width));
    };
    const int enc = cells(c.encoded), ren = std::max(enc, cells(c.rendered));
    // Appended in place: GCC 12 warns (-Wrestrict, a false positive) on a chain of + over
    // strings of computed lengths.
    std::string s;
    s.reserve(size_t(width) + 2);
    s.push_back('[');
    s.append(size_t(enc), '#');
    s.append(size_t(ren - enc), '=');
    s.append(size_t(width - ren), '.');
    s.push_back(']');
    return s;
}

std::string Progress::liveLine(const std::string& label, const std::string& text, const ProgressCounts& c, int total,
                               int columns) {
    std::string head = label.empty() ? std::string() : label + ": ";
    // One column spare: a line that fills the last column wraps on some terminals.
    const int room = columns - 1 - int(head.size()) - int(text.size()) - 3;  // "[", "]", " "
    if (room >= kMinBar) head += bar(c, total, std::min(room, kMaxBar)) + " ";
    std::string s = head + text;
    if (columns > 1 && int(s.size()) > columns - 1) s.resize(size_t(columns - 1));
    return s;
}

void Progress::update(const ProgressCounts& counts) {
    const auto now = std::chrono::steady_clock::now();
    if (!started_) {
        started_ = true;
        start_ = last_ = now;
    }
    window_.setMinFrames(2 * std::max(1, counts.alive));
    window_.add(std::chrono::duration<double>(now - start_).count(), counts.rendered);
    const double sinceLast = std::chrono::duration<double>(now - last_).count();
    if (sinceLast < interval_) return;
    last_ = now;
    const std::string words = text(counts, total_, window_.rate(), window_.eta(total_));
    std::string s;
    if (live_) {
        // The bar keeps its width while the words grow: it is sized for the longest they get.
        const ProgressCounts widest{total_, total_, counts.alive, counts.alive};
        const int room = int(text(widest, total_, 99.9, 3599.0).size()) - int(words.size());
        s = "\r\033[K" + liveLine(label_, words, counts, total_, stderrColumns() - std::max(0, room));
    } else {
        s = (label_.empty() ? std::string() : label_ + ": ") + "rayfarm: " + words + "\n";
    }
    if (out_ == stderr) {
        writeStderrText(s);  // a broken stderr (| head -1) ends the run as SIGPIPE would
    } else {
        std::fputs(s.c_str(), out_);
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
