#include "farm/output/video_format.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

extern "C" {
#include <libavcodec/avcodec.h>
}

namespace rf::farm {

namespace {

const char* kX264Presets[] = {"ultrafast", "superfast", "veryfast", "faster", "fast",
                              "medium",    "slow",      "slower",   "veryslow", "placebo"};

using std::invalid_argument;

int presetIndex(const std::string& preset) {
    for (int i = 0; i < 10; ++i)
        if (preset == kX264Presets[i]) return i;
    return -1;
}

void requireEncoder(const std::string& name) {
    if (!avcodec_find_encoder_by_name(name.c_str()))
        throw invalid_argument("this FFmpeg has no " + name + " encoder (Debian's libavcodec has it)");
}

void refuseCodec(const VideoRequest& r, const char* container, std::initializer_list<const char*> accepted) {
    if (r.codec.empty()) return;
    for (const char* a : accepted)
        if (r.codec == a) return;
    throw invalid_argument("--codec " + r.codec + ": " + container + " files are written as " + *accepted.begin() +
                           " (the codec follows the output's extension)");
}

VideoFormat h264(const VideoRequest& r) {
    refuseCodec(r, ".mp4", {"h264", "libx264"});
    VideoFormat f;
    f.container = Container::Mp4;
    f.muxer = "mp4";
    const std::string preset = r.preset.empty() ? "ultrafast" : r.preset;
    if (presetIndex(preset) < 0) throw invalid_argument("--preset: expected an x264 preset (ultrafast … medium … placebo), got \"" + preset + "\"");
    if (r.crf > 51) throw invalid_argument("--crf: expected 0–51 for H.264, got " + std::to_string(r.crf));
    f.encoder = r.lossless ? "libx264rgb" : "libx264";
    f.pixFmt = r.lossless ? "rgb24" : "yuv420p";
    f.evenSize = !r.lossless;
    const int crf = r.crf >= 0 ? r.crf : 18;
    f.encoderOptions = {{"preset", preset}, r.lossless ? std::pair<std::string, std::string>{"qp", "0"} : std::pair<std::string, std::string>{"crf", std::to_string(crf)}};
    f.describe = r.lossless ? "libx264rgb qp 0" : "libx264 crf " + std::to_string(crf) + " " + preset;
    return f;
}

VideoFormat vp9(const VideoRequest& r) {
    refuseCodec(r, ".webm", {"vp9", "libvpx-vp9"});
    VideoFormat f;
    f.container = Container::Webm;
    f.muxer = "webm";
    f.encoder = "libvpx-vp9";
    f.alpha = r.alpha;
    f.pixFmt = r.alpha ? "yuva420p" : "yuv420p";
    const std::string preset = r.preset.empty() ? "veryfast" : r.preset;
    const int p = presetIndex(preset);
    if (p < 0) throw invalid_argument("--preset: expected ultrafast … placebo (VP9 cpu-used 8 … 0), got \"" + preset + "\"");
    if (r.crf > 63) throw invalid_argument("--crf: expected 0–63 for VP9, got " + std::to_string(r.crf));
    const int cpuUsed = std::max(0, 8 - p);  // ultrafast 8 … veryslow and placebo 0
    const int crf = r.crf >= 0 ? r.crf : 32;
    // Constant quality needs a zero bitrate; one thread keeps the bitstream the same at any
    // rank count (as for x264). No look-ahead (lag 0): every frame is in the file as soon as it
    // is encoded, so closing after Ctrl-C is quick enough to finish before mpirun's SIGKILL.
    f.encoderOptions = {{"cpu-used", std::to_string(cpuUsed)}, {"b", "0"}, {"row-mt", "0"}, {"deadline", "good"},
                        {"lag-in-frames", "0"}};
    if (r.lossless) f.encoderOptions.push_back({"lossless", "1"});
    else f.encoderOptions.push_back({"crf", std::to_string(crf)});
    f.describe = std::string("libvpx-vp9 ") + (r.lossless ? "lossless" : "crf " + std::to_string(crf)) + " cpu-used " +
                 std::to_string(cpuUsed) + ", " + f.pixFmt;
    return f;
}

VideoFormat prores(const VideoRequest& r) {
    refuseCodec(r, ".mov", {"prores", "prores_ks"});
    if (r.crf >= 0) throw invalid_argument("--crf: ProRes (.mov) has no rate factor; choose the profile with --preset 4444|4444xq|hq|standard|lt|proxy");
    if (r.lossless) throw invalid_argument("--lossless: ProRes (.mov) is never lossless; use .mp4 --lossless or PNG/EXR frames");
    const std::string preset = r.preset.empty() ? "4444" : r.preset;
    static const std::pair<const char*, const char*> profiles[] = {
        {"proxy", "0"}, {"lt", "1"}, {"standard", "2"}, {"hq", "3"}, {"4444", "4"}, {"4444xq", "5"}};
    const auto it = std::find_if(std::begin(profiles), std::end(profiles), [&](const auto& q) { return preset == q.first; });
    if (it == std::end(profiles)) throw invalid_argument("--preset: expected a ProRes profile (4444, 4444xq, hq, standard, lt, proxy), got \"" + preset + "\"");
    const bool is444 = preset == "4444" || preset == "4444xq";
    if (r.alpha && !is444) throw invalid_argument("--preset " + preset + ": ProRes carries alpha only in 4444 and 4444xq");
    VideoFormat f;
    f.container = Container::Mov;
    f.muxer = "mov";
    f.encoder = "prores_ks";
    f.alpha = r.alpha;
    f.pixFmt = is444 ? (r.alpha ? "yuva444p10le" : "yuv444p10le") : "yuv422p10le";
    f.evenSize = !is444;
    f.encoderOptions = {{"profile", it->second}, {"vendor", "apl0"}};
    if (r.alpha) f.encoderOptions.push_back({"alpha_bits", "16"});
    f.describe = "prores_ks " + preset + ", " + f.pixFmt;
    return f;
}

VideoFormat gif(const VideoRequest& r) {
    refuseCodec(r, ".gif", {"gif"});
    if (r.crf >= 0) throw invalid_argument("--crf: a GIF has no rate factor (its palette is made for the film)");
    if (r.lossless) throw invalid_argument("--lossless: a GIF holds 256 colours; use .mp4 --lossless or PNG/EXR frames");
    const std::string dither = r.preset.empty() ? "sierra2_4a" : r.preset;
    if (dither != "sierra2_4a" && dither != "bayer" && dither != "floyd_steinberg" && dither != "none")
        throw invalid_argument("--preset: for a GIF, the dither: sierra2_4a, bayer, floyd_steinberg or none; got \"" + dither + "\"");
    VideoFormat f;
    f.container = Container::Gif;
    f.muxer = "gif";
    f.encoder = "gif";
    f.alpha = r.alpha;
    f.pixFmt = "pal8";
    f.evenSize = false;
    f.encoderOptions = {{"dither", dither}};
    f.describe = std::string("gif, palette made for the film, dither ") + dither + (r.alpha ? ", one-bit transparency" : "");
    return f;
}

}  // namespace

std::string avErrorText(int rc) {
    char buf[AV_ERROR_MAX_STRING_SIZE] = {0};
    av_strerror(rc, buf, sizeof buf);
    return buf;
}

Container containerFor(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".mp4") return Container::Mp4;
    if (ext == ".webm") return Container::Webm;
    if (ext == ".mov") return Container::Mov;
    if (ext == ".gif") return Container::Gif;
    throw invalid_argument("the output must be .mp4 (H.264), .webm (VP9), .mov (ProRes 4444) or .gif");
}

VideoFormat videoFormatFor(const VideoRequest& r) {
    VideoFormat f;
    switch (containerFor(r.path)) {
        case Container::Mp4: f = h264(r); break;
        case Container::Webm: f = vp9(r); break;
        case Container::Mov: f = prores(r); break;
        case Container::Gif: f = gif(r); break;
    }
    requireEncoder(f.encoder);
    return f;
}

}  // namespace rf::farm
