#include "mp4_sink.h"

#include "frame_time.h"
#include "mp4_remux.h"

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
    int width = 0, height = 0, encW = 0, encH = 0;
    int channels = 3;        ///< of the frames coming in
    int srcChannels = 3;     ///< of what goes to swscale (RGBA only when the format keeps alpha)
    uint8_t over[3] = {0, 0, 0};
    AVFormatContext* fmt = nullptr;
    AVCodecContext* ctx = nullptr;
    AVStream* stream = nullptr;
    SwsContext* sws = nullptr;
    AVFrame* frame = nullptr;
    AVPacket* pkt = nullptr;
    std::vector<uint8_t> flat, padded;
    int64_t nextPts = 0;
    bool closed = false;
    /// MP4 and MOV: written fragmented, remuxed to faststart at close (mp4_remux.h).
    bool fragmented = false;
    AVRational rate{30, 1};
    /// Packets on disk: each is flushed as it is muxed (its own fragment, or WebM cluster).
    std::atomic<int> flushed{0};

    [[noreturn]] void fail(const std::string& what, int rc) {
        throw std::runtime_error(path + ": " + what + (rc < 0 ? ": " + avErrorText(rc) : std::string()));
    }

    void drain() {
        for (;;) {
            int rc = avcodec_receive_packet(ctx, pkt);
            if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return;
            if (rc < 0) fail("encoding failed", rc);
            av_packet_rescale_ts(pkt, ctx->time_base, stream->time_base);
            pkt->stream_index = stream->index;
            rc = av_interleaved_write_frame(fmt, pkt);  // takes ownership of the packet's data
            if (rc < 0) fail("writing failed", rc);
            flush();
        }
    }

    /// Ends the fragment (MP4/MOV) or cluster (WebM) holding the packet just muxed and pushes it
    /// to the file: a process killed after this leaves a file that plays it.
    void flush() {
        int rc = av_write_frame(fmt, nullptr);
        if (rc < 0) fail("writing failed", rc);
        avio_flush(fmt->pb);
        if (fmt->pb->error < 0) fail("writing failed", fmt->pb->error);
        flushed.fetch_add(1, std::memory_order_relaxed);
    }

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

    void openEncoder(const VideoFormat& vf, const Mp4Options& o);
    void openFile(const VideoFormat& vf);
    void makeConverter(AVPixelFormat pix);
    const uint8_t* prepare(const std::vector<uint8_t>& in);
};

void Mp4Sink::Impl::openEncoder(const VideoFormat& vf, const Mp4Options& o) {
    int rc = avformat_alloc_output_context2(&fmt, nullptr, vf.muxer.c_str(), path.c_str());
    if (rc < 0 || !fmt) fail("cannot set up the " + vf.muxer + " muxer", rc);
    const AVCodec* codec = avcodec_find_encoder_by_name(vf.encoder.c_str());
    if (!codec) fail("no " + vf.encoder + " encoder in this FFmpeg", 0);
    stream = avformat_new_stream(fmt, nullptr);
    ctx = avcodec_alloc_context3(codec);
    if (!stream || !ctx) fail("out of memory", 0);

    rate = av_d2q(o.fps, 1001000);
    const AVPixelFormat pix = av_get_pix_fmt(vf.pixFmt.c_str());
    ctx->width = encW;
    ctx->height = encH;
    ctx->framerate = rate;
    ctx->time_base = av_inv_q(rate);
    ctx->sample_aspect_ratio = {1, 1};
    // One encoder thread: x264's (and libvpx's) output depends on the thread count, and "auto"
    // follows the CPU affinity mpirun gives rank 0, so the same frames would encode differently
    // at another rank count (and a --resume would not reproduce the video). One thread of x264's
    // ultrafast preset encodes 640x360 at several hundred fps, far above what the farm renders.
    ctx->thread_count = 1;
    ctx->pix_fmt = pix;
    const bool rgb = (av_pix_fmt_desc_get(pix)->flags & AV_PIX_FMT_FLAG_RGB) != 0;
    ctx->color_range = rgb ? AVCOL_RANGE_JPEG : AVCOL_RANGE_MPEG;
    ctx->colorspace = rgb ? AVCOL_SPC_RGB : AVCOL_SPC_BT709;
    // Primaries and transfer tagged BT.709 (the sRGB primaries; players treat the sRGB curve as
    // BT.709 in practice), so every player shows the same colours.
    ctx->color_primaries = AVCOL_PRI_BT709;
    ctx->color_trc = AVCOL_TRC_BT709;
    if (fmt->oformat->flags & AVFMT_GLOBALHEADER) ctx->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;

    AVDictionary* copts = nullptr;
    for (const auto& [k, v] : vf.encoderOptions) av_dict_set(&copts, k.c_str(), v.c_str(), 0);
    rc = avcodec_open2(ctx, codec, &copts);
    av_dict_free(&copts);
    if (rc < 0) fail("cannot open the " + vf.encoder + " encoder", rc);
    rc = avcodec_parameters_from_context(stream->codecpar, ctx);
    if (rc < 0) fail("cannot set stream parameters", rc);
    stream->time_base = ctx->time_base;
    stream->avg_frame_rate = rate;
    stream->r_frame_rate = rate;
    // WebM signals VP9 alpha (coded as BlockAdditional side data) with AlphaMode on the track.
    if (vf.alpha && vf.container == Container::Webm) av_dict_set(&stream->metadata, "alpha_mode", "1", 0);
}

