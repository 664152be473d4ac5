#pragma once
/// Pictures of the film for people who look before they play: a contact sheet (a grid of evenly
/// spaced frames, each labelled with its frame number and time) and a poster (one frame at full
/// size, for a web page's <video poster=...>). Both are sinks in output order, so they hold only
/// finished frames, and are written when the film completes or is interrupted.
#include <functional>
#include <string>
#include <vector>

#include "farm/output/frame_sink.h"

namespace rf::farm {

struct ContactSheetPlan {
    std::vector<int> frames;  ///< the frames shown, in order
    int cols = 1, rows = 1;
    int shrink = 1;           ///< thumbnails are width/shrink × height/shrink (box filter)
    int thumbW = 1, thumbH = 1;
    int labelScale = 1;       ///< bitmap font scale
    int pad = 4;              ///< between cells and around the sheet
    int cellH = 1;            ///< thumbnail plus label strip
    int sheetW = 1, sheetH = 1;
};

/// Up to maxFrames frames evenly spaced over first…last (both ends included), 4 to a row;
/// thumbnails about 160 pixels wide (full size for small films).
ContactSheetPlan planContactSheet(int first, int last, int width, int height, int maxFrames = 12);

/// Label of a frame: "#12 0.40s".
std::string frameLabel(int frame, double seconds);

class ContactSheetSink : public FrameSink {
public:
    /// channels: of the 8-bit plane (4: laid over the sheet's grey). timeOf: a frame's time in
    /// seconds (the timeline's).
    ContactSheetSink(std::string path, int width, int height, int channels, int first, int last,
                     std::function<double(int)> timeOf);
    void write(int frame, const std::vector<uint8_t>& pixels) override;
    bool wants(int frame) const override;
    /// Writes the sheet with the frames that came (nothing if none did).
    void close() override;
    const ContactSheetPlan& plan() const { return plan_; }

private:
    std::string path_;
    int width_, height_, channels_;
    std::function<double(int)> timeOf_;
    ContactSheetPlan plan_;
    std::vector<uint8_t> sheet_;
    int placed_ = 0;
    bool closed_ = false;
};

/// Writes one chosen frame full size as PNG (RGBA when the frames have alpha).
class PosterSink : public FrameSink {
public:
    PosterSink(std::string path, int frame, int width, int height, int channels)
        : path_(std::move(path)), frame_(frame), width_(width), height_(height), channels_(channels) {}
    void write(int frame, const std::vector<uint8_t>& pixels) override;
    bool wants(int frame) const override { return frame == frame_; }
    void close() override {}

private:
    std::string path_;
    int frame_, width_, height_, channels_;
};

}  // namespace rf::farm
