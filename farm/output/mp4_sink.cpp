#include "mp4_sink.h"

#include "chunk_encoder.h"
#include "chunk_muxer.h"
#include "frame_time.h"

#include <atomic>
#include <cstdio>
#include <cstring>
#include <stdexcept>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>
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
                " is repeated); the PNG frames keep " + std::to_string(width) + "x" + std::to_string(height);
    return note;
}

void flattenRgba(const uint8_t* rgba, size_t pixels, const uint8_t over[3], uint8_t* rgb) {
    for (size_t i = 0; i < pixels; ++i) {
        const unsigned a = rgba[4 * i + 3];
        for (int c = 0; c < 3; ++c) rgb[3 * i + c] = uint8_t((rgba[4 * i + c] * a + over[c] * (255 - a) + 127) / 255);
    }
}

struct Mp4Sink::Impl {
    std::string path;
    int width = 0, height = 0;
    Mp4Options options;
    std::unique_ptr<ChunkMuxer> muxer;
    std::unique_ptr<ChunkEncoder> encoder;  ///< the chunk being encoded here, if any
    int64_t chunkStart = 0;                 ///< its first frame's place in the film
    int64_t taken = 0;                      ///< frames of the film taken so far
    bool closed = false;

    void put(const std::vector<ChunkPacket>& packets) {
        for (const ChunkPacket& p : packets) muxer->write(p, chunkStart);
    }
    void endChunk() {
        if (!encoder) return;
        put(encoder->finish());
        encoder.reset();
    }
};

Mp4Sink::Mp4Sink(const std::string& path, int width, int height, const Mp4Options& o) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.width = width;
    m.height = height;
    m.options = o;
    if (o.chunkFrames < kMinChunkFrames) throw std::runtime_error(path + ": chunks of fewer than 2 frames");
    av_log_set_level(AV_LOG_ERROR);  // the encoders' per-run statistics are noise on the farm's stderr
    m.muxer = std::make_unique<ChunkMuxer>(path, width, height, o, o.chunkFrames);
}

Mp4Sink::~Mp4Sink() {
    try {
        close();
    } catch (...) {
        // close() reported to whoever called it; here the file is abandoned.
    }
}

void Mp4Sink::write(int, const std::vector<uint8_t>& rgb) {
    Impl& m = *impl_;
    if (m.closed) throw std::runtime_error(m.path + ": write after close");
    if (!m.encoder) {
        m.encoder = std::make_unique<ChunkEncoder>(m.path, m.width, m.height, m.options, m.options.chunkFrames);
        m.chunkStart = m.taken;
    }
    m.put(m.encoder->add(rgb));
    ++m.taken;
    if (m.taken - m.chunkStart == m.options.chunkFrames) m.endChunk();
}

void Mp4Sink::writeChunk(const EncodedChunk& c) {
    Impl& m = *impl_;
    if (m.closed) throw std::runtime_error(m.path + ": write after close");
    if (m.encoder || int64_t(c.index) * m.options.chunkFrames != m.taken)
        throw std::runtime_error(m.path + ": chunk " + std::to_string(c.index) + " came out of order (" + std::to_string(m.taken) +
                                 " frames in the film so far)");
    m.muxer->checkExtradata(c.extradata, c.index);
    m.chunkStart = m.taken;
    m.put(c.packets);
    m.taken += c.frames;
}

void Mp4Sink::close() {
    Impl& m = *impl_;
    if (m.closed) return;
    m.closed = true;
    m.endChunk();
    m.muxer->close();
}

int Mp4Sink::framesInOutput() const { return impl_->muxer->packetsInFile(); }

int Mp4Sink::framesTaken() const { return int(impl_->taken); }

}  // namespace rf::farm