void Mp4Sink::Impl::openFile(const VideoFormat& vf) {
    int rc = avio_open(&fmt->pb, path.c_str(), AVIO_FLAG_WRITE);
    if (rc < 0) fail("cannot open for writing", rc);
    std::remove(remuxTempPath(path).c_str());  // a run killed during its remux left it
    AVDictionary* fopts = nullptr;
    // MP4 and MOV: an empty moov, then one fragment per frame, flushed by flush() (frag_custom):
    // the file plays up to its last frame whatever ends the process. close() remuxes it to
    // faststart.
    fragmented = vf.container == Container::Mp4 || vf.container == Container::Mov;
    if (fragmented) av_dict_set(&fopts, "movflags", "+frag_custom+empty_moov+default_base_moof", 0);
    rc = avformat_write_header(fmt, &fopts);
    av_dict_free(&fopts);
    if (rc < 0) fail("cannot write the " + vf.muxer + " header", rc);
}

void Mp4Sink::Impl::makeConverter(AVPixelFormat pix) {
    frame = av_frame_alloc();
    pkt = av_packet_alloc();
    if (!frame || !pkt) fail("out of memory", 0);
    frame->format = pix;
    frame->width = encW;
    frame->height = encH;
    frame->color_range = ctx->color_range;
    frame->colorspace = ctx->colorspace;
    frame->color_primaries = ctx->color_primaries;
    frame->color_trc = ctx->color_trc;
    int rc = av_frame_get_buffer(frame, 0);
    if (rc < 0) fail("out of memory", rc);
    if (pix == AV_PIX_FMT_RGB24) return;  // lossless RGB: copied as it is
    const AVPixelFormat src = srcChannels == 4 ? AV_PIX_FMT_RGBA : AV_PIX_FMT_RGB24;
    sws = sws_getContext(encW, encH, src, encW, encH, pix, SWS_BILINEAR | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, nullptr,
                         nullptr, nullptr);
    if (!sws) fail("cannot set up the RGB to YUV conversion", 0);
    // Full-range RGB in, BT.709 matrix and limited (TV) range out, matching the tags above.
    const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
    sws_setColorspaceDetails(sws, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);
}

Mp4Sink::Mp4Sink(const std::string& path, int width, int height, const Mp4Options& o) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.width = width;
    m.height = height;
    m.channels = o.channels;
    std::memcpy(m.over, o.flattenOver, 3);
    av_log_set_level(AV_LOG_ERROR);  // the encoders' per-run statistics are noise on the farm's stderr
    try {
        VideoFormat vf;
        try {
            vf = videoFormatOf(path, o);
        } catch (const std::invalid_argument& e) {
            m.fail(e.what(), 0);
        }
        m.srcChannels = vf.alpha ? 4 : 3;
        mp4EncodedSize(width, height, o, m.encW, m.encH, path);
        m.openEncoder(vf, o);
        m.openFile(vf);
        m.makeConverter(m.ctx->pix_fmt);
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

/// The frame as encW × encH pixels of srcChannels: flattened if the format has no alpha, padded
/// if the size had to be made even.
const uint8_t* Mp4Sink::Impl::prepare(const std::vector<uint8_t>& in) {
    const size_t pixels = size_t(width) * height;
    const uint8_t* src = in.data();
    if (channels == 4 && srcChannels == 3) {
        flat.resize(pixels * 3);
        flattenRgba(src, pixels, over, flat.data());
        src = flat.data();
    }
    if (encW == width && encH == height) return src;
    // Repeat the last column and row rather than adding black, so chroma at the edge is not smeared.
    const size_t ch = size_t(srcChannels);
    padded.resize(size_t(encW) * encH * ch);
    for (int y = 0; y < encH; ++y) {
        const uint8_t* row = src + ch * size_t(std::min(y, height - 1)) * width;
        uint8_t* dst = padded.data() + ch * size_t(y) * encW;
        std::memcpy(dst, row, ch * size_t(width));
        for (int x = width; x < encW; ++x) std::memcpy(dst + ch * x, row + ch * (width - 1), ch);
    }
    return padded.data();
}

void Mp4Sink::write(int, const std::vector<uint8_t>& rgb) {
    Impl& m = *impl_;
    if (m.closed) throw std::runtime_error(m.path + ": write after close");
    if (rgb.size() < size_t(m.width) * m.height * m.channels) throw std::runtime_error(m.path + ": frame has the wrong size");
    const uint8_t* src = m.prepare(rgb);
    int rc = av_frame_make_writable(m.frame);
    if (rc < 0) m.fail("out of memory", rc);
    const int stride = m.srcChannels * m.encW;
    if (m.sws) {
        const uint8_t* planes[1] = {src};
        const int strides[1] = {stride};
        sws_scale(m.sws, planes, strides, 0, m.encH, m.frame->data, m.frame->linesize);
    } else {
        for (int y = 0; y < m.encH; ++y)
            std::memcpy(m.frame->data[0] + size_t(y) * m.frame->linesize[0], src + size_t(y) * stride, size_t(stride));
    }
    m.frame->pts = m.nextPts++;
    rc = avcodec_send_frame(m.ctx, m.frame);
    if (rc < 0) m.fail("encoding failed", rc);
    m.drain();
}

void Mp4Sink::close() {
    Impl& m = *impl_;
    if (m.closed || !m.ctx) return;
    m.closed = true;
    int rc = avcodec_send_frame(m.ctx, nullptr);
    if (rc < 0 && rc != AVERROR_EOF) m.fail("encoding failed", rc);
    m.drain();
    rc = av_write_trailer(m.fmt);
    if (rc < 0) m.fail("cannot finish the " + std::string(m.fmt->oformat->name), rc);
    rc = avio_closep(&m.fmt->pb);
    if (rc < 0) m.fail("cannot close", rc);
    if (m.fragmented) remuxFaststart(m.path, m.fmt->oformat->name, m.rate.num, m.rate.den, m.flushed.load());
}

int Mp4Sink::framesInOutput() const { return impl_->flushed.load(std::memory_order_relaxed); }

}  // namespace rf::farm
