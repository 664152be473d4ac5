#include "farm/output/mp4_sink.h"

#include <stdexcept>

extern "C" {
#include <libavutil/log.h>
}

#include "farm/output/chunk_encoder.h"
#include "farm/output/chunk_muxer.h"

namespace rf::farm {

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

Mp4Sink::Mp4Sink(const std::string& path, int width, int height, const Mp4Options& o, int keepEarlierUpTo)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.width = width;
    m.height = height;
    m.options = o;
    if (o.chunkFrames < kMinChunkFrames) throw std::runtime_error(path + ": chunks of fewer than 2 frames");
    av_log_set_level(AV_LOG_ERROR);  // the encoders' per-run statistics are noise on the farm's stderr
    m.muxer = std::make_unique<ChunkMuxer>(path, width, height, o, o.chunkFrames, keepEarlierUpTo);
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
