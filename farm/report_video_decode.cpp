#include "report_video_decode.h"

#include <algorithm>
#include <stdexcept>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libswscale/swscale.h>
}

namespace rf::report {

namespace {

/// Owns the libav objects of one decode, freed in reverse order whatever happens.
struct Decoder {
    AVFormatContext* fmt = nullptr;
    AVCodecContext* ctx = nullptr;
    AVPacket* pkt = nullptr;
    AVFrame* frame = nullptr;
    SwsContext* sws = nullptr;
    ~Decoder() {
        if (sws) sws_freeContext(sws);
        av_frame_free(&frame);
        av_packet_free(&pkt);
        avcodec_free_context(&ctx);
        if (fmt) avformat_close_input(&fmt);
    }
};

std::string avError(int rc) {
    char buf[AV_ERROR_MAX_STRING_SIZE] = {0};
    av_strerror(rc, buf, sizeof buf);
    return buf;
}

}  // namespace

std::vector<std::vector<uint8_t>> decodeVideoRgb8(const std::string& path, int width, int height) {
    auto fail = [&](const std::string& what, int rc) {
        throw std::runtime_error(path + ": " + what + (rc < 0 ? ": " + avError(rc) : std::string()));
    };
    Decoder d;
    int rc = avformat_open_input(&d.fmt, path.c_str(), nullptr, nullptr);
    if (rc < 0) fail("cannot open", rc);
    if ((rc = avformat_find_stream_info(d.fmt, nullptr)) < 0) fail("cannot read stream info", rc);
    const int stream = av_find_best_stream(d.fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
    if (stream < 0) fail("no video stream", stream);
    const AVCodecParameters* par = d.fmt->streams[stream]->codecpar;
    const AVCodec* codec = avcodec_find_decoder(par->codec_id);
    if (!codec) fail("no decoder for its codec", 0);
    d.ctx = avcodec_alloc_context3(codec);
    if (!d.ctx || avcodec_parameters_to_context(d.ctx, par) < 0) fail("cannot set up the decoder", 0);
    d.ctx->thread_count = 1;  // frame order and timing stay simple; decoding is not what is measured
    if ((rc = avcodec_open2(d.ctx, codec, nullptr)) < 0) fail("cannot open the decoder", rc);
    d.pkt = av_packet_alloc();
    d.frame = av_frame_alloc();
    if (!d.pkt || !d.frame) fail("out of memory", 0);

    std::vector<std::vector<uint8_t>> frames;
    auto take = [&]() {
        const AVFrame* f = d.frame;
        if (f->width < width || f->height < height) fail("frame smaller than " + std::to_string(width) + "x" + std::to_string(height), 0);
        d.sws = sws_getCachedContext(d.sws, f->width, f->height, AVPixelFormat(f->format), f->width, f->height,
                                     AV_PIX_FMT_RGB24, SWS_BILINEAR | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, nullptr,
                                     nullptr, nullptr);
        if (!d.sws) fail("cannot convert its pixel format", 0);
        const bool rgbCoded = f->format == AV_PIX_FMT_GBRP || f->format == AV_PIX_FMT_RGB24 || f->format == AV_PIX_FMT_BGR0;
        if (!rgbCoded) {
            // The sink writes BT.709 limited range; ask for exactly the inverse.
            const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
            const int srcFull = f->color_range == AVCOL_RANGE_JPEG ? 1 : 0;
            sws_setColorspaceDetails(d.sws, bt709, srcFull, bt709, 1, 0, 1 << 16, 1 << 16);
        }
        std::vector<uint8_t> rgb(size_t(f->width) * f->height * 3);
        uint8_t* dst[4] = {rgb.data(), nullptr, nullptr, nullptr};
        int dstStride[4] = {3 * f->width, 0, 0, 0};
        sws_scale(d.sws, f->data, f->linesize, 0, f->height, dst, dstStride);
        std::vector<uint8_t> out(size_t(width) * height * 3);
        for (int y = 0; y < height; ++y)
            std::copy_n(&rgb[size_t(y) * f->width * 3], size_t(width) * 3, &out[size_t(y) * width * 3]);
        frames.push_back(std::move(out));
    };
    auto drain = [&]() {
        while (true) {
            const int r = avcodec_receive_frame(d.ctx, d.frame);
            if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
            if (r < 0) fail("decoding failed", r);
            take();
            av_frame_unref(d.frame);
        }
    };
    while ((rc = av_read_frame(d.fmt, d.pkt)) >= 0) {
        if (d.pkt->stream_index == stream) {
            const int s = avcodec_send_packet(d.ctx, d.pkt);
            av_packet_unref(d.pkt);
            if (s < 0) fail("decoding failed", s);
            drain();
        } else {
            av_packet_unref(d.pkt);
        }
    }
    if (rc != AVERROR_EOF) fail("read failed", rc);
    avcodec_send_packet(d.ctx, nullptr);
    drain();
    return frames;
}

}  // namespace rf::report
