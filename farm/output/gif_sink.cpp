#include "farm/output/gif_sink.h"

#include "farm/output/video_format.h"

#include <dlfcn.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <type_traits>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavfilter/avfilter.h>
#include <libavfilter/buffersink.h>
#include <libavfilter/buffersrc.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
}

namespace rf::farm {

namespace {
struct GifFile;

/// libavfilter, opened the first time a GIF is written rather than linked: it brings about 30
/// more shared libraries (Vulkan, libplacebo, speech and audio filters) whose loading cost every
/// rayfarm process 27 ms at start-up, though only a GIF needs its two palette filters.
struct AvFilterApi {
    decltype(&avfilter_graph_alloc) graphAlloc = nullptr;
    decltype(&avfilter_graph_free) graphFree = nullptr;
    decltype(&avfilter_get_by_name) getByName = nullptr;
    decltype(&avfilter_graph_create_filter) createFilter = nullptr;
    decltype(&avfilter_inout_alloc) inoutAlloc = nullptr;
    decltype(&avfilter_inout_free) inoutFree = nullptr;
    decltype(&avfilter_graph_parse_ptr) parse = nullptr;
    decltype(&avfilter_graph_config) config = nullptr;
    decltype(&av_buffersrc_add_frame) addFrame = nullptr;
    decltype(&av_buffersink_get_frame) getFrame = nullptr;
    std::string error;  ///< why it could not be opened, or ""
};

const AvFilterApi& avfilterApi() {
    static const AvFilterApi api = [] {
        AvFilterApi a;
        // The major version this was compiled against: its ABI.
        const std::string name = "libavfilter.so." + std::to_string(LIBAVFILTER_VERSION_MAJOR);
        void* lib = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL);  // kept open for the process
        if (!lib) {
            a.error = "cannot load " + name + " (GIF output needs FFmpeg's libavfilter): " + dlerror();
            return a;
        }
        bool missing = false;
        auto bind = [&](auto& fn, const char* symbol) {
            fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(dlsym(lib, symbol));
            if (!fn && !missing) a.error = name + " has no " + symbol, missing = true;
        };
        bind(a.graphAlloc, "avfilter_graph_alloc");
        bind(a.graphFree, "avfilter_graph_free");
        bind(a.getByName, "avfilter_get_by_name");
        bind(a.createFilter, "avfilter_graph_create_filter");
        bind(a.inoutAlloc, "avfilter_inout_alloc");
        bind(a.inoutFree, "avfilter_inout_free");
        bind(a.parse, "avfilter_graph_parse_ptr");
        bind(a.config, "avfilter_graph_config");
        bind(a.addFrame, "av_buffersrc_add_frame");
        bind(a.getFrame, "av_buffersink_get_frame");
        return a;
    }();
    return api;
}
}  // namespace

void requireGifFilters(const std::string& path) {
    const AvFilterApi& api = avfilterApi();
    if (!api.error.empty()) throw std::runtime_error(path + ": " + api.error);
}

struct GifSink::Impl {
    std::string path, dither;
    int width = 0, height = 0, channels = 3;
    AVRational rate{30, 1};
    AVFilterGraph* graph = nullptr;
    AVFilterContext* src = nullptr;
    AVFilterContext* sink = nullptr;
    AVFrame* frame = nullptr;
    int64_t nextPts = 0;
    bool closed = false;

    [[noreturn]] void fail(const std::string& what, int rc = 0) {
        throw std::runtime_error(path + ": " + what + (rc < 0 ? ": " + avErrorText(rc) : std::string()));
    }
    void buildGraph();
    void openFile(GifFile& g, const std::string& tmp);
    void drain(GifFile& g);
    void encodeAll();
    ~Impl() {
        av_frame_free(&frame);
        if (graph) avfilterApi().graphFree(&graph);
    }
};

