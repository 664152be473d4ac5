#include "farm/output/chunk_encoder.h"

#include <chrono>
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

struct ChunkEncoder::Impl {
    std::string path;
    int width = 0, height = 0, encW = 0, encH = 0;
    int channels = 3;     ///< of the frames coming in
    int srcChannels = 3;  ///< of what goes to swscale (RGBA only when the format keeps alpha)
    uint8_t over[3] = {0, 0, 0};
    AVCodecContext* ctx = nullptr;
    SwsContext* sws = nullptr;
    AVFrame* frame = nullptr;
    AVPacket* pkt = nullptr;
    std::vector<uint8_t> flat, padded;
    int64_t nextPts = 0;
    bool finished = false;

    ~Impl() {
        if (sws) sws_freeContext(sws);
        av_frame_free(&frame);
        av_packet_free(&pkt);
        avcodec_free_context(&ctx);
    }

    [[noreturn]] void fail(const std::string& what, int rc) {
        throw std::runtime_error(path + ": " + what + (rc < 0 ? ": " + avErrorText(rc) : std::string()));
    }

    void open(const VideoFormat& vf, const Mp4Options& o, int chunkFrames);
    void makeConverter(AVPixelFormat pix);
    const uint8_t* prepare(const std::vector<uint8_t>& in);
    void drain(std::vector<ChunkPacket>& out);
};

void ChunkEncoder::Impl::open(const VideoFormat& vf, const Mp4Options& o, int chunkFrames) {
    const AVCodec* codec = avcodec_find_encoder_by_name(vf.encoder.c_str());
    if (!codec) fail("no " + vf.encoder + " encoder in this FFmpeg", 0);
    ctx = avcodec_alloc_context3(codec);
    if (!ctx) fail("out of memory", 0);
    const AVRational rate = av_d2q(o.fps, 1001000);
    const AVPixelFormat pix = av_get_pix_fmt(vf.pixFmt.c_str());
    ctx->width = encW;
    ctx->height = encH;
    ctx->framerate = rate;
    ctx->time_base = av_inv_q(rate);  // one tick a frame: chunk timestamps count frames
    ctx->sample_aspect_ratio = {1, 1};
    // One encoder thread: x264's (and libvpx's) output depends on the thread count, and "auto"
    // follows the CPU affinity mpirun gives the rank, so the same frames would encode differently
    // on another rank or host. Chunks encode on many ranks at once, which is where the
    // parallelism comes from.
    ctx->thread_count = 1;
    ctx->pix_fmt = pix;
    const bool rgb = (av_pix_fmt_desc_get(pix)->flags & AV_PIX_FMT_FLAG_RGB) != 0;
    ctx->color_range = rgb ? AVCOL_RANGE_JPEG : AVCOL_RANGE_MPEG;
    ctx->colorspace = rgb ? AVCOL_SPC_RGB : AVCOL_SPC_BT709;
    // Primaries and transfer tagged BT.709 (the sRGB primaries; players treat the sRGB curve as
    // BT.709 in practice), so every player shows the same colours.
    ctx->color_primaries = AVCOL_PRI_BT709;
    ctx->color_trc = AVCOL_TRC_BT709;
    const AVOutputFormat* muxer = av_guess_format(vf.muxer.c_str(), nullptr, nullptr);
    if (muxer && (muxer->flags & AVFMT_GLOBALHEADER)) ctx->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;

    AVDictionary* copts = nullptr;
    for (const auto& [k, v] : vf.encoderOptions) av_dict_set(&copts, k.c_str(), v.c_str(), 0);
    if (vf.encoder == "libx264" || vf.encoder == "libx264rgb") {
        // The fresh encoder makes the chunk's first frame an IDR picture; no other IDR inside a
        // chunk (a scene cut gives an I picture instead), so two IDR pictures are never
        // consecutive across a join: every chunk's IDR has idr_pic_id 0, which H.264 allows only
        // between non-consecutive IDRs. x264's SEI (its version and options) opens every chunk,
        // the same text in each, since every chunk is encoded with the same settings.
        av_dict_set(&copts, "x264-params", "keyint=infinite", 0);
    } else {
        // VP9: at most one forced key frame in a chunk, at its start.
        ctx->gop_size = chunkFrames;
    }
    int rc = avcodec_open2(ctx, codec, &copts);
    av_dict_free(&copts);
    if (rc < 0) fail("cannot open the " + vf.encoder + " encoder", rc);
}

