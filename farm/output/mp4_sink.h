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

#include "frame_sink.h"
#include "video_chunk.h"
#include "video_format.h"

namespace rf::farm {

struct Mp4Options {
    double fps = 30.0;
    int crf = 18;                       ///< the codec's rate factor (-1: the format's default)
    /// The codec's preset ("": the format's default; H.264's is ultrafast, README: the same PSNR
    /// as veryfast at 4x the speed).
    std::string preset = "ultrafast";
    /// libx264rgb at qp 0: the RGB frames decode back bit for bit (High 4:4:4 Predictive; not
    /// every player plays it: for reference comparisons). VP9: its lossless mode.
    bool lossless = false;
    std::string codec;                  ///< --codec, "" for the container's own
    int channels = 3;                   ///< frames come as RGB (3) or straight RGBA (4)
    /// For RGBA frames in a format without alpha: the sRGB colour they are laid over.
    uint8_t flattenOver[3] = {0, 0, 0};
    /// Frames a chunk (--chunk-frames; fixed for a film, whatever the ranks): each chunk starts
    /// with a key frame and is encoded by an encoder of its own.
    int chunkFrames = 60;
};

/// The format these options give for `path` (throws std::invalid_argument like videoFormatFor).
VideoFormat videoFormatOf(const std::string& path, const Mp4Options& o);

/// Checks options before rendering starts (encoder present, preset known, size encodable); throws
/// std::invalid_argument with a message for the user. Returns a note for the user (e.g. about
/// padding an odd size, or alpha that the format cannot carry), or "". path: the output
/// (its extension picks the format).
std::string checkMp4Options(int width, int height, const Mp4Options& o, const std::string& path = "out.mp4");

/// Encoded size: 4:2:0 and 4:2:2 need even sizes, so an odd width or height gets one more
/// column or row repeating the last one.
void mp4EncodedSize(int width, int height, const Mp4Options& o, int& encW, int& encH, const std::string& path = "out.mp4");

/// Opens path and writes the header at construction; frames must come in order. A frame is the
/// 8-bit plane of the job's PixelLayout (anything after it, the linear plane, is ignored).
class Mp4Sink : public FrameSink {
public:
    Mp4Sink(const std::string& path, int width, int height, const Mp4Options& o);
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

/// Straight RGBA laid over an sRGB colour, to RGB (in 8-bit sRGB, as a browser composites).
void flattenRgba(const uint8_t* rgba, size_t pixels, const uint8_t over[3], uint8_t* rgb);

}  // namespace rf::farm
