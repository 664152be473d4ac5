#pragma once
/// Progress on stderr. On a terminal one live line with a bar, rewritten in place:
///   [#########====..............] 45/120 rendered, 30 encoded, 6.1 fps, ETA 0:12, 3/3 workers busy
/// otherwise (a log file, Slurm's output) the same words, one line every few seconds:
///   rayfarm: 45/120 rendered, 30 encoded, 6.1 fps, ETA 0:12, 3/3 workers busy
/// "rendered" moves frame by frame as each frame's last pixels come back; "encoded" moves as
/// frames reach the output (with chunked encoding, a chunk at a time), so rendered ≥ encoded.
/// The rate is over the last RateWindow::kSeconds of rendered frames and the ETA is the frames
/// not yet rendered at that rate, so neither jumps when a chunk is encoded.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <string>
#include <utility>

namespace rf::farm {

/// What the progress line counts.
struct ProgressCounts {
    int rendered = 0;  ///< frames rendered, those kept from an earlier run included
    int encoded = 0;   ///< frames handed to the output (video, frames directory)
    int alive = 0;     ///< rendering ranks still answering
    int busy = 0;      ///< of those, the ones holding work
};

/// The rendering rate over a sliding window of time, and the time left at that rate.
class RateWindow {
public:
    static constexpr double kSeconds = 10.0;
    explicit RateWindow(double seconds = kSeconds) : seconds_(seconds) {}
    /// At time t (seconds, never decreasing), `done` frames are rendered.
    void add(double t, int done);
    /// The window also spans at least this many frames (Progress: two per worker), however long
    /// they took.
    void setMinFrames(int frames) { minFrames_ = std::max(1, frames); }
    /// Frames per second over the window: the frames rendered since its oldest sample over the
    /// time from it to the last frame (the whole run while it is shorter than the window); a
    /// wait longer than the average gap between frames lowers it. 0 until a frame is rendered.
    double rate() const;
    /// Seconds until `total` frames are rendered at rate(), less the time since the last frame
    /// came (up to one average gap), so it falls smoothly between frames; -1 while the rate is
    /// unknown.
    double eta(int total) const;

private:
    double seconds_;
    int minFrames_ = 1;
    double now_ = 0.0;                            ///< the last add's time
    std::deque<std::pair<double, int>> samples_;  ///< (t, done) when done changed, oldest first
};

class Progress {
public:
    /// total: frames in the output (kept frames count as rendered from the start). label: put
    /// before each line (a job of several films: "film 2 of 3, NAME"), "" for none.
    /// The plain lines come every 5 s, or every RAYFARM_PROGRESS_SECONDS seconds when set.
    Progress(int total, bool live, std::FILE* out = stderr, std::string label = "");
    /// Rate-limited: prints only if enough time has passed since the last line.
    void update(const ProgressCounts& counts);
    /// Ends the live line.
    void finish();
    /// The words of a line (without the bar): "45/120 rendered, 30 encoded, 6.1 fps, ETA 0:12,
    /// 3/3 workers busy" (busy of alive). eta < 0: "ETA --".
    static std::string text(const ProgressCounts& c, int total, double fps, double eta);
    /// "[####====......]" of `width` cells between the brackets: '#' encoded, '=' rendered and
    /// not yet encoded, '.' the rest.
    static std::string bar(const ProgressCounts& c, int total, int width);
    /// The live line for a terminal `columns` wide: the label (if any), the bar as wide as fits
    /// (kMinBar to kMaxBar cells; none if kMinBar do not fit) and the text, cut to the width.
    static constexpr int kMinBar = 5, kMaxBar = 30;
    static std::string liveLine(const std::string& label, const std::string& text, const ProgressCounts& c, int total,
                                int columns);

private:
    int total_;
    bool live_;
    std::string label_;
    std::FILE* out_;
    double interval_;
    bool printed_ = false;
    bool started_ = false;
    RateWindow window_;
    std::chrono::steady_clock::time_point start_, last_;
};

/// Whether stderr is a terminal.
bool stderrIsTerminal();
/// stderr's terminal width in columns (80 when it cannot say).
int stderrColumns();

}  // namespace rf::farm