void ChunkEncoder::Impl::makeConverter(AVPixelFormat pix) {
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

/// The frame as encW × encH pixels of srcChannels: flattened if the format has no alpha, padded
/// if the size had to be made even.
const uint8_t* ChunkEncoder::Impl::prepare(const std::vector<uint8_t>& in) {
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

void ChunkEncoder::Impl::drain(std::vector<ChunkPacket>& out) {
    for (;;) {
        const int rc = avcodec_receive_packet(ctx, pkt);
        if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return;
        if (rc < 0) fail("encoding failed", rc);
        ChunkPacket p;
        p.pts = pkt->pts;
        p.dts = pkt->dts;
        p.duration = pkt->duration;
        p.flags = pkt->flags;
        p.data.assign(reinterpret_cast<const char*>(pkt->data), size_t(pkt->size));
        for (int i = 0; i < pkt->side_data_elems; ++i) {
            const AVPacketSideData& s = pkt->side_data[i];
            p.side.emplace_back(int32_t(s.type), std::string(reinterpret_cast<const char*>(s.data), s.size));
        }
        av_packet_unref(pkt);
        out.push_back(std::move(p));
    }
}

ChunkEncoder::ChunkEncoder(const std::string& path, int width, int height, const Mp4Options& o, int chunkFrames)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.width = width;
    m.height = height;
    m.channels = o.channels;
    std::memcpy(m.over, o.flattenOver, 3);
    av_log_set_level(AV_LOG_ERROR);  // the encoders' per-run statistics are noise on the farm's stderr
    VideoFormat vf;
    try {
        vf = videoFormatOf(path, o);
    } catch (const std::invalid_argument& e) {
        m.fail(e.what(), 0);
    }
    m.srcChannels = vf.alpha ? 4 : 3;
    mp4EncodedSize(width, height, o, m.encW, m.encH, path);
    m.open(vf, o, chunkFrames);
    m.makeConverter(m.ctx->pix_fmt);
}

ChunkEncoder::~ChunkEncoder() = default;

std::vector<ChunkPacket> ChunkEncoder::add(const std::vector<uint8_t>& rgb) {
    Impl& m = *impl_;
    if (m.finished) throw std::runtime_error(m.path + ": a frame after the chunk was finished");
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
    std::vector<ChunkPacket> out;
    m.drain(out);
    return out;
}

std::vector<ChunkPacket> ChunkEncoder::finish() {
    Impl& m = *impl_;
    std::vector<ChunkPacket> out;
    if (m.finished) return out;
    m.finished = true;
    const int rc = avcodec_send_frame(m.ctx, nullptr);
    if (rc < 0 && rc != AVERROR_EOF) m.fail("encoding failed", rc);
    m.drain(out);
    return out;
}

std::string ChunkEncoder::extradata() const {
    const AVCodecContext* c = impl_->ctx;
    return c->extradata ? std::string(reinterpret_cast<const char*>(c->extradata), size_t(c->extradata_size)) : std::string();
}

int ChunkEncoder::frames() const { return int(impl_->nextPts); }

const AVCodecContext* ChunkEncoder::codec() const { return impl_->ctx; }

EncodedChunk encodeChunk(const std::string& path, int width, int height, const Mp4Options& o, int chunkFrames, int index,
                         const std::vector<std::vector<uint8_t>>& frames) {
    const auto t0 = std::chrono::steady_clock::now();
    ChunkEncoder enc(path, width, height, o, chunkFrames);
    EncodedChunk c;
    c.index = index;
    c.frames = int(frames.size());
    for (const auto& f : frames)
        for (ChunkPacket& p : enc.add(f)) c.packets.push_back(std::move(p));
    for (ChunkPacket& p : enc.finish()) c.packets.push_back(std::move(p));
    c.extradata = enc.extradata();
    c.encodeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return c;
}

}  // namespace rf::farm
