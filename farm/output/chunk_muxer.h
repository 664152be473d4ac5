#pragma once
/// Rank 0's side of chunked encoding: the film's container (MP4, WebM, MOV), into which the
/// chunks' packets go in order, their timestamps shifted by the chunk's place in the film, and
/// never re-encoded. Every packet is flushed to the file as it is written (MP4/MOV as a fragment,
/// WebM as a cluster), so the file plays whatever ends the process; at close an MP4/MOV is
/// remuxed to faststart (mp4_remux.h). The muxer is opened in bit-exact mode (no library
/// version tag, no random segment UID), so the file's bytes depend only on its packets.
#include <cstdint>
#include <memory>
#include <string>

#include "farm/output/video_options.h"
#include "farm/output/video_chunk.h"

namespace rf::farm {

class ChunkMuxer {
public:
    /// Opens path and writes the header, with the stream parameters a chunk encoder of these
    /// settings has (one is opened to learn them), flushed at once: from here on the file plays
    /// (no frames yet). Throws std::runtime_error "PATH: what failed".
    ///
    /// keepEarlierUpTo > 0 (a --resume of a film of that many frames): a video already at path,
    /// which holds the film's first frames, stays there until this one holds at least as many
    /// (counted up to keepEarlierUpTo, so the whole film always replaces it). Meanwhile this one
    /// is written to PATH.part and then renamed over it (the writing goes on in the renamed
    /// file), so at every moment path plays at least what it played before. Closed holding
    /// fewer (an interrupted resume), the earlier video stays and PATH.part is removed.
    ChunkMuxer(const std::string& path, int width, int height, const Mp4Options& o, int chunkFrames, int keepEarlierUpTo = 0);
    ~ChunkMuxer();
    ChunkMuxer(const ChunkMuxer&) = delete;
    ChunkMuxer& operator=(const ChunkMuxer&) = delete;

    /// Writes one packet of the chunk whose first frame is frameOffset frames into the film.
    void write(const ChunkPacket& p, int64_t frameOffset);
    /// Throws if a chunk's global header is not the stream's (an encoder built or set up
    /// differently on another rank): its packets would not decode with this stream's header.
    void checkExtradata(const std::string& extradata, int chunkIndex) const;
    /// Trailer, close, and for MP4/MOV the faststart remux. Safe to call twice.
    void close();
    /// Frames the file at path plays now: the packets flushed to it (a frame each), or while an
    /// earlier video is kept (keepEarlier), the earlier one's. Readable from any thread.
    int packetsInFile() const;
    /// The temporary name a kept earlier video makes the new one go by: PATH.part.
    static std::string sidePath(const std::string& path) { return path + ".part"; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace rf::farm
