#include "farm/cluster/messages.h"

#include "farm/process/byte_fields.h"

#include <atomic>
#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace rf::farm {

namespace {

// Payloads are plain structs copied byte for byte: every rank runs the same build of rayfarm
// (mpirun starts one executable), so layout and endianness agree.
// The ray counters travel as the whole RayStats, so a counter added to it arrives too.
struct ResultHeader {
    int32_t frame, x0, y0, x1, y1;
    int32_t layout = 0;  ///< channels | linear << 8
    int32_t chunk, frames;
    int32_t assembler, unused = 0;
    uint64_t epoch;
    double busySeconds;
    RayStats rays;
};
static_assert(std::is_trivially_copyable_v<RayStats>);
static_assert(std::is_trivially_copyable_v<ResultHeader>);
static_assert(std::is_trivially_copyable_v<Heartbeat>);

template <class T>
std::string bytesOf(const T& v) {
    return std::string(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <class T>
T fromBytes(const std::string& b, const char* what) {
    if (b.size() != sizeof(T)) throw std::runtime_error(std::string("malformed ") + what + " message");
    T v;
    std::memcpy(&v, b.data(), sizeof(T));
    return v;
}

struct WireRect {
    int32_t frame, x0, y0, x1, y1;
    int32_t chunk, frames;
    int32_t assembler;  ///< also keeps the struct free of padding: every byte is a field's
    uint64_t epoch;
};
// No padding: a decoded item encodes back to the very bytes it came from (the fuzz harness
// checks it), which unspecified padding bytes would break.
static_assert(std::has_unique_object_representations_v<WireRect>);

WireRect wireOf(const WorkItem& w) {
    return {w.frame, w.rect.x0, w.rect.y0, w.rect.x1, w.rect.y1, w.chunk, w.frames, w.assembler, w.epoch};
}
WorkItem itemOf(const WireRect& r) {
    if (r.assembler < -1) throw std::runtime_error("malformed work message");
    return {r.frame, {r.x0, r.y0, r.x1, r.y1}, r.epoch, r.chunk, r.frames, r.assembler};
}

ResultHeader headerOf(const TileResult& r) {
    return {r.item.frame, r.item.rect.x0, r.item.rect.y0, r.item.rect.x1, r.item.rect.y1,
            r.layout.channels | int32_t(r.layout.linear) << 8, r.item.chunk, r.item.frames, r.item.assembler, 0,
            r.item.epoch, r.busySeconds, r.rays};
}

/// The result a header describes, its pixels not yet read; throws on a malformed one.
TileResult resultOf(const ResultHeader& h) {
    TileResult r;
    r.item = {h.frame, {h.x0, h.y0, h.x1, h.y1}, h.epoch, h.chunk, h.frames, h.assembler};
    r.layout.channels = h.layout & 0xff;
    r.layout.linear = (h.layout >> 8) & 1;
    if ((r.layout.channels != 3 && r.layout.channels != 4) || (h.layout >> 9) != 0 || h.assembler < -1 || h.unused != 0)
        throw std::runtime_error("malformed result message: unknown pixel layout");
    // In 64 bits: a corrupt rectangle must not overflow int (TileRect::pixels) on the way.
    const int64_t w = int64_t(h.x1) - h.x0, hgt = int64_t(h.y1) - h.y0;
    if (w <= 0 || hgt <= 0 || w > (1 << 20) || hgt > (1 << 20))
        throw std::runtime_error("malformed result message: empty or huge rectangle");
    r.busySeconds = h.busySeconds;
    r.rays = h.rays;
    return r;
}

}  // namespace

std::string encodeWorkItem(const WorkItem& w) { return bytesOf(wireOf(w)); }

WorkItem decodeWorkItem(const std::string& bytes) { return itemOf(fromBytes<WireRect>(bytes, "work")); }

std::string encodeChunkOrder(const ChunkOrder& o) {
    ByteWriter w;
    w.put(wireOf(o.item));
    w.put(o.sendPngs);
    w.put(uint32_t(o.kept.size()));
    for (const auto& [frame, png] : o.kept) {
        w.put(frame);
        w.bytes(png);
    }
    w.put(uint32_t(o.rawWanted.size()));
    for (int32_t f : o.rawWanted) w.put(f);
    return std::move(w.out);
}

ChunkOrder decodeChunkOrder(const std::string& bytes) {
    ByteReader r{bytes, "chunk order"};
    ChunkOrder o;
    o.item = itemOf(r.get<WireRect>());
    o.sendPngs = r.get<int32_t>();
    o.kept.resize(r.count(12));
    for (auto& [frame, png] : o.kept) {
        frame = r.get<int32_t>();
        png = r.bytes();
    }
    o.rawWanted.resize(r.count(4));
    for (int32_t& f : o.rawWanted) f = r.get<int32_t>();
    r.end();
    if (o.item.chunk < 0 || o.item.frames <= 0) r.bad("not a chunk");
    return o;
}

std::string encodeChunkFrame(const ChunkFrame& f) {
    ByteWriter w;
    w.put(wireOf(f.item));
    w.put(f.frame);
    w.put(f.wasKept);
    w.bytes(f.png);
    w.bytes(f.pngSha256);
    w.bytes(f.pixels.data(), f.pixels.size());
    return std::move(w.out);
}

ChunkFrame decodeChunkFrame(const std::string& bytes) {
    ByteReader r{bytes, "chunk frame"};
    ChunkFrame f;
    f.item = itemOf(r.get<WireRect>());
    f.frame = r.get<int32_t>();
    f.wasKept = r.get<int32_t>();
    f.png = r.bytes();
    f.pngSha256 = r.bytes();
    const std::string px = r.bytes();
    f.pixels.assign(px.begin(), px.end());
    r.end();
    return f;
}

std::string encodeChunkDone(const WorkItem& item, const std::string& chunkBytes) {
    ByteWriter w;
    w.put(wireOf(item));
    w.out.append(chunkBytes);
    return std::move(w.out);
}

WorkItem decodeChunkDone(const std::string& bytes, std::string& chunkBytes) {
    ByteReader r{bytes, "chunk"};
    const WorkItem item = itemOf(r.get<WireRect>());
    chunkBytes = bytes.substr(r.at);
    return item;
}

std::string encodeTileResult(const TileResult& r) {
    std::string out = bytesOf(headerOf(r));
    out.append(reinterpret_cast<const char*>(r.rgb.data()), r.rgb.size());
    return out;
}

TileResult decodeTileResult(const std::string& bytes) {
    if (bytes.size() < sizeof(ResultHeader)) throw std::runtime_error("malformed result message");
    ResultHeader h;
    std::memcpy(&h, bytes.data(), sizeof h);
    TileResult r = resultOf(h);
    // In 64 bits: sides up to 2^20 overflow int (TileRect::pixels) before the size check.
    const int64_t pixels = int64_t(r.item.rect.width()) * int64_t(r.item.rect.height());
    if (uint64_t(bytes.size() - sizeof h) != uint64_t(r.layout.bytes(size_t(pixels))))
        throw std::runtime_error("malformed result message: pixel count does not match its rectangle");
    r.rgb.assign(bytes.begin() + sizeof h, bytes.end());
    return r;
}

std::string encodeTileDone(const TileResult& r) { return bytesOf(headerOf(r)); }

TileResult decodeTileDone(const std::string& bytes) { return resultOf(fromBytes<ResultHeader>(bytes, "tile done")); }

uint64_t newEpoch() {
    static std::atomic<uint64_t> next{1};
    return next++;
}

std::string encodeViewSpec(const ViewSpec& v) { return bytesOf(v); }

ViewSpec decodeViewSpec(const std::string& bytes) { return fromBytes<ViewSpec>(bytes, "view"); }

std::string encodeHeartbeat(const Heartbeat& h) { return bytesOf(h); }

Heartbeat decodeHeartbeat(const std::string& bytes) { return fromBytes<Heartbeat>(bytes, "heartbeat"); }

}  // namespace rf::farm
