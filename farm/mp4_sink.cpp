#include "mp4_sink.h"

#include <cstring>
#include <stdexcept>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

namespace rf::farm {

namespace {

const char* kPresets[] = {"ultrafast", "superfast", "veryfast", "faster", "fast",
                          "medium",    "slow",      "slower",   "veryslow", "placebo"};

std::string avError(int rc) {
    char buf[AV_ERROR_MAX_STRING_SIZE] = {0};
    av_strerror(rc, buf, sizeof buf);
    return buf;
}

}  // namespace

void mp4EncodedSize(int width, int height, const Mp4Options& o, int& encW, int& encH) {
    encW = o.lossless ? width : width + (width & 1);
    encH = o.lossless ? height : height + (height & 1);
}

std::string checkMp4Options(int width, int height, const Mp4Options& o) {
    const char* encoder = o.lossless ? "libx264rgb" : "libx264";
    if (!avcodec_find_encoder_by_name(encoder))
        throw std::invalid_argument(std::string("this FFmpeg has no ") + encoder + " encoder (Debian's libavcodec has it)");
    bool known = false;
    for (const char* p : kPresets) known = known || o.preset == p;
    if (!known) throw std::invalid_argument("--preset: expected an x264 preset (ultrafast … medium … placebo), got \"" + o.preset + "\"");
    if (!(o.fps > 0.0 && o.fps <= 1000.0)) throw std::invalid_argument("--fps: expected a rate above 0 and up to 1000");
    int w = 0, h = 0;
    mp4EncodedSize(width, height, o, w, h);
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
        return "the video is " + std::to_string(w) + "x" + std::to_string(h) + " (yuv420p needs even sizes: the last " +
               (w != width ? std::string("column") : std::string("")) + (w != width && h != height ? " and " : "") +
               (h != height ? std::string("row") : std::string("")) + " is repeated); the PNG frames keep " +
               std::to_string(width) + "x" + std::to_string(height);
    return "";
}

struct Mp4Sink::Impl {
    std::string path;
    int width = 0, height = 0, encW = 0, encH = 0;
    AVFormatContext* fmt = nullptr;
    AVCodecContext* ctx = nullptr;
    AVStream* stream = nullptr;
    SwsContext* sws = nullptr;
    AVFrame* frame = nullptr;
    AVPacket* pkt = nullptr;
    std::vector<uint8_t> padded;
    int64_t nextPts = 0;
    bool closed = false;

    [[noreturn]] void fail(const std::string& what, int rc) {
        throw std::runtime_error(path + ": " + what + (rc < 0 ? ": " + avError(rc) : std::string()));
    }

    void drain(bool flushing) {
        for (;;) {
            int rc = avcodec_receive_packet(ctx, pkt);
            if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return;
            if (rc < 0) fail("encoding failed", rc);
            av_packet_rescale_ts(pkt, ctx->time_base, stream->time_base);
            pkt->stream_index = stream->index;
            rc = av_interleaved_write_frame(fmt, pkt);  // takes ownership of the packet's data
            if (rc < 0) fail("writing failed", rc);
        }
        (void)flushing;
    }

    /// The muxer, the H.264 encoder and its stream, tagged BT.709.
    void openEncoder(const Mp4Options& o);
    /// The file at path, and the MP4 header with the index up front (faststart).
    void openFile();
    /// The frame the RGB pixels are converted into, and the converter (not for lossless RGB).
    void allocFrame(bool lossless);

