#pragma once
/// What the video's options mean before any encoder is open: Mp4Options (rate, quality,
/// codec, chunk length), the format they give for an output name, the encoded size, and the
/// checks made before rendering. Shared by the chunk encoder, the muxer that joins chunks, and
/// the sink over both (mp4_sink.h).
#include <cstddef>
#include <cstdint>
#include <string>

#include "farm/output/video_format.h"

namespace rf::farm {

struct Mp4Options {
    double fps = 30.0;
    int crf = 18;                       ///< the codec's rate factor (-1: the format's default)
    /// The codec's preset ("": the format's default; H.264's is ultrafast, docs/performance.md:
    /// the same PSNR as veryfast at 4x the speed).
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

/// Straight RGBA laid over an sRGB colour, to RGB (in 8-bit sRGB, as a browser composites).
void flattenRgba(const uint8_t* rgba, size_t pixels, const uint8_t over[3], uint8_t* rgb);

}  // namespace rf::farm
