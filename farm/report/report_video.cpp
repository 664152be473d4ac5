#include "farm/report/report_video.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "engine/util/image_metrics.h"
#include "farm/output/mp4_sink.h"
#include "farm/report/report_plot.h"
#include "farm/output/video_decode.h"

namespace rf::report {

namespace {

std::string num(double v, const char* f = "%.6g") {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[32];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

VideoRow encodeAndMeasure(const std::vector<std::vector<uint8_t>>& frames, int w, int h, const std::string& path,
                          const farm::Mp4Options& o) {
    VideoRow row;
    row.preset = o.preset;
    row.crf = o.crf;
    row.lossless = o.lossless;
    row.frames = int(frames.size());
    // Short encodes are timed as the fastest of a few repeats: other work on the machine only adds.
    double total = 0.0;
    row.encodeSeconds = 1e300;
    for (int rep = 0; rep < 5 && (rep == 0 || total < 0.3); ++rep) {
        const auto t0 = std::chrono::steady_clock::now();
        {
            farm::Mp4Sink sink(path, w, h, o);
            for (size_t i = 0; i < frames.size(); ++i) sink.write(int(i), frames[i]);
            sink.close();
        }
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        total += s;
        row.encodeSeconds = std::min(row.encodeSeconds, s);
    }
    row.encodeFps = row.frames / std::max(row.encodeSeconds, 1e-9);
    row.bytes = std::filesystem::file_size(path);
    row.kbps = double(row.bytes) * 8.0 / 1000.0 / (row.frames / o.fps);

    const auto decoded = farm::decodeVideoRgb8(path, w, h);
    if (decoded.size() != frames.size())
        throw std::runtime_error(path + ": decoded " + std::to_string(decoded.size()) + " frames, encoded " +
                                 std::to_string(frames.size()));
    double mse = 0.0, ssim = 0.0;
    row.minPsnr = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < frames.size(); ++i) {
        const double r = rmseRgb8(decoded[i], frames[i], w, h);
        mse += r * r;
        row.minPsnr = std::min(row.minPsnr, psnrFromRmse(r));
        ssim += ssimRgb8(decoded[i], frames[i], w, h);
    }
    row.psnr = psnrFromRmse(std::sqrt(mse / double(frames.size())));
    row.ssim = ssim / double(frames.size());
    return row;
}

}  // namespace

std::vector<VideoRow> runVideoSweep(const std::vector<std::vector<uint8_t>>& frames, int width, int height,
                                    const VideoSweepSpec& spec, const std::string& scratchPath,
                                    const std::function<void(int, int, const VideoRow&)>& progress) {
    if (frames.empty()) throw std::invalid_argument("video sweep: no frames");
    std::vector<farm::Mp4Options> runs;
    if (spec.losslessCheck) {
        farm::Mp4Options o;
        o.fps = spec.fps;
        o.lossless = true;
        o.preset = "ultrafast";
        o.crf = 0;
        runs.push_back(o);
    }
    for (const std::string& p : spec.presets)
        for (int c : spec.crf) {
            farm::Mp4Options o;
            o.fps = spec.fps;
            o.preset = p;
            o.crf = c;
            runs.push_back(o);
        }
    std::vector<VideoRow> rows;
    for (size_t i = 0; i < runs.size(); ++i) {
        rows.push_back(encodeAndMeasure(frames, width, height, scratchPath, runs[i]));
        if (progress) progress(int(i) + 1, int(runs.size()), rows.back());
    }
    std::filesystem::remove(scratchPath);
    markVideoPareto(rows);
    return rows;
}

void markVideoPareto(std::vector<VideoRow>& rows) {
    for (VideoRow& a : rows) {
        a.pareto = !a.lossless;  // lossless RGB is a decode check, not a delivery format
        if (!a.pareto) continue;
        for (const VideoRow& b : rows) {
            if (&a == &b || b.lossless) continue;
            if (b.encodeFps >= a.encodeFps && b.psnr >= a.psnr && (b.encodeFps > a.encodeFps || b.psnr > a.psnr)) {
                a.pareto = false;
                break;
            }
        }
    }
}

void writeVideoCsv(const std::string& path, const std::vector<VideoRow>& rows) {
    std::ofstream f(path);
    if (!f) throw std::runtime_error(path + ": cannot write");
    f << "preset,crf,lossless,frames,encode_s,encode_fps,bytes,kbps,psnr_db,min_psnr_db,ssim,pareto\n";
    for (const VideoRow& r : rows)
        f << r.preset << "," << r.crf << "," << (r.lossless ? 1 : 0) << "," << r.frames << "," << num(r.encodeSeconds)
          << "," << num(r.encodeFps) << "," << r.bytes << "," << num(r.kbps) << "," << num(r.psnr) << ","
          << num(r.minPsnr) << "," << num(r.ssim) << "," << (r.pareto ? 1 : 0) << "\n";
    if (!f.flush()) throw std::runtime_error(path + ": write failed");
}

std::string videoPlotScript(const std::vector<VideoRow>& rows, const std::string& title, const std::string& pngPath) {
    std::ostringstream s;
    s << "# Encoded MP4 against the lossless frames, written by rayfarm report. Re-draw: gnuplot THIS_FILE\n"
      << "set terminal pngcairo size 960,640 enhanced font 'DejaVu Sans,10'\n"
      << "set output " << gnuplotQuote(pngPath) << "\n"
      << "set title " << gnuplotQuote(title) << " noenhanced\n"
      << "set logscale x\nset xlabel 'encoding speed (frames/s, open to close of the MP4 sink)'\n"
      << "set ylabel 'PSNR against the lossless frames (dB)'\n"
      << "set grid lc rgb '#dddddd'\nset key outside right top box opaque noenhanced\nset format x '%g'\n"
      << "set xtics (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000, 20000)\n"
;
    // Explicit ranges: gnuplot warns on (and pads oddly) a range that holds a single value.
    double flo = 1e300, fhi = 0.0, plo = 1e300, phi = -1e300;
    for (const VideoRow& r : rows) {
        if (r.lossless || !std::isfinite(r.psnr)) continue;
        flo = std::min(flo, r.encodeFps), fhi = std::max(fhi, r.encodeFps);
        plo = std::min(plo, r.psnr), phi = std::max(phi, r.psnr);
    }
    if (fhi > 0.0)
        s << "set xrange [" << num(flo / 1.5) << ":" << num(fhi * 1.5) << "]\nset yrange [" << num(plo - 2.0) << ":"
          << num(phi + 2.0) << "]\n";
    std::map<std::string, std::vector<const VideoRow*>> byPreset;
    std::vector<const VideoRow*> front;
    for (const VideoRow& r : rows) {
        if (r.lossless) continue;
        byPreset[r.preset].push_back(&r);
        if (r.pareto) front.push_back(&r);
    }
    std::sort(front.begin(), front.end(), [](auto* a, auto* b) { return a->encodeFps < b->encodeFps; });
    std::vector<std::string> plots;
    int pt = 5;
    for (const auto& [preset, list] : byPreset) {
        s << "$p_" << preset << " << EOD\n";
        for (const VideoRow* r : list) s << num(r->encodeFps) << " " << num(r->psnr) << " \"crf " << r->crf << "\"\n";
        s << "EOD\n";
        plots.push_back("$p_" + preset + " using 1:2 with linespoints pt " + std::to_string(pt++) + " ps 1.3 title " +
                        gnuplotQuote("preset " + preset));
        plots.push_back("$p_" + preset + " using 1:2:3 with labels offset 0.9,0 left font ',8' notitle");
    }
    s << "$front << EOD\n";
    for (const VideoRow* r : front) s << num(r->encodeFps) << " " << num(r->psnr) << "\n";
    s << "EOD\n";
    plots.push_back("$front using 1:2 with lines lw 3 lc rgb '#d62728' dt 2 title 'Pareto front'");
    s << "plot ";
    for (size_t i = 0; i < plots.size(); ++i) s << (i ? ", \\\n     " : "") << plots[i];
    s << "\n";
    return s.str();
}

std::string videoMarkdown(const std::vector<VideoRow>& rows, int frames, int width, int height) {
    std::ostringstream s;
    s << "## Video: the encoded MP4 against the lossless frames\n\n"
      << frames << " frames of the timeline at " << width << "×" << height
      << ", rendered once at the default setting, then encoded by the farm's MP4 sink (libx264, yuv420p BT.709) "
      << "for each preset and CRF, decoded again through libavcodec and scored against the 8-bit frames: PSNR from "
      << "the mean squared error over all frames, the worst frame's PSNR, mean SSIM. Encoding speed is frames over "
      << "the time from opening the sink to closing it (x264 on all cores). Every row: `video.csv`; plot: "
      << "`video_psnr_vs_fps.png`. CRF 0 is lossless in YUV: what it loses is the conversion to yuv420p "
      << "(colour at half resolution, 8-bit limited range), the ceiling for every other setting.\n\n";
    for (const VideoRow& r : rows)
        if (r.lossless)
            s << (std::isinf(r.psnr) ? "Decode check: the lossless encode (libx264rgb, qp 0) decodes bit for bit "
                                       "(PSNR ∞), so the numbers below measure the encoder, not the decoding path.\n\n"
                                     : "**Decode check failed**: the lossless encode decodes with PSNR " +
                                           num(r.psnr, "%.2f") + " dB, so the figures below include a decoding error.\n\n");
    s << "Pareto front (no other setting both encodes faster and scores higher):\n\n"
      << "| preset | CRF | encode fps | kbit/s | PSNR | worst frame | SSIM |\n|---|---:|---:|---:|---:|---:|---:|\n";
    std::vector<const VideoRow*> front;
    for (const VideoRow& r : rows)
        if (r.pareto) front.push_back(&r);
    std::sort(front.begin(), front.end(), [](auto* a, auto* b) { return a->encodeFps > b->encodeFps; });
    for (const VideoRow* r : front)
        s << "| " << r->preset << " | " << r->crf << " | " << num(r->encodeFps, "%.1f") << " | " << num(r->kbps, "%.0f")
          << " | " << num(r->psnr, "%.2f") << " dB | " << num(r->minPsnr, "%.2f") << " dB | " << num(r->ssim, "%.4f")
          << " |\n";
    s << "\nThis front weighs speed against fidelity only. At the same CRF a slower preset mostly buys a smaller "
      << "file (kbit/s in `video.csv`), which it does not reward.\n\n";
    return s.str();
}

}  // namespace rf::report
