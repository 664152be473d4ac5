#pragma once
/// The video file through the FFmpeg libraries; the container and codec follow the output's
/// name (video_format.h): H.264 in MP4 (yuv420p, BT.709 tags, TV range, faststart), VP9 in
/// WebM (yuva420p with alpha), ProRes 4444 in MOV (yuva444p10le with alpha). Constant frame rate
/// with timestamps from the frame count. (GIF: gif_sink.h.) The film is encoded in chunks of
/// Mp4Options::chunkFrames frames, each by a fresh encoder (video_chunk.h), whether the frames
/// come here (write) or a chunk comes encoded by the rank that rendered it (writeChunk): the
/// file is the same either way. Every packet reaches the disk as it is encoded (MP4/MOV
/// fragmented, remuxed to faststart at close: mp4_remux.h; a WebM cluster per frame), so the
/// file plays whatever ends the process.
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "farm/output/frame_sink.h"
#include "farm/output/video_chunk.h"
#include "farm/output/video_options.h"

namespace rf::farm {

/// Opens path and writes the header at construction; frames must come in order. A frame is the
/// 8-bit plane of the job's PixelLayout (anything after it, the linear plane, is ignored).
class Mp4Sink : public FrameSink {
public:
    /// keepEarlierUpTo > 0 (a --resume of a film of that many frames): the video already at
    /// path stays until this one holds as many frames (ChunkMuxer).
    Mp4Sink(const std::string& path, int width, int height, const Mp4Options& o, int keepEarlierUpTo = 0);
    ~Mp4Sink() override;
    /// The film's next frame, encoded here into its chunk (a new encoder at each chunk's start).
    void write(int frame, const std::vector<uint8_t>& rgb) override;
    /// The film's next chunk, encoded elsewhere: it must start where the frames so far end (a
    /// chunk boundary). Its packets are copied in, not re-encoded. Throws std::runtime_error
    /// for a chunk out of order or with another stream header.
    void writeChunk(const EncodedChunk& chunk) override;
    /// Closes the chunk in progress (a film that ends, or an interrupted one) and the file.
    void close() override;
    /// Frames taken so far (written or in chunks).
    int framesTaken() const;
    /// Frames flushed to the file (thread-safe: read while another thread writes).
    int framesInOutput() const override;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace rf::farm
