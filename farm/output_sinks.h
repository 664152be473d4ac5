#pragma once
/// The sinks a render job names: the video (MP4, WebM, MOV or GIF) with the contact sheet and
/// poster beside it in output order, and the frames directory (PNG, plus EXR with
/// --frames-format exr) as frames complete.
#include <functional>
#include <memory>
#include <set>
#include <vector>

#include "frame_sink.h"
#include "render_job.h"

namespace rf::farm {

struct OutputSinks {
    std::unique_ptr<FrameSink> video;   ///< every frame in output order
    std::unique_ptr<FrameSink> frames;  ///< each frame as soon as it is complete; null with --no-frames
};

/// timeOf: a frame's time in seconds, for the contact sheet's labels. Opens the video at once,
/// so an unwritable output throws here.
OutputSinks makeOutputSinks(const RenderJob& job, std::function<double(int)> timeOf);

/// Frames of the job already finished in its frames directory: the PNG (with the job's
/// channels, its checksum as recorded) and, with EXR frames, the EXR too. corrupt: as for
/// findKeptFrames.
std::set<int> keptFramesForJob(const RenderJob& job, std::vector<int>* corrupt = nullptr);

}  // namespace rf::farm
