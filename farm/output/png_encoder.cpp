#include "farm/output/png_encoder.h"

#include <cstdint>
#include <stb_image.h>

#include <cstring>
#include <stdexcept>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/frame.h>
#include <libavutil/opt.h>
}

namespace rf::farm {

struct PngEncoder::Impl {
    int width = 0, height = 0, channels = 3;
    AVCodecContext* ctx = nullptr;
    AVFrame* frame = nullptr;
    AVPacket* pkt = nullptr;
    ~Impl() {
        av_packet_free(&pkt);
        av_frame_free(&frame);
        avcodec_free_context(&ctx);
    }
};

PngEncoder::PngEncoder(int width, int height, int channels) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.width = width;
    m.height = height;
    m.channels = channels;
    const AVPixelFormat pix = channels == 4 ? AV_PIX_FMT_RGBA : AV_PIX_FMT_RGB24;
    const AVCodec* codec = avcodec_find_encoder(AV_CODEC_ID_PNG);
    if (!codec) throw std::runtime_error("this FFmpeg has no PNG encoder");
    m.ctx = avcodec_alloc_context3(codec);
    m.frame = av_frame_alloc();
    m.pkt = av_packet_alloc();
    if (!m.ctx || !m.frame || !m.pkt) throw std::runtime_error("out of memory");
    m.ctx->width = width;
    m.ctx->height = height;
    m.ctx->pix_fmt = pix;
    m.ctx->time_base = {1, 25};
    m.ctx->compression_level = 1;
    m.ctx->thread_count = 1;
    av_opt_set(m.ctx->priv_data, "pred", "none", 0);
    if (avcodec_open2(m.ctx, codec, nullptr) < 0) throw std::runtime_error("cannot open the PNG encoder");
    m.frame->format = pix;
    m.frame->width = width;
    m.frame->height = height;
    if (av_frame_get_buffer(m.frame, 0) < 0) throw std::runtime_error("out of memory");
}

PngEncoder::~PngEncoder() = default;

std::string PngEncoder::encode(const std::vector<uint8_t>& rgb) {
    Impl& m = *impl_;
    const size_t row = size_t(m.channels) * m.width;
    if (rgb.size() < row * m.height) throw std::runtime_error("PNG frame has the wrong size");
    if (av_frame_make_writable(m.frame) < 0) throw std::runtime_error("out of memory");
    for (int y = 0; y < m.height; ++y)
        std::memcpy(m.frame->data[0] + size_t(y) * m.frame->linesize[0], rgb.data() + row * y, row);
    if (avcodec_send_frame(m.ctx, m.frame) < 0) throw std::runtime_error("PNG encoding failed");
    if (avcodec_receive_packet(m.ctx, m.pkt) < 0) throw std::runtime_error("PNG encoding failed");
    std::string out(reinterpret_cast<const char*>(m.pkt->data), size_t(m.pkt->size));
    av_packet_unref(m.pkt);
    return out;
}

std::vector<uint8_t> decodePngFrame(const std::string& png, const std::string& what, int width, int height, int channels) {
    int w = 0, h = 0, comp = 0;
    if (png.size() > size_t(INT32_MAX)) throw std::runtime_error(what + ": over 2 GB");
    unsigned char* data =
        stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()), int(png.size()), &w, &h, &comp, channels);
    if (!data) throw std::runtime_error(what + ": cannot read the PNG (" + stbi_failure_reason() + ")");
    std::vector<uint8_t> out(data, data + size_t(w) * h * channels);
    stbi_image_free(data);
    if (w != width || h != height)
        throw std::runtime_error(what + ": " + std::to_string(w) + "x" + std::to_string(h) + ", expected " + std::to_string(width) +
                                 "x" + std::to_string(height));
    return out;
}

}  // namespace rf::farm
