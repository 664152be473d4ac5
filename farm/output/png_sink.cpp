#include "farm/output/png_sink.h"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "farm/process/usage_error.h"
#include "farm/output/digest.h"
#include "engine/util/file_write.h"
#include "farm/output/output_check.h"

namespace rf::farm {

namespace {
const char* kManifest = "rayfarm-frames.json";
const char* kChecksums = "rayfarm-frames.sha256";  ///< "HEX  frame_NNNNNN.png" lines, as sha256sum writes

uint32_t bigEndian(const unsigned char* p) { return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3]; }

bool isCompletePng(const std::string& png, int width, int height, int channels) {
    if (png.size() < 26 + 12) return false;
    const auto* head = reinterpret_cast<const unsigned char*>(png.data());
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (std::memcmp(head, sig, 8) != 0 || std::memcmp(head + 12, "IHDR", 4) != 0) return false;
    if (bigEndian(head + 16) != uint32_t(width) || bigEndian(head + 20) != uint32_t(height)) return false;
    if (head[24] != 8 || head[25] != (channels == 4 ? 6 : 2)) return false;  // 8-bit RGB (2) or RGBA (6)
    return png.compare(png.size() - 8, 4, "IEND") == 0;
}

/// A kept frame's bytes, if it is a regular file: opened without blocking (a FIFO in its place
/// would otherwise wait for a writer for good) and checked before it is read.
bool readRegularFile(const std::string& path, std::string& bytes) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return false;
    struct stat st {};
    bool ok = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
    bytes.clear();
    if (ok) bytes.reserve(size_t(st.st_size));
    char buf[1 << 16];
    for (ssize_t n; ok && (n = ::read(fd, buf, sizeof buf)) != 0;) {
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) ok = false;
        else bytes.append(buf, size_t(n));
    }
    ::close(fd);
    return ok;
}
}  // namespace

std::string framePngPath(const std::string& dir, int frame) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", frame);
    return (std::filesystem::path(dir) / name).string();
}

void PngSink::write(int frame, const std::vector<uint8_t>& rgb) {
    if (!encoder_) encoder_ = std::make_unique<PngEncoder>(width_, height_, channels_);
    const std::string png = encoder_->encode(rgb);
    writePng(frame, png, sha256Hex(png));
}

void PngSink::writePng(int frame, const std::string& png, const std::string& sha256) {
    const std::string path = framePngPath(dir_, frame);
    const std::string tmp = path + ".part";
    // No fsync per frame (it would stall the sink at 30 fps); write and close are checked,
    // and the resume check verifies each kept frame's digest anyway.
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
    // One append per frame; a frame renamed but not yet listed (killed in between) is simply
    // rendered again by --resume.
    const std::string line = sha256 + "  " + std::filesystem::path(path).filename().string() + "\n";
    const std::string sums = (std::filesystem::path(dir_) / kChecksums).string();
    const int fd = ::open(sums.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0666);
    const bool ok = fd >= 0 && ::write(fd, line.data(), line.size()) == ssize_t(line.size());
    const int err = errno;
    if (fd >= 0 && ::close(fd) != 0 && ok) throw std::runtime_error(sums + ": cannot write: " + std::strerror(errno));
    if (!ok) throw std::runtime_error(sums + ": cannot write: " + std::strerror(err));
}

std::map<std::string, std::string> inputDigests(const FileBundle& bundle) {
    std::map<std::string, std::string> out;
    for (const auto& [path, bytes] : bundle.files) out[path] = sha256Hex(bytes);
    return out;
}

void writeFramesManifest(const std::string& dir, const std::string& identity, const std::map<std::string, std::string>& inputs) {
    const nlohmann::ordered_json j = {{"identity", identity}, {"inputs", inputs}};
    writeFileChecked((std::filesystem::path(dir) / kChecksums).string(), "");
    writeFileChecked((std::filesystem::path(dir) / kManifest).string(), j.dump(1) + "\n");
}

