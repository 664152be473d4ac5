#pragma once
/// Frame times from the frame index alone, never accumulated: frame i of a timeline starting
/// at t0 with fps frames per second is at t0 + i / fps.

namespace rf::anim {

/// Time in seconds of frame i.
inline double frameTime(double t0, double fps, long long i) { return t0 + static_cast<double>(i) / fps; }

/// Number of frames of a timeline of `seconds` at `fps`, at least 1. A loop (a turntable) does
/// not repeat its first frame at the end, so it has exactly round(seconds·fps) frames.
int frameCount(double seconds, double fps);

}  // namespace rf::anim
