#include "farm/output/chunk_muxer.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <sys/stat.h>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
}

#include "farm/output/chunk_encoder.h"
#include "farm/output/mp4_remux.h"

namespace rf::farm {

namespace {
/// The file path names: a symbolic link followed (also one whose file does not exist yet, as
/// before a first render through it), else path itself.
std::string fileNamedBy(const std::string& path) {
    std::error_code ec;
    std::filesystem::path p = path;
    for (int hops = 0; hops < 40 && std::filesystem::is_symlink(p, ec); ++hops) {
        const std::filesystem::path to = std::filesystem::read_symlink(p, ec);
        if (ec) break;
        p = to.is_absolute() ? to : p.parent_path() / to;
    }
    return p.string();
}
}  // namespace

struct ChunkMuxer::Impl {
    std::string path;
    AVFormatContext* fmt = nullptr;
    AVStream* stream = nullptr;
    AVPacket* pkt = nullptr;
    AVRational codecTimeBase{1, 30};
    AVRational rate{30, 1};
    std::string extradata;
    bool fragmented = false;  ///< MP4 and MOV: written fragmented, remuxed to faststart at close
    bool closed = false;
    std::atomic<int> flushed{0};
    std::string writing;        ///< where the file is written: path, or target.part while an earlier video is kept
    std::string target;         ///< the file path names (a symbolic link's target): what the side file replaces
    long earlier = 0;           ///< frames of the earlier video kept at path (keepEarlier)
    std::atomic<bool> inPlace{true};  ///< writing == path (or renamed there)

    /// Renames the side file over the earlier video once it holds as much.
    void swapIfAhead() {
        if (inPlace.load() || flushed.load() < earlier) return;
        if (std::rename(writing.c_str(), target.c_str()) != 0) fail("cannot rename " + writing + " over it", AVERROR(errno));
        writing = target;
        inPlace = true;
    }

    [[noreturn]] void fail(const std::string& what, int rc) const {
        throw std::runtime_error(path + ": " + what + (rc < 0 ? ": " + avErrorText(rc) : std::string()));
    }

    void release() {
        av_packet_free(&pkt);
        if (fmt) {
            if (fmt->pb) avio_closep(&fmt->pb);
            avformat_free_context(fmt);
            fmt = nullptr;
        }
    }
};

ChunkMuxer::ChunkMuxer(const std::string& path, int width, int height, const Mp4Options& o, int chunkFrames, int keepEarlierUpTo)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.writing = path;
    m.target = path;
    // Only a regular file is kept (a FIFO or device is written in place, as always; reading one
    // would block); a symbolic link keeps pointing at it: the side file is written beside the
    // file it names, so the rename replaces that file, in its own file system, not the link.
    struct stat st {};
    const bool regular = ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
    m.target = fileNamedBy(path);
    std::remove(sidePath(m.target).c_str());  // a resume killed before it caught up left it
    if (keepEarlierUpTo > 0 && regular) {
        m.earlier = readablePackets(path, keepEarlierUpTo);  // no further: only "as many" matters
        if (m.earlier > 0) {
            m.writing = sidePath(m.target);
            m.inPlace = false;
        }
    }
    try {
        VideoFormat vf;
        try {
            vf = videoFormatOf(path, o);
        } catch (const std::invalid_argument& e) {
            m.fail(e.what(), 0);
        }
        int rc = avformat_alloc_output_context2(&m.fmt, nullptr, vf.muxer.c_str(), m.writing.c_str());
        if (rc < 0 || !m.fmt) m.fail("cannot set up the " + vf.muxer + " muxer", rc);
        m.fmt->flags |= AVFMT_FLAG_BITEXACT;
        m.stream = avformat_new_stream(m.fmt, nullptr);
        m.pkt = av_packet_alloc();
        if (!m.stream || !m.pkt) m.fail("out of memory", 0);
        {
            // The stream's parameters (and H.264's SPS/PPS) are those of any chunk's encoder.
            const ChunkEncoder probe(path, width, height, o, chunkFrames);
            rc = avcodec_parameters_from_context(m.stream->codecpar, probe.codec());
            if (rc < 0) m.fail("cannot set stream parameters", rc);
            m.codecTimeBase = probe.codec()->time_base;
            m.rate = probe.codec()->framerate;
            m.extradata = probe.extradata();
        }
        m.stream->time_base = m.codecTimeBase;
        m.stream->avg_frame_rate = m.rate;
        m.stream->r_frame_rate = m.rate;
        // WebM signals VP9 alpha (coded as BlockAdditional side data) with AlphaMode on the track.
        if (vf.alpha && vf.container == Container::Webm) av_dict_set(&m.stream->metadata, "alpha_mode", "1", 0);

        rc = avio_open(&m.fmt->pb, m.writing.c_str(), AVIO_FLAG_WRITE);
        if (rc < 0) m.fail("cannot open for writing", rc);
        std::remove(remuxTempPath(m.target).c_str());  // a run killed during its remux left it
        AVDictionary* fopts = nullptr;
        // MP4 and MOV: an empty moov, then one fragment per packet, flushed as written
        // (frag_custom): the file plays up to its last frame whatever ends the process.
        m.fragmented = vf.container == Container::Mp4 || vf.container == Container::Mov;
        if (m.fragmented) av_dict_set(&fopts, "movflags", "+frag_custom+empty_moov+default_base_moof", 0);
        rc = avformat_write_header(m.fmt, &fopts);
        av_dict_free(&fopts);
        if (rc < 0) m.fail("cannot write the " + vf.muxer + " header", rc);
        // The header on disk now: a process killed before the first chunk leaves a file that
        // opens (no frames) instead of one whose moov was still in the buffer.
        avio_flush(m.fmt->pb);
        if (m.fmt->pb->error < 0) m.fail("writing failed", m.fmt->pb->error);
    } catch (...) {
        m.release();
        throw;
    }
}