namespace {

/// What differs between the manifest's inputs and today's, in a few words ("" if nothing).
std::string changedInputs(const nlohmann::json& had, const std::map<std::string, std::string>& now) {
    std::vector<std::string> changed;
    for (const auto& [path, sum] : now) {
        if (!had.contains(path)) changed.push_back(path + " is new");
        else if (had[path] != sum) changed.push_back(path + " changed");
    }
    for (auto it = had.begin(); it != had.end(); ++it)
        if (!now.count(it.key())) changed.push_back(it.key() + " is no longer used");
    std::string out;
    for (size_t i = 0; i < changed.size() && i < 3; ++i) out += (i ? ", " : "") + changed[i];
    if (changed.size() > 3) out += " and " + std::to_string(changed.size() - 3) + " more";
    return out;
}

/// The settings that differ between two identities (RenderJob::identity()), each as "NAME was
/// OLD, now NEW", a setting left out at its default as "not given"; "" when either is not an
/// object.
std::string changedSettings(const std::string& had, const std::string& now) {
    const auto a = nlohmann::ordered_json::parse(had, nullptr, false), b = nlohmann::ordered_json::parse(now, nullptr, false);
    if (!a.is_object() || !b.is_object()) return "";
    auto shown = [](const nlohmann::ordered_json& o, const std::string& key) { return o.contains(key) ? o[key].dump() : "not given"; };
    std::vector<std::string> keys;
    for (auto it = b.begin(); it != b.end(); ++it) keys.push_back(it.key());
    for (auto it = a.begin(); it != a.end(); ++it)
        if (!b.contains(it.key())) keys.push_back(it.key());
    std::string out;
    for (const std::string& k : keys) {
        if (a.contains(k) && b.contains(k) && a[k] == b[k]) continue;
        out += (out.empty() ? "" : ", ") + k + " was " + shown(a, k) + ", now " + shown(b, k);
    }
    return out;
}

}  // namespace

void checkFramesManifest(const std::string& dir, const std::string& identity, const std::map<std::string, std::string>& inputs) {
    const std::string path = (std::filesystem::path(dir) / kManifest).string();
    // Read without blocking: a FIFO in their place would wait for a writer for good.
    for (const char* name : {kManifest, kChecksums}) {
        const std::string p = (std::filesystem::path(dir) / name).string();
        if (const std::string what = notRegularFile(p); !what.empty())
            throw UsageError(p + ": is " + what + ", not the frames' " + (name == kManifest ? "manifest" : "checksum list") +
                             "; use another --frames-dir or run without --resume");
    }
    std::ifstream f(path);
    if (!f) throw UsageError(dir + ": nothing to resume (no " + kManifest + " here; run without --resume)");
    std::stringstream ss;
    ss << f.rdbuf();
    const nlohmann::json j = nlohmann::json::parse(ss.str(), nullptr, false);
    if (!j.is_object() || !j.contains("identity") || !j["identity"].is_string() || !j.contains("inputs") || !j["inputs"].is_object())
        throw UsageError(path + ": not a manifest this rayfarm can resume from (it has no input digests); run without --resume");
    const std::string have = j["identity"].get<std::string>();
    if (have != identity) {
        const std::string settings = changedSettings(have, identity);
        throw UsageError(dir + ": cannot resume: its frames were rendered with other settings (" +
                         (settings.empty() ? have + "; now " + identity : settings) +
                         "); resume with the first run's settings, or use --overwrite or another --frames-dir");
    }
    const std::string changed = changedInputs(j["inputs"], inputs);
    if (!changed.empty())
        throw UsageError(dir + ": the scene changed since its frames were rendered (" + changed +
                              "); use another --frames-dir or run without --resume");
}

namespace {

/// frame file name → SHA-256 recorded when it was written (the last line for a name wins).
std::map<std::string, std::string> recordedDigests(const std::string& dir) {
    std::map<std::string, std::string> out;
    std::ifstream f(std::filesystem::path(dir) / kChecksums);
    std::string line;
    while (std::getline(f, line))
        if (line.size() > 66 && line.compare(64, 2, "  ") == 0) out[line.substr(66)] = line.substr(0, 64);
    return out;
}

}  // namespace

int frameOfFileName(const std::string& name, const std::string& extension) {
    const std::string tail = "." + extension;
    if (name.size() <= 6 + tail.size() || name.compare(0, 6, "frame_") != 0 ||
        name.compare(name.size() - tail.size(), tail.size(), tail) != 0)
        return -1;
    const std::string digits = name.substr(6, name.size() - 6 - tail.size());
    if (digits.size() > 10 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
    const long long f = std::stoll(digits);
    if (f > INT32_MAX) return -1;
    char canonical[32];
    std::snprintf(canonical, sizeof canonical, "frame_%06d", int(f));
    return name == canonical + tail ? int(f) : -1;  // only the name this rayfarm writes
}

std::vector<int> framesInDir(const std::string& dir, const std::string& extension, const anim::FrameRanges& frames) {
    // One pass over the directory, not one look-up per frame: a selection may hold 10⁹ frames.
    std::vector<int> found;
    std::error_code ec;
    for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const int f = frameOfFileName(it->path().filename().string(), extension);
        if (f >= 0 && frames.contains(f)) found.push_back(f);
    }
    std::sort(found.begin(), found.end());
    return found;
}

