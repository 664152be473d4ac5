#pragma once
/// The video part of `rayfarm report`: the same frames encoded by the MP4 sink at several CRF
/// and preset values, decoded again, and scored against the lossless frames (PSNR, SSIM) next to
/// the encoding speed (frames per second) and the bit rate.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rf::report {

struct VideoSweepSpec {
    std::vector<int> crf{0, 12, 18, 23, 28, 35};  ///< 0: lossless in YUV, the yuv420p ceiling
    std::vector<std::string> presets{"ultrafast", "veryfast", "medium", "slow"};
    double fps = 30.0;
    bool losslessCheck = true;  ///< also encode losslessly (libx264rgb, qp 0): must decode exactly
};

struct VideoRow {
    std::string preset;
    int crf = 0;
    bool lossless = false;
    int frames = 0;
    double encodeSeconds = 0.0;  ///< sink opened to sink closed (fastest of repeats)
    double encodeFps = 0.0;
    uint64_t bytes = 0;
    double kbps = 0.0;      ///< at the timeline's frame rate
    double psnr = 0.0;      ///< from the MSE over all frames; +inf if every frame decodes exactly
    double minPsnr = 0.0;   ///< the worst frame
    double ssim = 1.0;      ///< mean over frames
    bool pareto = false;    ///< no other row is both faster and at least as accurate
};

/// Encodes frames (each width × height × 3 sRGB bytes) once per (preset, crf) through the MP4 sink
/// into scratchPath, decodes it, and measures it. progress(i, n, row) after each encode.
std::vector<VideoRow> runVideoSweep(const std::vector<std::vector<uint8_t>>& frames, int width, int height,
                                    const VideoSweepSpec& spec, const std::string& scratchPath,
                                    const std::function<void(int, int, const VideoRow&)>& progress = {});

/// Marks rows with no other row at least as fast and at least as accurate (PSNR), one strictly.
void markVideoPareto(std::vector<VideoRow>& rows);

/// video.csv: a header and one line per row.
void writeVideoCsv(const std::string& path, const std::vector<VideoRow>& rows);

/// The gnuplot script for PSNR against encoding frames per second, one line per preset.
std::string videoPlotScript(const std::vector<VideoRow>& rows, const std::string& title, const std::string& pngPath);

/// A Markdown section for summary.md: the best trade-offs and what was measured.
std::string videoMarkdown(const std::vector<VideoRow>& rows, int frames, int width, int height);

}  // namespace rf::report