void GifSink::Impl::buildGraph() {
    requireGifFilters(path);
    const AvFilterApi& api = avfilterApi();
    graph = api.graphAlloc();
    if (!graph) fail("out of memory");
    const char* pix = channels == 4 ? "rgba" : "rgb24";
    const std::string srcArgs = "video_size=" + std::to_string(width) + "x" + std::to_string(height) + ":pix_fmt=" + pix +
                                ":time_base=" + std::to_string(rate.den) + "/" + std::to_string(rate.num) + ":pixel_aspect=1/1";
    int rc = api.createFilter(&src, api.getByName("buffer"), "in", srcArgs.c_str(), nullptr, graph);
    if (rc < 0) fail("cannot set up the GIF filters", rc);
    rc = api.createFilter(&sink, api.getByName("buffersink"), "out", nullptr, nullptr, graph);
    if (rc < 0) fail("cannot set up the GIF filters", rc);
    // One palette from every pixel of every frame (stats_mode=full). With alpha, one entry is
    // kept for transparency; without, all 256 go to colours.
    const std::string chain = std::string("split[a][b];[a]palettegen=stats_mode=full:reserve_transparent=") +
                              (channels == 4 ? "1" : "0") + "[p];[b][p]paletteuse=dither=" + dither + ":alpha_threshold=128";
    AVFilterInOut* outputs = api.inoutAlloc();
    AVFilterInOut* inputs = api.inoutAlloc();
    outputs->name = av_strdup("in");
    outputs->filter_ctx = src;
    inputs->name = av_strdup("out");
    inputs->filter_ctx = sink;
    rc = api.parse(graph, chain.c_str(), &inputs, &outputs, nullptr);
    api.inoutFree(&inputs);
    api.inoutFree(&outputs);
    if (rc < 0) fail("cannot set up the GIF filters (palettegen, paletteuse)", rc);
    rc = api.config(graph, nullptr);
    if (rc < 0) fail("cannot set up the GIF filters", rc);
}

namespace {

/// The GIF encoder and muxer of one output file, freed on every path out.
struct GifFile {
    AVFormatContext* fmt = nullptr;
    AVCodecContext* ctx = nullptr;
    AVStream* st = nullptr;
    AVPacket* pkt = av_packet_alloc();
    AVFrame* out = av_frame_alloc();
    ~GifFile() {
        av_frame_free(&out);
        av_packet_free(&pkt);
        avcodec_free_context(&ctx);
        if (fmt) {
            if (fmt->pb) avio_closep(&fmt->pb);
            avformat_free_context(fmt);
        }
    }
};

}  // namespace

/// Opens the GIF encoder and muxer on tmp and writes the header with loop 0 (the NETSCAPE2.0
/// extension: loop for ever).
void GifSink::Impl::openFile(GifFile& g, const std::string& tmp) {
    if (!g.pkt || !g.out) fail("out of memory");
    int rc = avformat_alloc_output_context2(&g.fmt, nullptr, "gif", tmp.c_str());
    if (rc < 0) fail("cannot set up the GIF muxer", rc);
    const AVCodec* codec = avcodec_find_encoder(AV_CODEC_ID_GIF);
    if (!codec) fail("no GIF encoder in this FFmpeg");
    g.st = avformat_new_stream(g.fmt, nullptr);
    g.ctx = avcodec_alloc_context3(codec);
    if (!g.st || !g.ctx) fail("out of memory");
    g.ctx->width = width;
    g.ctx->height = height;
    g.ctx->pix_fmt = AV_PIX_FMT_PAL8;
    g.ctx->time_base = av_inv_q(rate);
    g.ctx->framerate = rate;
    g.ctx->thread_count = 1;
    rc = avcodec_open2(g.ctx, codec, nullptr);
    if (rc < 0) fail("cannot open the GIF encoder", rc);
    avcodec_parameters_from_context(g.st->codecpar, g.ctx);
    g.st->time_base = g.ctx->time_base;
    g.st->avg_frame_rate = rate;
    rc = avio_open(&g.fmt->pb, tmp.c_str(), AVIO_FLAG_WRITE);
    if (rc < 0) fail("cannot open for writing", rc);
    AVDictionary* opts = nullptr;
    av_dict_set(&opts, "loop", "0", 0);
    rc = avformat_write_header(g.fmt, &opts);
    av_dict_free(&opts);
    if (rc < 0) fail("cannot write the GIF header", rc);
}