anim::FrameRanges findKeptFrames(const std::string& dir, const anim::FrameRanges& frames, int width, int height,
                                 std::vector<int>* corrupt, int channels) {
    const std::map<std::string, std::string> recorded = recordedDigests(dir);
    anim::FrameRanges kept;
    for (int f : framesInDir(dir, "png", frames)) {
        const std::string path = framePngPath(dir, f);
        const auto it = recorded.find(std::filesystem::path(path).filename().string());
        // A middle bit flipped keeps header and IEND intact: only the digest tells.
        std::string png;
        const bool good = it != recorded.end() && readRegularFile(path, png) && isCompletePng(png, width, height, channels) &&
                          sha256Hex(png) == it->second;
        if (good) kept.insert(f);
        else if (corrupt) corrupt->push_back(f);
    }
    return kept;
}

std::vector<std::string> damagedFrameNotes(const std::string& dir, const std::vector<int>& corrupt, const anim::FrameRanges& frames,
                                           bool exr) {
    std::vector<std::string> notes;
    auto clear = [&](const std::string& path, const std::string& what) {
        std::error_code ec;
        std::string where = "removed";
        if (what == "a directory") {
            // Someone's folder: kept, out of the frame's way (a file cannot be renamed over it).
            std::string aside = path + ".not-a-frame";
            for (int i = 2; std::filesystem::exists(std::filesystem::symlink_status(aside)); ++i)
                aside = path + ".not-a-frame-" + std::to_string(i);
            std::filesystem::rename(path, aside, ec);
            where = "moved to " + aside;
        } else {
            std::filesystem::remove(path, ec);
        }
        if (ec) throw std::runtime_error(path + ": is " + what + " in place of a frame, and cannot be moved: " + ec.message());
        notes.push_back(path + ": is " + what + ", not a frame (" + where + "); rendering it again");
    };
    // Without the checksum list no frame can be checked: one note says so, not one a frame.
    const std::string sums = (std::filesystem::path(dir) / kChecksums).string();
    std::error_code ec;
    const bool haveSums = std::filesystem::exists(std::filesystem::symlink_status(sums, ec));
    const std::map<std::string, std::string> recorded = haveSums ? recordedDigests(dir) : std::map<std::string, std::string>();
    int unchecked = 0;
    for (int f : corrupt) {
        const std::string path = framePngPath(dir, f);
        const std::string what = notRegularFile(path);
        if (!what.empty()) clear(path, what);
        else if (!haveSums) ++unchecked;
        else if (!recorded.count(std::filesystem::path(path).filename().string()))
            notes.push_back(path + ": no checksum recorded for it in " + sums + " (its run stopped before listing it); rendering it again");
        else notes.push_back(path + ": does not match the checksum recorded when it was written; rendering it again");
    }
    if (unchecked)
        notes.push_back(sums + ": missing, so the " + std::to_string(unchecked) + " kept frame" + (unchecked == 1 ? "" : "s") +
                        " cannot be checked; rendering " + (unchecked == 1 ? "it" : "them") + " again");
    if (exr)
        for (int f : framesInDir(dir, "exr", frames)) {
            char name[32];
            std::snprintf(name, sizeof name, "frame_%06d.exr", f);
            const std::string path = (std::filesystem::path(dir) / name).string();
            if (const std::string what = notRegularFile(path); !what.empty()) clear(path, what);
        }
    return notes;
}

namespace {
/// A frame PNG or EXR of any frame number (frame_000012.png, frame_1234567.exr), or with
/// withPart, one a killed run left half-written (frame_000012.png.part).
bool isFrameFile(std::string name, bool withPart) {
    if (withPart && name.size() > 5 && name.compare(name.size() - 5, 5, ".part") == 0) name.resize(name.size() - 5);
    return frameOfFileName(name, "png") >= 0 || frameOfFileName(name, "exr") >= 0;
}
}  // namespace

void prepareFramesDir(const std::string& dir) {
    ensureWritableDir(dir);
    const bool ours = std::filesystem::exists(std::filesystem::path(dir) / "rayfarm-frames.json");
    std::vector<std::filesystem::path> old;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (isFrameFile(e.path().filename().string(), true)) old.push_back(e.path());
    if (!old.empty() && !ours)
        throw UsageError(dir + ": holds frame PNGs that rayfarm did not write; choose another --frames-dir");
    for (const auto& p : old) std::filesystem::remove(p);
}

void appendFramesLog(const std::string& dir, const std::string& lines) {
    const std::string path = (std::filesystem::path(dir) / "rayfarm.log").string();
    const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) return;
    if (::write(fd, lines.data(), lines.size()) != ssize_t(lines.size())) {
        // Best effort (see the header): the frames and the video are what matter.
    }
    ::close(fd);
}

void refuseEarlierFrames(const std::string& dir) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) return;
    size_t n = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec))
        if (isFrameFile(e.path().filename().string(), false)) ++n;
    if (n == 0) return;
    throw UsageError(dir + ": holds " + std::to_string(n) + " frame file" + (n == 1 ? "" : "s") +
                     " of an earlier run; add --resume to render only the frames missing, or --overwrite to render all again");
}


}  // namespace rf::farm
