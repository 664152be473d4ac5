#include "farm/output/video_options.h"

#include <cstdio>
#include <stdexcept>

#include "anim/frame_time.h"

extern "C" {
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
}

namespace rf::farm {

namespace {

VideoRequest requestOf(const std::string& path, const Mp4Options& o) {
    VideoRequest r;
    r.path = path;
    r.codec = o.codec;
    r.crf = o.lossless ? -1 : o.crf;
    r.preset = o.preset;
    r.lossless = o.lossless;
    r.alpha = o.channels == 4;
    return r;
}

}  // namespace

VideoFormat videoFormatOf(const std::string& path, const Mp4Options& o) { return videoFormatFor(requestOf(path, o)); }

void mp4EncodedSize(int width, int height, const Mp4Options& o, int& encW, int& encH, const std::string& path) {
    const bool even = videoFormatOf(path, o).evenSize;
    encW = even ? width + (width & 1) : width;
    encH = even ? height + (height & 1) : height;
}

std::string checkMp4Options(int width, int height, const Mp4Options& o, const std::string& path) {
    if (!anim::fpsInRange(o.fps)) throw std::invalid_argument(std::string("--fps: ") + anim::kFpsRangeText);
    const VideoFormat f = videoFormatOf(path, o);
    // A GIF's delays are whole hundredths of a second in 16 bits: above 100 fps two frames share
    // a time and the muxer fails after the render; below 100/65535 fps the delay is clamped.
    if (f.container == Container::Gif && !(o.fps >= 0.0016 && o.fps <= 100.0)) {
        char got[32];
        std::snprintf(got, sizeof got, "%g", o.fps);
        throw std::invalid_argument("a GIF's frame delays count hundredths of a second, up to 655 s: expected a rate "
                                    "from 0.0016 to 100, got " + std::string(got) + " (use .mp4, .webm or .mov above 100 fps)");
    }
    std::string note;
    if (o.channels == 4 && !f.alpha)
        note = path + " cannot carry alpha: its frames are laid over the background colour (PNG frames keep alpha; .webm and .mov carry it)";
    int w = 0, h = 0;
    mp4EncodedSize(width, height, o, w, h, path);
    // FFmpeg's own size limit (about 268 million pixels with padding): refused here, before any
    // rendering, rather than by the encoder after the first frame.
    const int logLevel = av_log_get_level();
    av_log_set_level(AV_LOG_QUIET);  // the one line below says it; FFmpeg would log a second
    const bool sizeOk = av_image_check_size(unsigned(w), unsigned(h), 0, nullptr) >= 0;
    av_log_set_level(logLevel);
    if (!sizeOk)
        throw std::invalid_argument("--size " + std::to_string(width) + "x" + std::to_string(height) +
                                    ": too large for FFmpeg's video encoders ((width+128)·(height+128) must stay below 2^28)");
    if (w != width || h != height)
        note += std::string(note.empty() ? "" : "; ") + "the video is " + std::to_string(w) + "x" + std::to_string(h) + " (" +
                f.pixFmt + " needs even sizes: the last " + (w != width ? std::string("column") : std::string("")) +
                (w != width && h != height ? " and " : "") + (h != height ? std::string("row") : std::string("")) +
                " is repeated)";
    return note;
}

void flattenRgba(const uint8_t* rgba, size_t pixels, const uint8_t over[3], uint8_t* rgb) {
    for (size_t i = 0; i < pixels; ++i) {
        const unsigned a = rgba[4 * i + 3];
        for (int c = 0; c < 3; ++c) rgb[3 * i + c] = uint8_t((rgba[4 * i + c] * a + over[c] * (255 - a) + 127) / 255);
    }
}

}  // namespace rf::farm
