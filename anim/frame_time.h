#pragma once
/// Frame times from the frame index alone, never accumulated: frame i of a timeline starting
/// at t0 with fps frames per second is at t0 + i / fps.

namespace rf::anim {

/// Frame rates a film can have. MP4's time base is 1/fps as a rational; well below 1e-5 fps the
/// muxer's durations overflow and the first write fails, so the floor (a frame every 1000 s)
/// leaves room. The ceiling keeps a frame's time step well above a double's rounding.
constexpr double kMinFps = 0.001, kMaxFps = 1000.0;
inline bool fpsInRange(double fps) { return fps >= kMinFps && fps <= kMaxFps; }
constexpr const char* kFpsRangeText = "expected a rate from 0.001 (a frame every 1000 s) up to 1000";

/// Time in seconds of frame i.
inline double frameTime(double t0, double fps, long long i) { return t0 + static_cast<double>(i) / fps; }

/// Number of frames of a timeline of `seconds` at `fps`, at least 1. A loop (a turntable) does
/// not repeat its first frame at the end, so it has exactly round(seconds·fps) frames.
int frameCount(double seconds, double fps);

}  // namespace rf::anim
