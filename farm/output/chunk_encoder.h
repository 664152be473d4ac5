#pragma once
/// The encoder of one chunk (video_chunk.h): a fresh FFmpeg encoder for the chunk's frames,
/// opened with the film's settings, whose packets come back as ChunkPackets with timestamps
/// counted from the chunk's first frame. Constructed for each chunk and never reused, so no
/// rate control, look-ahead or reference crosses a chunk's edge, and one thread, so the bytes do
/// not depend on the machine (x264's and libvpx's output changes with their thread count).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "farm/output/video_options.h"
#include "farm/output/video_chunk.h"

struct AVCodecContext;  // libavcodec's, for the muxer beside this file (chunk_muxer.cpp)

namespace rf::farm {

class ChunkEncoder {
public:
    /// path: the output (its extension picks the format); width × height: the frames' size
    /// (an odd size is padded as mp4EncodedSize says); chunkFrames: the film's K (the key-frame
    /// distance is set from it so that a chunk holds one key frame, at its start). Throws
    /// std::runtime_error "PATH: what failed" when the encoder cannot be opened.
    ChunkEncoder(const std::string& path, int width, int height, const Mp4Options& o, int chunkFrames);
    ~ChunkEncoder();
    ChunkEncoder(const ChunkEncoder&) = delete;
    ChunkEncoder& operator=(const ChunkEncoder&) = delete;

    /// Encodes the chunk's next frame (the 8-bit plane of the job's PixelLayout; anything after
    /// it is ignored). Returns the packets the encoder gave out meanwhile, often none yet.
    std::vector<ChunkPacket> add(const std::vector<uint8_t>& frame);
    /// Drains the encoder: the chunk's remaining packets. Nothing may be added after it.
    std::vector<ChunkPacket> finish();
    /// The global header (H.264 SPS/PPS as the container stores it; empty for VP9 and ProRes).
    std::string extradata() const;
    /// Frames added so far.
    int frames() const;
    /// The opened codec, for the muxer's stream parameters (chunk_muxer.cpp).
    const AVCodecContext* codec() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Encodes a whole chunk at once: frames in order, index its number in the film.
EncodedChunk encodeChunk(const std::string& path, int width, int height, const Mp4Options& o, int chunkFrames, int index,
                         const std::vector<std::vector<uint8_t>>& frames);

}  // namespace rf::farm
