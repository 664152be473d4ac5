#include "farm/output/video_decode.h"

#include <algorithm>
#include <stdexcept>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libswscale/swscale.h>
}

namespace rf::farm {

namespace {

std::string avError(int rc) {
    char buf[AV_ERROR_MAX_STRING_SIZE] = {0};
    av_strerror(rc, buf, sizeof buf);
    return buf;
}

/// One decode: owns the libav objects, freed in reverse order whatever happens, and collects
/// the frames cropped to width × height.
struct Decoder {
    std::string path;
    int width = 0, height = 0;
    AVFormatContext* fmt = nullptr;
    AVCodecContext* ctx = nullptr;
    AVPacket* pkt = nullptr;
    AVFrame* frame = nullptr;
    SwsContext* sws = nullptr;
    int stream = -1;
    std::vector<std::vector<uint8_t>> frames;

    ~Decoder() {
        if (sws) sws_freeContext(sws);
        av_frame_free(&frame);
        av_packet_free(&pkt);
        avcodec_free_context(&ctx);
        if (fmt) avformat_close_input(&fmt);
    }

    [[noreturn]] void fail(const std::string& what, int rc) const {
        throw std::runtime_error(path + ": " + what + (rc < 0 ? ": " + avError(rc) : std::string()));
    }

    /// The file, its best video stream and a decoder for it.
    void open() {
        int rc = avformat_open_input(&fmt, path.c_str(), nullptr, nullptr);
        if (rc < 0) fail("cannot open", rc);
        if ((rc = avformat_find_stream_info(fmt, nullptr)) < 0) fail("cannot read stream info", rc);
        stream = av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
        if (stream < 0) fail("no video stream", stream);
        const AVCodecParameters* par = fmt->streams[stream]->codecpar;
        const AVCodec* codec = avcodec_find_decoder(par->codec_id);
        if (!codec) fail("no decoder for its codec", 0);
        ctx = avcodec_alloc_context3(codec);
        if (!ctx || avcodec_parameters_to_context(ctx, par) < 0) fail("cannot set up the decoder", 0);
        ctx->thread_count = 1;  // frame order and timing stay simple; decoding is not what is measured
        if ((rc = avcodec_open2(ctx, codec, nullptr)) < 0) fail("cannot open the decoder", rc);
        pkt = av_packet_alloc();
        frame = av_frame_alloc();
        if (!pkt || !frame) fail("out of memory", 0);
    }

    /// The decoded frame to RGB, cropped to width × height.
    void take() {
        const AVFrame* f = frame;
        if (f->width < width || f->height < height) fail("frame smaller than " + std::to_string(width) + "x" + std::to_string(height), 0);
        sws = sws_getCachedContext(sws, f->width, f->height, AVPixelFormat(f->format), f->width, f->height,
                                   AV_PIX_FMT_RGB24, SWS_BILINEAR | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, nullptr,
                                   nullptr, nullptr);
        if (!sws) fail("cannot convert its pixel format", 0);
        const bool rgbCoded = f->format == AV_PIX_FMT_GBRP || f->format == AV_PIX_FMT_RGB24 || f->format == AV_PIX_FMT_BGR0;
        if (!rgbCoded) {
            // The sink writes BT.709 limited range; ask for exactly the inverse.
            const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
            const int srcFull = f->color_range == AVCOL_RANGE_JPEG ? 1 : 0;
            sws_setColorspaceDetails(sws, bt709, srcFull, bt709, 1, 0, 1 << 16, 1 << 16);
        }
        std::vector<uint8_t> rgb(size_t(f->width) * f->height * 3);
        uint8_t* dst[4] = {rgb.data(), nullptr, nullptr, nullptr};
        int dstStride[4] = {3 * f->width, 0, 0, 0};
        sws_scale(sws, f->data, f->linesize, 0, f->height, dst, dstStride);
        std::vector<uint8_t> out(size_t(width) * height * 3);
        for (int y = 0; y < height; ++y)
            std::copy_n(&rgb[size_t(y) * f->width * 3], size_t(width) * 3, &out[size_t(y) * width * 3]);
        frames.push_back(std::move(out));
    }

    /// Every frame the decoder has ready.
    void drain() {
        while (true) {
            const int r = avcodec_receive_frame(ctx, frame);
            if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
            if (r < 0) fail("decoding failed", r);
            take();
            av_frame_unref(frame);
        }
    }
};

}  // namespace

std::vector<std::vector<uint8_t>> decodeVideoRgb8(const std::string& path, int width, int height) {
    Decoder d;
    d.path = path;
    d.width = width;
    d.height = height;
    d.open();
    int rc = 0;
    while ((rc = av_read_frame(d.fmt, d.pkt)) >= 0) {
        if (d.pkt->stream_index == d.stream) {
            const int s = avcodec_send_packet(d.ctx, d.pkt);
            av_packet_unref(d.pkt);
            if (s < 0) d.fail("decoding failed", s);
            d.drain();
        } else {
            av_packet_unref(d.pkt);
        }
    }
    if (rc != AVERROR_EOF) d.fail("read failed", rc);
    avcodec_send_packet(d.ctx, nullptr);
    d.drain();
    return std::move(d.frames);
}

}  // namespace rf::farm
