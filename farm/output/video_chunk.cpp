#include "farm/output/video_chunk.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "farm/process/byte_fields.h"

namespace rf::farm {

namespace {

constexpr uint32_t kMagic = 0x4b4e4843;  // "CHNK"

}  // namespace

std::string serializeChunk(const EncodedChunk& c) {
    ByteWriter w;
    size_t total = 64 + c.extradata.size();
    for (const ChunkPacket& p : c.packets) total += 64 + p.data.size();
    w.out.reserve(total);
    w.put(kMagic);
    w.put(c.index);
    w.put(c.frames);
    w.put(c.encodeSeconds);
    w.bytes(c.extradata);
    w.put(uint32_t(c.packets.size()));
    for (const ChunkPacket& p : c.packets) {
        w.put(p.pts);
        w.put(p.dts);
        w.put(p.duration);
        w.put(p.flags);
        w.bytes(p.data);
        w.put(uint32_t(p.side.size()));
        for (const auto& [type, bytes] : p.side) {
            w.put(type);
            w.bytes(bytes);
        }
    }
    return std::move(w.out);
}

EncodedChunk parseChunk(const std::string& bytes) {
    ByteReader r{bytes, "chunk"};
    if (r.get<uint32_t>() != kMagic) r.bad("not a chunk");
    EncodedChunk c;
    c.index = r.get<int32_t>();
    c.frames = r.get<int32_t>();
    c.encodeSeconds = r.get<double>();
    c.extradata = r.bytes();
    const uint32_t n = r.count(36);
    c.packets.resize(n);
    for (ChunkPacket& p : c.packets) {
        p.pts = r.get<int64_t>();
        p.dts = r.get<int64_t>();
        p.duration = r.get<int64_t>();
        p.flags = r.get<int32_t>();
        p.data = r.bytes();
        const uint32_t sides = r.count(12);
        p.side.resize(sides);
        for (auto& [type, b] : p.side) {
            type = r.get<int32_t>();
            b = r.bytes();
        }
    }
    r.end();
    if (c.index < 0 || c.frames <= 0) r.bad("bad index or frame count");
    return c;
}

int defaultChunkFrames(double fps, int filmFrames) {
    const long long twoSeconds = std::lround(2.0 * fps);
    const long long eighth = (std::max(filmFrames, 1) + (kDefaultChunksPerFilm - 1LL)) / kDefaultChunksPerFilm;  // no overflow near INT_MAX
    return int(std::max<long long>(kMinChunkFrames, std::min(twoSeconds, eighth)));
}

}  // namespace rf::farm
