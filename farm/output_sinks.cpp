#include "output_sinks.h"

#include "contact_sheet.h"
#include "exr_frames.h"
#include "gif_sink.h"
#include "png_sink.h"

namespace rf::farm {

OutputSinks makeOutputSinks(const RenderJob& job, std::function<double(int)> timeOf) {
    const int w = job.settings.width, h = job.settings.height;
    const PixelLayout layout = job.layout();
    std::vector<std::unique_ptr<FrameSink>> inOrder;
    if (job.video.container == Container::Gif) {
        const std::string dither = job.video.encoderOptions.at(0).second;
        inOrder.push_back(std::make_unique<GifSink>(job.output, w, h, layout.channels, job.mp4.fps, dither));
    } else {
        inOrder.push_back(std::make_unique<Mp4Sink>(job.output, w, h, job.mp4));
    }
    if (!job.contactSheet.empty())
        inOrder.push_back(std::make_unique<ContactSheetSink>(job.contactSheet, w, h, layout.channels, job.first, job.last, timeOf));
    if (!job.poster.empty())
        inOrder.push_back(std::make_unique<PosterSink>(job.poster, job.posterFrame >= 0 ? job.posterFrame : job.first, w, h, layout.channels));
    OutputSinks out;
    out.video = inOrder.size() == 1 ? std::move(inOrder[0]) : std::make_unique<TeeSink>(std::move(inOrder));
    if (!job.framesDir.empty()) {
        std::vector<std::unique_ptr<FrameSink>> frames;
        frames.push_back(std::make_unique<PngSink>(job.framesDir, w, h, layout.channels));
        if (job.exrFrames) frames.push_back(std::make_unique<ExrSink>(job.framesDir, w, h, layout));
        out.frames = frames.size() == 1 ? std::move(frames[0]) : std::make_unique<TeeSink>(std::move(frames));
    }
    return out;
}

std::set<int> keptFramesForJob(const RenderJob& job, std::vector<int>* corrupt) {
    const std::vector<int> order = job.frames();
    std::set<int> kept = findKeptFrames(job.framesDir, order, job.settings.width, job.settings.height, corrupt, job.layout().channels);
    if (!job.exrFrames) return kept;
    const std::set<int> exr = findKeptExrFrames(job.framesDir, order, job.settings.width, job.settings.height);
    std::set<int> both;
    for (int f : kept)
        if (exr.count(f)) both.insert(f);
    return both;
}

}  // namespace rf::farm