ChunkMuxer::~ChunkMuxer() {
    try {
        close();
    } catch (...) {
        // close() reported to whoever called it; here the file is abandoned.
    }
    impl_->release();
}

void ChunkMuxer::checkExtradata(const std::string& extradata, int chunkIndex) const {
    if (extradata != impl_->extradata)
        impl_->fail("chunk " + std::to_string(chunkIndex) +
                        " was encoded with another stream header than the film's (a rank with another FFmpeg or x264?)",
                    0);
}

void ChunkMuxer::write(const ChunkPacket& p, int64_t frameOffset) {
    Impl& m = *impl_;
    if (m.closed) throw std::runtime_error(m.path + ": write after close");
    int rc = av_new_packet(m.pkt, int(p.data.size()));
    if (rc < 0) m.fail("out of memory", rc);
    if (!p.data.empty()) std::memcpy(m.pkt->data, p.data.data(), p.data.size());
    for (const auto& [type, bytes] : p.side) {
        uint8_t* dst = av_packet_new_side_data(m.pkt, AVPacketSideDataType(type), bytes.size());
        if (!dst) m.fail("out of memory", 0);
        std::memcpy(dst, bytes.data(), bytes.size());
    }
    m.pkt->pts = p.pts + frameOffset;
    m.pkt->dts = p.dts + frameOffset;
    m.pkt->duration = p.duration;
    m.pkt->flags = p.flags;
    av_packet_rescale_ts(m.pkt, m.codecTimeBase, m.stream->time_base);
    m.pkt->stream_index = m.stream->index;
    rc = av_interleaved_write_frame(m.fmt, m.pkt);  // takes the packet's data
    if (rc < 0) m.fail("writing failed", rc);
    // Ends the fragment (MP4/MOV) or cluster (WebM) holding the packet and pushes it to the
    // file: a process killed after this leaves a file that plays it.
    rc = av_write_frame(m.fmt, nullptr);
    if (rc < 0) m.fail("writing failed", rc);
    avio_flush(m.fmt->pb);
    if (m.fmt->pb->error < 0) m.fail("writing failed", m.fmt->pb->error);
    m.flushed.fetch_add(1, std::memory_order_relaxed);
    m.swapIfAhead();
}

void ChunkMuxer::close() {
    Impl& m = *impl_;
    if (m.closed || !m.fmt) return;
    m.closed = true;
    int rc = av_write_trailer(m.fmt);
    if (rc < 0) m.fail("cannot finish the " + std::string(m.fmt->oformat->name), rc);
    rc = avio_closep(&m.fmt->pb);
    if (rc < 0) m.fail("cannot close", rc);
    if (!m.inPlace) {
        // An interrupted resume that did not catch up: the earlier video plays more.
        std::remove(m.writing.c_str());
        return;
    }
    // Through the file a link names, so the faststart file replaces it and the link stays.
    if (m.fragmented) remuxFaststart(m.target, m.fmt->oformat->name, m.rate.num, m.rate.den, m.flushed.load());
}

int ChunkMuxer::packetsInFile() const {
    if (!impl_->inPlace.load()) return int(impl_->earlier);
    return impl_->flushed.load(std::memory_order_relaxed);
}

}  // namespace rf::farm
