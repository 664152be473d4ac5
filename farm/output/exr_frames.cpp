#include "farm/output/exr_frames.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <OpenEXR/ImfArray.h>
#include <OpenEXR/ImfRgbaFile.h>

#include "engine/util/file_source.h"
#include "farm/output/png_sink.h"

namespace rf::farm {

std::string frameExrPath(const std::string& dir, int frame) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.exr", frame);
    return (std::filesystem::path(dir) / name).string();
}

void writeExrRgba(const std::string& path, int width, int height, const float* rgba) {
    const std::string tmp = path + ".part";
    try {
        std::vector<Imf::Rgba> px(size_t(width) * height);
        for (size_t i = 0; i < px.size(); ++i)
            px[i] = Imf::Rgba(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2], rgba[4 * i + 3]);
        Imf::RgbaOutputFile out(tmp.c_str(), width, height, Imf::WRITE_RGBA, 1.f, Imath::V2f(0, 0), 1.f,
                                Imf::INCREASING_Y, Imf::ZIP_COMPRESSION, 1);
        out.setFrameBuffer(px.data(), 1, size_t(width));
        out.writePixels(height);
    } catch (const std::exception& e) {
        std::filesystem::remove(tmp);
        throw std::runtime_error(path + ": cannot write EXR: " + e.what());
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw std::runtime_error(path + ": cannot write: " + ec.message());
}

std::vector<float> readExrRgba(const std::string& path, int& width, int& height) {
    try {
        Imf::RgbaInputFile in(path.c_str(), 1);
        const Imath::Box2i dw = in.dataWindow();
        width = dw.max.x - dw.min.x + 1;
        height = dw.max.y - dw.min.y + 1;
        std::vector<Imf::Rgba> px(size_t(width) * height);
        in.setFrameBuffer(px.data() - dw.min.x - size_t(dw.min.y) * width, 1, size_t(width));
        in.readPixels(dw.min.y, dw.max.y);
        std::vector<float> out(px.size() * 4);
        for (size_t i = 0; i < px.size(); ++i) {
            out[4 * i] = px[i].r;
            out[4 * i + 1] = px[i].g;
            out[4 * i + 2] = px[i].b;
            out[4 * i + 3] = px[i].a;
        }
        return out;
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": cannot read EXR: " + e.what());
    }
}

anim::FrameRanges findKeptExrFrames(const std::string& dir, const anim::FrameRanges& frames, int width, int height) {
    anim::FrameRanges kept;
    for (int f : framesInDir(dir, "exr", frames)) {
        const std::string path = frameExrPath(dir, f);
        if (!notRegularFile(path).empty()) continue;  // a FIFO would block the reader: rendered again
        try {
            Imf::RgbaInputFile in(path.c_str(), 1);
            const Imath::Box2i dw = in.dataWindow();
            if (dw.max.x - dw.min.x + 1 == width && dw.max.y - dw.min.y + 1 == height && in.isComplete()) kept.insert(f);
        } catch (const std::exception&) {
            // Unreadable: rendered again.
        }
    }
    return kept;
}

void ExrSink::write(int frame, const std::vector<uint8_t>& pixels) {
    const size_t n = size_t(width_) * height_;
    if (!layout_.linear || pixels.size() != layout_.bytes(n))
        throw std::runtime_error(frameExrPath(dir_, frame) + ": the frame has no linear plane");
    std::vector<float> rgba(n * 4);
    std::memcpy(rgba.data(), pixels.data() + layout_.linearOffset(n), rgba.size() * sizeof(float));
    writeExrRgba(frameExrPath(dir_, frame), width_, height_, rgba.data());
}

}  // namespace rf::farm
