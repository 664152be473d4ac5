#pragma once
/// The frames directory: one PNG per frame (frame_000012.png, the timeline's index), written as
/// each frame completes, plus a manifest naming the settings, so --resume can trust what it finds.
#include <set>
#include <string>
#include <vector>

#include "frame_sink.h"
#include "png_encoder.h"

namespace rf::farm {

/// DIR/frame_NNNNNN.png
std::string framePngPath(const std::string& dir, int frame);

/// Writes each frame to a temporary name and renames it, so a frame file is either whole or
/// absent even if the run is killed mid-write.
class PngSink : public FrameSink {
public:
    PngSink(std::string dir, int width, int height) : dir_(std::move(dir)), width_(width), height_(height) {}
    void write(int frame, const std::vector<uint8_t>& rgb) override;
    void close() override {}

private:
    std::string dir_;
    int width_, height_;
    std::unique_ptr<PngEncoder> encoder_;  ///< made on the sink's thread, at the first frame
};

/// The manifest: what the frames in a directory were rendered from (scene, size, quality).
/// Writes DIR/rayfarm-frames.json.
void writeFramesManifest(const std::string& dir, const std::string& identity);
/// Throws cli::UsageError naming the directory if its manifest is missing or differs.
void checkFramesManifest(const std::string& dir, const std::string& identity);

/// Frames of `frames` already in dir as complete PNGs of width × height (header checked, IEND
/// present).
std::set<int> findKeptFrames(const std::string& dir, const std::vector<int>& frames, int width, int height);

}  // namespace rf::farm