/// Writes every packet the encoder has ready.
void GifSink::Impl::drain(GifFile& g) {
    for (;;) {
        int r = avcodec_receive_packet(g.ctx, g.pkt);
        if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
        if (r < 0) fail("GIF encoding failed", r);
        av_packet_rescale_ts(g.pkt, g.ctx->time_base, g.st->time_base);
        g.pkt->stream_index = g.st->index;
        r = av_interleaved_write_frame(g.fmt, g.pkt);
        if (r < 0) fail("writing failed", r);
    }
}

/// Pulls the paletted frames out of the graph and writes the file beside it, renamed into place
/// only when complete.
void GifSink::Impl::encodeAll() {
    const std::string tmp = path + ".part";
    try {
        GifFile g;
        openFile(g, tmp);
        for (;;) {
            int rc = avfilterApi().getFrame(sink, g.out);
            if (rc == AVERROR_EOF || rc == AVERROR(EAGAIN)) break;
            if (rc < 0) fail("palette filters failed", rc);
            rc = avcodec_send_frame(g.ctx, g.out);
            av_frame_unref(g.out);
            if (rc < 0) fail("GIF encoding failed", rc);
            drain(g);
        }
        avcodec_send_frame(g.ctx, nullptr);
        drain(g);
        int rc = av_write_trailer(g.fmt);
        if (rc < 0) fail("cannot finish the GIF", rc);
        rc = avio_closep(&g.fmt->pb);
        if (rc < 0) fail("cannot close", rc);
    } catch (...) {
        std::filesystem::remove(tmp);  // after g freed its file handle
        throw;
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) fail("cannot write: " + ec.message());
}

GifSink::GifSink(const std::string& path, int width, int height, int channels, double fps, const std::string& dither)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.width = width;
    m.height = height;
    m.channels = channels;
    m.dither = dither;
    m.rate = av_d2q(fps, 1001000);
    av_log_set_level(AV_LOG_ERROR);
    {
        // Fail now, not after the whole film, if the file cannot be written (the file itself
        // is written at close, through a temporary name next to it).
        const std::string tmp = path + ".part";
        std::ofstream probe(tmp, std::ios::binary);
        if (!probe) m.fail("cannot open for writing");
        probe.close();
        std::filesystem::remove(tmp);
    }
    m.buildGraph();
    m.frame = av_frame_alloc();
    if (!m.frame) m.fail("out of memory");
}

GifSink::~GifSink() = default;

void GifSink::write(int, const std::vector<uint8_t>& pixels) {
    Impl& m = *impl_;
    if (m.closed) throw std::runtime_error(m.path + ": write after close");
    const size_t row = size_t(m.channels) * m.width;
    if (pixels.size() < row * m.height) throw std::runtime_error(m.path + ": frame has the wrong size");
    m.frame->format = m.channels == 4 ? AV_PIX_FMT_RGBA : AV_PIX_FMT_RGB24;
    m.frame->width = m.width;
    m.frame->height = m.height;
    int rc = av_frame_get_buffer(m.frame, 0);
    if (rc < 0) m.fail("out of memory", rc);
    for (int y = 0; y < m.height; ++y) std::memcpy(m.frame->data[0] + size_t(y) * m.frame->linesize[0], pixels.data() + row * y, row);
    m.frame->pts = m.nextPts++;
    rc = avfilterApi().addFrame(m.src, m.frame);  // takes the frame's buffers
    av_frame_unref(m.frame);
    if (rc < 0) m.fail("palette filters failed", rc);
}

void GifSink::close() {
    Impl& m = *impl_;
    if (m.closed) return;
    m.closed = true;
    if (m.nextPts == 0) return;  // nothing rendered: no GIF rather than an empty one
    int rc = avfilterApi().addFrame(m.src, nullptr);
    if (rc < 0) m.fail("palette filters failed", rc);
    m.encodeAll();
}

}  // namespace rf::farm