    void release() {
        if (sws) sws_freeContext(sws);
        sws = nullptr;
        av_frame_free(&frame);
        av_packet_free(&pkt);
        avcodec_free_context(&ctx);
        if (fmt) {
            if (fmt->pb) avio_closep(&fmt->pb);
            avformat_free_context(fmt);
            fmt = nullptr;
        }
    }
};

void Mp4Sink::Impl::openEncoder(const Mp4Options& o) {
    Impl& m = *this;
    int rc = avformat_alloc_output_context2(&m.fmt, nullptr, "mp4", path.c_str());
    if (rc < 0 || !m.fmt) m.fail("cannot set up the MP4 muxer", rc);
    const AVCodec* codec = avcodec_find_encoder_by_name(o.lossless ? "libx264rgb" : "libx264");
    if (!codec) m.fail("no libx264 encoder in this FFmpeg", 0);
    m.stream = avformat_new_stream(m.fmt, nullptr);
    m.ctx = avcodec_alloc_context3(codec);
    if (!m.stream || !m.ctx) m.fail("out of memory", 0);

    const AVRational rate = av_d2q(o.fps, 1001000);
    m.ctx->width = m.encW;
    m.ctx->height = m.encH;
    m.ctx->framerate = rate;
    m.ctx->time_base = av_inv_q(rate);
    m.ctx->sample_aspect_ratio = {1, 1};
    // One x264 thread: x264's output depends on its thread count, and "auto" follows the CPU
    // affinity mpirun gives rank 0, so the same frames would encode differently at another
    // rank count (and a --resume would not reproduce the video). One thread of the ultrafast
    // preset encodes 640x360 at several hundred fps, far above what the farm renders.
    m.ctx->thread_count = 1;
    if (o.lossless) {
        m.ctx->pix_fmt = AV_PIX_FMT_RGB24;
        m.ctx->color_range = AVCOL_RANGE_JPEG;
        m.ctx->colorspace = AVCOL_SPC_RGB;
    } else {
        m.ctx->pix_fmt = AV_PIX_FMT_YUV420P;
        m.ctx->color_range = AVCOL_RANGE_MPEG;
        m.ctx->colorspace = AVCOL_SPC_BT709;
    }
    // Primaries and transfer tagged BT.709 (the sRGB primaries; players treat the sRGB curve as
    // BT.709 in practice), so every player shows the same colours.
    m.ctx->color_primaries = AVCOL_PRI_BT709;
    m.ctx->color_trc = AVCOL_TRC_BT709;
    if (m.fmt->oformat->flags & AVFMT_GLOBALHEADER) m.ctx->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;

    AVDictionary* copts = nullptr;
    av_dict_set(&copts, "preset", o.preset.c_str(), 0);
    if (o.lossless) av_dict_set(&copts, "qp", "0", 0);
    else av_dict_set(&copts, "crf", std::to_string(o.crf).c_str(), 0);
    rc = avcodec_open2(m.ctx, codec, &copts);
    av_dict_free(&copts);
    if (rc < 0) m.fail("cannot open the H.264 encoder", rc);
    rc = avcodec_parameters_from_context(m.stream->codecpar, m.ctx);
    if (rc < 0) m.fail("cannot set stream parameters", rc);
    m.stream->time_base = m.ctx->time_base;
    m.stream->avg_frame_rate = rate;
    m.stream->r_frame_rate = rate;
}

void Mp4Sink::Impl::openFile() {
    Impl& m = *this;
    int rc = avio_open(&m.fmt->pb, path.c_str(), AVIO_FLAG_WRITE);
    if (rc < 0) m.fail("cannot open for writing", rc);
    AVDictionary* fopts = nullptr;
    av_dict_set(&fopts, "movflags", "+faststart", 0);
    rc = avformat_write_header(m.fmt, &fopts);
    av_dict_free(&fopts);
    if (rc < 0) m.fail("cannot write the MP4 header", rc);
}

void Mp4Sink::Impl::allocFrame(bool lossless) {
    Impl& m = *this;
    m.frame = av_frame_alloc();
    m.pkt = av_packet_alloc();
    if (!m.frame || !m.pkt) m.fail("out of memory", 0);
    m.frame->format = m.ctx->pix_fmt;
    m.frame->width = m.encW;
    m.frame->height = m.encH;
    m.frame->color_range = m.ctx->color_range;
    m.frame->colorspace = m.ctx->colorspace;
    m.frame->color_primaries = m.ctx->color_primaries;
    m.frame->color_trc = m.ctx->color_trc;
    const int rc = av_frame_get_buffer(m.frame, 0);
    if (rc < 0) m.fail("out of memory", rc);
    if (!lossless) {
        m.sws = sws_getContext(m.encW, m.encH, AV_PIX_FMT_RGB24, m.encW, m.encH, AV_PIX_FMT_YUV420P,
                               SWS_BILINEAR | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, nullptr, nullptr, nullptr);
        if (!m.sws) m.fail("cannot set up RGB to YUV conversion", 0);
        // Full-range RGB in, BT.709 matrix and limited (TV) range out, matching the tags above.
        const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
        sws_setColorspaceDetails(m.sws, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);
    }
}

Mp4Sink::Mp4Sink(const std::string& path, int width, int height, const Mp4Options& o) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.width = width;
    m.height = height;
    mp4EncodedSize(width, height, o, m.encW, m.encH);
    av_log_set_level(AV_LOG_ERROR);  // x264's per-run statistics are noise on the farm's stderr
    try {
        m.openEncoder(o);
        m.openFile();
        m.allocFrame(o.lossless);
    } catch (...) {
        m.release();
        throw;
    }
}

