#pragma once
/// What `view --stats FILE` reports: frames shown, frame rate while the camera moves, and the
/// latency from an input event to the first frame on screen that answers it.
#include <map>
#include <string>
#include <vector>

namespace rf::view {

class ViewStats {
public:
    /// A frame of `width` pixels across reached the screen at `nowS` (seconds, any fixed
    /// origin). latencyMs < 0: it answers no input event (refinement, playback).
    void frameShown(double nowS, bool moving, double latencyMs, int width = 0);
    int framesShown() const { return frames_; }
    int movingFrames() const { return movingFrames_; }
    /// Moving frames per second of moving time (gaps over 0.5 s between moving frames are rest).
    double movingFps() const;
    double latencyMeanMs() const;
    /// Nearest-rank 95th percentile.
    double latencyP95Ms() const;
    /// Writes the figures as JSON; throws std::runtime_error naming the path on failure.
    void write(const std::string& path, int width, int height, int ranks, int threads) const;

private:
    int frames_ = 0, movingFrames_ = 0, movingIntervals_ = 0;
    double movingSeconds_ = 0.0, lastMovingS_ = -1.0;
    std::vector<double> latencies_;
    std::map<int, int> movingWidths_;  ///< moving frames by rendered width (lower resolution when slow)
};

}  // namespace rf::view
