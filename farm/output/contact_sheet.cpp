#include "farm/output/contact_sheet.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "farm/output/bitmap_font.h"
#include "engine/util/image.h"
#include "farm/output/video_options.h"

namespace rf::farm {

namespace {
const uint8_t kSheetGrey[3] = {48, 48, 48};
const uint8_t kLabelColour[3] = {235, 235, 235};

/// Writes a PNG through a temporary name, so the file is whole or absent.
void writePngWhole(const std::string& path, int w, int h, const std::vector<uint8_t>& px, int channels) {
    const std::string tmp = path + ".part.png";
    writePng(tmp, w, h, px, channels);
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw std::runtime_error(path + ": cannot write: " + ec.message());
}
}  // namespace

ContactSheetPlan planContactSheet(int first, int last, int width, int height, int maxFrames) {
    ContactSheetPlan p;
    const int count = last - first + 1;
    const int n = std::max(1, std::min(maxFrames, count));
    for (int i = 0; i < n; ++i)
        p.frames.push_back(n == 1 ? first : first + int(std::lround(double(i) * (count - 1) / (n - 1))));
    p.cols = std::min(4, n);
    p.rows = (n + p.cols - 1) / p.cols;
    p.shrink = std::max(1, int(std::ceil(width / 160.0)));
    p.thumbW = std::max(1, width / p.shrink);
    p.thumbH = std::max(1, height / p.shrink);
    p.labelScale = std::max(1, p.thumbW / 80);
    p.pad = 2 * p.labelScale + 2;
    p.cellH = p.thumbH + p.pad + kGlyphH * p.labelScale;
    p.sheetW = p.pad + p.cols * (p.thumbW + p.pad);
    p.sheetH = p.pad + p.rows * (p.cellH + p.pad);
    return p;
}

std::string frameLabel(int frame, double seconds) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "#%d %.2fs", frame, seconds);
    return buf;
}

ContactSheetSink::ContactSheetSink(std::string path, int width, int height, int channels, int first, int last,
                                   std::function<double(int)> timeOf)
    : path_(std::move(path)), width_(width), height_(height), channels_(channels), timeOf_(std::move(timeOf)),
      plan_(planContactSheet(first, last, width, height)) {
    sheet_.resize(size_t(plan_.sheetW) * plan_.sheetH * 3);
    for (size_t i = 0; i < sheet_.size(); ++i) sheet_[i] = kSheetGrey[i % 3];
}

bool ContactSheetSink::wants(int frame) const {
    return std::find(plan_.frames.begin(), plan_.frames.end(), frame) != plan_.frames.end();
}

void ContactSheetSink::write(int frame, const std::vector<uint8_t>& pixels) {
    const auto it = std::find(plan_.frames.begin(), plan_.frames.end(), frame);
    if (it == plan_.frames.end()) return;
    const size_t n = size_t(width_) * height_;
    if (pixels.size() < n * channels_) throw std::runtime_error(path_ + ": frame has the wrong size");
    std::vector<uint8_t> rgb(n * 3);
    if (channels_ == 4) flattenRgba(pixels.data(), n, kSheetGrey, rgb.data());
    else std::copy(pixels.begin(), pixels.begin() + long(n * 3), rgb.begin());

    const int index = int(it - plan_.frames.begin());
    const int cx = plan_.pad + (index % plan_.cols) * (plan_.thumbW + plan_.pad);
    const int cy = plan_.pad + (index / plan_.cols) * (plan_.cellH + plan_.pad);
    const int s = plan_.shrink;
    // Box filter: each thumbnail pixel is the mean of an s × s block (sRGB values, as browsers
    // scale them).
    for (int y = 0; y < plan_.thumbH; ++y)
        for (int x = 0; x < plan_.thumbW; ++x)
            for (int c = 0; c < 3; ++c) {
                unsigned sum = 0;
                for (int by = 0; by < s; ++by)
                    for (int bx = 0; bx < s; ++bx) sum += rgb[3 * (size_t(y * s + by) * width_ + size_t(x * s + bx)) + c];
                sheet_[3 * (size_t(cy + y) * plan_.sheetW + size_t(cx + x)) + c] = uint8_t((sum + s * s / 2) / (s * s));
            }
    drawText(sheet_, plan_.sheetW, plan_.sheetH, cx, cy + plan_.thumbH + plan_.pad / 2,
             frameLabel(frame, timeOf_ ? timeOf_(frame) : 0.0), plan_.labelScale, kLabelColour);
    ++placed_;
}

void ContactSheetSink::close() {
    if (closed_) return;
    closed_ = true;
    if (placed_ == 0) return;
    writePngWhole(path_, plan_.sheetW, plan_.sheetH, sheet_, 3);
}

void PosterSink::write(int frame, const std::vector<uint8_t>& pixels) {
    if (frame != frame_) return;
    if (pixels.size() < size_t(width_) * height_ * channels_) throw std::runtime_error(path_ + ": frame has the wrong size");
    writePngWhole(path_, width_, height_, std::vector<uint8_t>(pixels.begin(), pixels.begin() + long(size_t(width_) * height_ * channels_)), channels_);
}

}  // namespace rf::farm
