#include "png_sink.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli.h"
#include "file_write.h"

namespace rf::farm {

namespace {
const char* kManifest = "rayfarm-frames.json";

uint32_t bigEndian(const unsigned char* p) { return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3]; }

bool isCompletePng(const std::string& path, int width, int height) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return false;
    unsigned char head[24];
    if (!f.read(reinterpret_cast<char*>(head), sizeof head)) return false;
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (std::memcmp(head, sig, 8) != 0 || std::memcmp(head + 12, "IHDR", 4) != 0) return false;
    if (bigEndian(head + 16) != uint32_t(width) || bigEndian(head + 20) != uint32_t(height)) return false;
    unsigned char tail[12];
    f.seekg(-12, std::ios::end);
    if (!f.read(reinterpret_cast<char*>(tail), sizeof tail)) return false;
    return std::memcmp(tail + 4, "IEND", 4) == 0;
}
}  // namespace

std::string framePngPath(const std::string& dir, int frame) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", frame);
    return (std::filesystem::path(dir) / name).string();
}

void PngSink::write(int frame, const std::vector<uint8_t>& rgb) {
    const std::string path = framePngPath(dir_, frame);
    const std::string tmp = path + ".part";
    if (!encoder_) encoder_ = std::make_unique<PngEncoder>(width_, height_);
    const std::string png = encoder_->encode(rgb);
    // No fsync per frame (it would stall the sink at 30 fps); write and close are checked.
    try {
        writeFileChecked(tmp, png, false);
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);  // no .part left behind on a full disk
        throw;
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw std::runtime_error(path + ": cannot write: " + ec.message());
}

void writeFramesManifest(const std::string& dir, const std::string& identity) {
    const std::string path = (std::filesystem::path(dir) / kManifest).string();
    writeFileChecked(path, identity + "\n");
}

void checkFramesManifest(const std::string& dir, const std::string& identity) {
    const std::string path = (std::filesystem::path(dir) / kManifest).string();
    std::ifstream f(path);
    if (!f) throw cli::UsageError(dir + ": nothing to resume (no " + kManifest + " here; run without --resume)");
    std::stringstream ss;
    ss << f.rdbuf();
    std::string have = ss.str();
    while (!have.empty() && (have.back() == '\n' || have.back() == '\r')) have.pop_back();
    if (have != identity)
        throw cli::UsageError(dir + ": its frames were rendered from a different scene or settings (" + have +
                              "; now " + identity + "); use another --frames-dir or run without --resume");
}

std::set<int> findKeptFrames(const std::string& dir, const std::vector<int>& frames, int width, int height) {
    std::set<int> kept;
    for (int f : frames)
        if (isCompletePng(framePngPath(dir, f), width, height)) kept.insert(f);
    return kept;
}

}  // namespace rf::farm