Mp4Sink::~Mp4Sink() {
    try {
        close();
    } catch (...) {
        // close() reported to whoever called it; here the file is abandoned.
    }
    impl_->release();
}

void Mp4Sink::write(int, const std::vector<uint8_t>& rgb) {
    Impl& m = *impl_;
    if (m.closed) throw std::runtime_error(m.path + ": write after close");
    if (rgb.size() != size_t(m.width) * m.height * 3) throw std::runtime_error(m.path + ": frame has the wrong size");
    const uint8_t* src = rgb.data();
    if (m.encW != m.width || m.encH != m.height) {
        // Repeat the last column and row rather than adding black, so chroma at the edge is not smeared.
        m.padded.resize(size_t(m.encW) * m.encH * 3);
        for (int y = 0; y < m.encH; ++y) {
            const uint8_t* row = rgb.data() + 3 * size_t(std::min(y, m.height - 1)) * m.width;
            uint8_t* dst = m.padded.data() + 3 * size_t(y) * m.encW;
            std::memcpy(dst, row, 3 * size_t(m.width));
            for (int x = m.width; x < m.encW; ++x) std::memcpy(dst + 3 * x, row + 3 * (m.width - 1), 3);
        }
        src = m.padded.data();
    }
    int rc = av_frame_make_writable(m.frame);
    if (rc < 0) m.fail("out of memory", rc);
    if (m.sws) {
        const uint8_t* planes[1] = {src};
        const int strides[1] = {3 * m.encW};
        sws_scale(m.sws, planes, strides, 0, m.encH, m.frame->data, m.frame->linesize);
    } else {
        for (int y = 0; y < m.encH; ++y)
            std::memcpy(m.frame->data[0] + size_t(y) * m.frame->linesize[0], src + 3 * size_t(y) * m.encW, 3 * size_t(m.encW));
    }
    m.frame->pts = m.nextPts++;
    rc = avcodec_send_frame(m.ctx, m.frame);
    if (rc < 0) m.fail("encoding failed", rc);
    m.drain(false);
}

void Mp4Sink::close() {
    Impl& m = *impl_;
    if (m.closed || !m.ctx) return;
    m.closed = true;
    int rc = avcodec_send_frame(m.ctx, nullptr);
    if (rc < 0 && rc != AVERROR_EOF) m.fail("encoding failed", rc);
    m.drain(true);
    rc = av_write_trailer(m.fmt);
    if (rc < 0) m.fail("cannot finish the MP4", rc);
    rc = avio_closep(&m.fmt->pb);
    if (rc < 0) m.fail("cannot close", rc);
}

}  // namespace rf::farm
