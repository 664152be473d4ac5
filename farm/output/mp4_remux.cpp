#include "farm/output/mp4_remux.h"

#include <cerrno>
#include <cstdio>
#include <stdexcept>

extern "C" {
#include <libavformat/avformat.h>
}

#include "farm/output/video_format.h"

namespace rf::farm {

std::string remuxTempPath(const std::string& path) { return path + ".remux"; }

namespace {

/// Both files of the pass; everything FFmpeg allocated is freed on every way out.
struct Remux {
    std::string path, temp;
    AVFormatContext* in = nullptr;
    AVFormatContext* out = nullptr;
    AVPacket* pkt = nullptr;

    ~Remux() {
        av_packet_free(&pkt);
        avformat_close_input(&in);
        if (out) {
            if (out->pb) avio_closep(&out->pb);
            avformat_free_context(out);
        }
    }

    [[noreturn]] void fail(const std::string& what, int rc) {
        throw std::runtime_error(path + ": " + what + (rc < 0 ? ": " + avErrorText(rc) : std::string()));
    }

    long copied = 0;  ///< packets read back from the fragmented file (and written to temp)

    void open(const std::string& muxer, AVRational rate);
    void copyPackets();
    void finish(long expected);
};

void Remux::open(const std::string& muxer, AVRational rate) {
    int rc = avformat_open_input(&in, path.c_str(), nullptr, nullptr);
    if (rc < 0) fail("cannot read the fragmented video back", rc);
    if (in->nb_streams != 1) fail("expected one video stream", 0);
    const AVStream* src = in->streams[0];
    rc = avformat_alloc_output_context2(&out, nullptr, muxer.c_str(), temp.c_str());
    if (rc < 0 || !out) fail("cannot set up the " + muxer + " muxer", rc);
    out->flags |= AVFMT_FLAG_BITEXACT;  // no library version tag: the bytes follow the packets alone
    AVStream* dst = avformat_new_stream(out, nullptr);
    pkt = av_packet_alloc();
    if (!dst || !pkt) fail("out of memory", 0);
    rc = avcodec_parameters_copy(dst->codecpar, src->codecpar);
    if (rc < 0) fail("cannot copy the stream parameters", rc);
    dst->time_base = src->time_base;
    dst->avg_frame_rate = rate;
    dst->r_frame_rate = rate;
    rc = avio_open(&out->pb, temp.c_str(), AVIO_FLAG_WRITE);
    if (rc < 0) fail("cannot open " + temp + " for writing", rc);
    AVDictionary* opts = nullptr;
    av_dict_set(&opts, "movflags", "+faststart", 0);
    rc = avformat_write_header(out, &opts);
    av_dict_free(&opts);
    if (rc < 0) fail("cannot write the " + muxer + " header", rc);
}

void Remux::copyPackets() {
    for (;;) {
        int rc = av_read_frame(in, pkt);
        if (rc == AVERROR_EOF) return;
        if (rc < 0) fail("cannot read the fragmented video back", rc);
        av_packet_rescale_ts(pkt, in->streams[0]->time_base, out->streams[0]->time_base);
        pkt->stream_index = 0;
        pkt->pos = -1;
        rc = av_interleaved_write_frame(out, pkt);  // takes the packet's data
        if (rc < 0) fail("writing " + temp + " failed", rc);
        ++copied;
    }
}

/// Packets in the video file at `file` (demuxed, not decoded); -1 if it cannot be read.
long countPackets(const std::string& file) {
    AVFormatContext* ctx = nullptr;
    if (avformat_open_input(&ctx, file.c_str(), nullptr, nullptr) < 0) return -1;
    AVPacket* p = av_packet_alloc();
    long n = 0;
    int rc = 0;
    while (p && (rc = av_read_frame(ctx, p)) >= 0) {
        ++n;
        av_packet_unref(p);
    }
    av_packet_free(&p);
    avformat_close_input(&ctx);
    return rc == AVERROR_EOF ? n : -1;
}

void Remux::finish(long expected) {
    // Another process writing the same file (or a file system losing writes) shows as packets
    // missing or extra: the fragmented file stays as it is, and the run fails saying so.
    if (expected >= 0 && copied != expected)
        fail("read back " + std::to_string(copied) + " video packets, but " + std::to_string(expected) +
                 " were written: the file was changed while the film was written (another process writing it?)",
             0);
    int rc = av_write_trailer(out);  // faststart: moves the moov before the media data
    if (rc < 0) fail("cannot finish " + temp, rc);
    rc = avio_closep(&out->pb);
    if (rc < 0) fail("cannot close " + temp, rc);
    avformat_close_input(&in);
    if (expected >= 0) {
        const long there = countPackets(temp);
        if (there != expected)
            fail(temp + " holds " + std::to_string(there) + " video packets after the remux, expected " + std::to_string(expected), 0);
    }
    if (std::rename(temp.c_str(), path.c_str()) != 0) fail("cannot rename " + temp + " over it", AVERROR(errno));
}

}  // namespace

long readablePackets(const std::string& path, long upTo) {
    AVFormatContext* ctx = nullptr;
    if (avformat_open_input(&ctx, path.c_str(), nullptr, nullptr) < 0) return 0;
    long n = 0;
    if (avformat_find_stream_info(ctx, nullptr) >= 0 || ctx->nb_streams > 0) {
        AVPacket* p = av_packet_alloc();
        while (p && n < upTo && av_read_frame(ctx, p) >= 0) {
            const bool whole = !(p->flags & AV_PKT_FLAG_CORRUPT) && p->size > 0;
            if (whole && p->stream_index == 0) ++n;
            av_packet_unref(p);
            if (!whole) break;
        }
        av_packet_free(&p);
    }
    avformat_close_input(&ctx);
    return n;
}

void remuxFaststart(const std::string& path, const std::string& muxer, int fpsNum, int fpsDen, long expectedPackets) {
    Remux r;
    r.path = path;
    r.temp = remuxTempPath(path);
    try {
        r.open(muxer, AVRational{fpsNum, fpsDen});
        r.copyPackets();
        r.finish(expectedPackets);
    } catch (...) {
        std::remove(r.temp.c_str());  // the fragmented file stays: it plays
        throw;
    }
}

}  // namespace rf::farm
