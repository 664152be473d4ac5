#include "video_chunk.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace rf::farm {

namespace {

// Little helpers for a flat byte layout: every rank runs the same build (mpirun starts one
// executable), so fixed-size fields are copied as they are.
template <class T>
void put(std::string& out, const T& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

void putBytes(std::string& out, const std::string& b) {
    put(out, uint64_t(b.size()));
    out.append(b);
}

struct Reader {
    const std::string& in;
    size_t at = 0;

    template <class T>
    T get() {
        if (in.size() - at < sizeof(T)) throw std::runtime_error("malformed chunk message: truncated");
        T v;
        std::memcpy(&v, in.data() + at, sizeof v);
        at += sizeof v;
        return v;
    }
    std::string bytes() {
        const uint64_t n = get<uint64_t>();
        if (n > in.size() - at) throw std::runtime_error("malformed chunk message: a field runs past its end");
        std::string b = in.substr(at, size_t(n));
        at += size_t(n);
        return b;
    }
    /// A count of items each at least `least` bytes: bounded by what is left, so a corrupt count
    /// cannot make the reader reserve gigabytes.
    uint32_t count(size_t least) {
        const uint32_t n = get<uint32_t>();
        if (uint64_t(n) * least > in.size() - at) throw std::runtime_error("malformed chunk message: bad count");
        return n;
    }
};

constexpr uint32_t kMagic = 0x4b4e4843;  // "CHNK"

}  // namespace

std::string serializeChunk(const EncodedChunk& c) {
    std::string out;
    size_t total = 64 + c.extradata.size();
    for (const ChunkPacket& p : c.packets) total += 64 + p.data.size();
    out.reserve(total);
    put(out, kMagic);
    put(out, c.index);
    put(out, c.frames);
    put(out, c.encodeSeconds);
    putBytes(out, c.extradata);
    put(out, uint32_t(c.packets.size()));
    for (const ChunkPacket& p : c.packets) {
        put(out, p.pts);
        put(out, p.dts);
        put(out, p.duration);
        put(out, p.flags);
        putBytes(out, p.data);
        put(out, uint32_t(p.side.size()));
        for (const auto& [type, bytes] : p.side) {
            put(out, type);
            putBytes(out, bytes);
        }
    }
    return out;
}

EncodedChunk parseChunk(const std::string& bytes) {
    Reader r{bytes};
    if (r.get<uint32_t>() != kMagic) throw std::runtime_error("malformed chunk message: not a chunk");
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
    if (r.at != bytes.size()) throw std::runtime_error("malformed chunk message: bytes after its end");
    if (c.index < 0 || c.frames <= 0) throw std::runtime_error("malformed chunk message: bad index or frame count");
    return c;
}

int defaultChunkFrames(double fps) { return std::max(kMinChunkFrames, int(std::lround(2.0 * fps))); }

}  // namespace rf::farm
