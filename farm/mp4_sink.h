#pragma once
/// H.264 in MP4 through the FFmpeg libraries: libx264, yuv420p tagged BT.709 with TV (limited)
/// range, constant frame rate with timestamps from the frame count, faststart (moov first).
#include <memory>
#include <stdexcept>
#include <string>

#include "frame_sink.h"

namespace rf::farm {

struct Mp4Options {
    double fps = 30.0;
    int crf = 18;                       ///< x264 constant rate factor, 0–51
    std::string preset = "ultrafast";   ///< x264 preset (README: same PSNR as veryfast, 4x the speed)
    /// libx264rgb at qp 0: the RGB frames decode back bit for bit (High 4:4:4 Predictive; not
    /// every player plays it: for reference comparisons).
    bool lossless = false;
};

/// Checks options before rendering starts (x264 present, preset known, size encodable); throws
/// std::invalid_argument with a message for the user. Returns a note for the user (e.g. about padding an odd size), or "".
std::string checkMp4Options(int width, int height, const Mp4Options& o);

/// Encoded size: yuv420p needs even sizes, so an odd width or height gets one more column or
/// row repeating the last one. Lossless RGB keeps the size.
void mp4EncodedSize(int width, int height, const Mp4Options& o, int& encW, int& encH);

/// Opens path and writes the header at construction; frames must come in order.
class Mp4Sink : public FrameSink {
public:
    Mp4Sink(const std::string& path, int width, int height, const Mp4Options& o);
    ~Mp4Sink() override;
    void write(int frame, const std::vector<uint8_t>& rgb) override;
    void close() override;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace rf::farm
