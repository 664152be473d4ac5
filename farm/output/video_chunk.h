#pragma once
/// A film is encoded in independent chunks of K frames (K fixed per film, --chunk-frames): each
/// chunk by a fresh encoder, so it starts with a key frame, its rate control and look-ahead see
/// only its own frames, and its bytes are a pure function of its frames. Whoever encodes a chunk
/// (rank 0 in pixel mode and in one process, the rank that rendered it in frame mode), the
/// joined film is the same, byte for byte.
///
/// An EncodedChunk is what travels from the encoding rank to rank 0: the packets, not yet in a
/// container, with their timestamps counted from the chunk's first frame. Rank 0 joins chunks
/// in order by shifting those timestamps (chunk_muxer.h); nothing is re-encoded.
#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rf::farm {

/// One compressed frame as the encoder gave it. Timestamps are in frames (the encoder's time
/// base is one over the frame rate), from the chunk's first frame; dts may be negative when the
/// codec reorders (B-frames).
struct ChunkPacket {
    int64_t pts = 0, dts = 0, duration = 0;
    int32_t flags = 0;   ///< AV_PKT_FLAG_* (key frame)
    std::string data;
    /// AVPacketSideData as (type, bytes): VP9's alpha plane travels this way (BlockAdditional).
    std::vector<std::pair<int32_t, std::string>> side;
};

struct EncodedChunk {
    int32_t index = 0;       ///< the chunk's number in the film, from 0
    int32_t frames = 0;      ///< frames it holds (K, or fewer for the film's last chunk)
    double encodeSeconds = 0.0;  ///< encoder time spent on it (stats only; not part of the video)
    /// The encoder's global header (H.264 SPS/PPS): equal for every chunk of a film, checked
    /// against the container's when the chunk is joined.
    std::string extradata;
    std::vector<ChunkPacket> packets;
};

/// Bytes for the wire (and back). parseChunk throws std::runtime_error on a malformed payload.
std::string serializeChunk(const EncodedChunk& c);
EncodedChunk parseChunk(const std::string& bytes);

/// How a film's frames fall into chunks: chunk c holds frames first + c·K … first + (c+1)·K − 1,
/// the last one fewer. Depends on the film alone (never on ranks), so the cut is the same for
/// every run of it.
struct ChunkPlan {
    int first = 0, last = 0;  ///< the film's frames, inclusive
    int k = 60;               ///< frames a chunk

    int count() const { return (last - first) / k + 1; }
    int chunkOf(int frame) const { return (frame - first) / k; }
    int firstFrame(int chunk) const { return first + chunk * k; }
    int lastFrame(int chunk) const { return std::min(last, first + (chunk + 1) * k - 1); }
    int framesIn(int chunk) const { return lastFrame(chunk) - firstFrame(chunk) + 1; }
};

/// The default chunk length for a film of `filmFrames` frames: about two seconds of film, so a
/// player can seek to any two-second mark and a chunk is long enough that its key frame costs
/// little, but no more than an eighth of the film, so that a short film still has enough
/// chunks to spread over ranks in frame mode (at least 2 frames; see kMinChunkFrames). It
/// depends on the film alone, never on the ranks, so the file is the same for any rank count.
int defaultChunkFrames(double fps, int filmFrames);

/// A film shorter than this many two-second chunks is cut into this many chunks by default.
inline constexpr int kDefaultChunksPerFilm = 8;

/// A chunk of one frame would make consecutive H.264 IDR pictures with the same idr_pic_id
/// (every fresh x264 starts at 0), which the standard forbids; two frames never can.
inline constexpr int kMinChunkFrames = 2;

}  // namespace rf::farm
