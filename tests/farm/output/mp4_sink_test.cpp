// The MP4 encoder checked by decoding with FFmpeg's own tools (ffprobe, ffmpeg), independently
// of the code under test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "farm/output/mp4_remux.h"
#include "farm/output/mp4_sink.h"
#include "tests/farm/output/tool_output.h"

using namespace rf::farm;

namespace {

std::string outDir() { return rf::testing::testOutDir("farm_mp4"); }

using rf::testing::runCapture;

std::string probe(const std::string& file, const std::string& entries) {
    std::string s = runCapture("ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=" + entries +
                               " -of default=nw=1 '" + file + "'");
    return s;
}

// A moving smooth gradient with a sharp square: something an encoder has to work for.
std::vector<uint8_t> synthetic(int w, int h, int f, bool square = true) {
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            uint8_t* p = &rgb[3 * (size_t(y) * w + x)];
            // Gradients of 4 levels per pixel whatever the size: at tiny sizes a steeper red ramp
            // is mostly chroma detail that 4:2:0 cannot keep, whoever encodes it.
            p[0] = uint8_t(std::min(255, x * 4));
            p[1] = uint8_t(std::min(255, y * 5));
            p[2] = uint8_t((f * 20) % 256);
            if (square && x >= f && x < f + 8 && y >= 4 && y < 12) p[0] = p[1] = p[2] = 250;
        }
    return rgb;
}

double psnr(const uint8_t* a, const uint8_t* b, size_t n) {
    double se = 0;
    for (size_t i = 0; i < n; ++i) se += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
    if (se == 0) return 1e9;
    return 10.0 * std::log10(255.0 * 255.0 / (se / n));
}

std::string encode(const std::string& name, int w, int h, int frames, const Mp4Options& o, bool square = true) {
    const std::string path = outDir() + "/" + name;
    Mp4Sink sink(path, w, h, o);
    for (int f = 0; f < frames; ++f) sink.write(f, synthetic(w, h, f, square));
    sink.close();
    return path;
}

}  // namespace

// Stated tolerance: CRF 18 on these frames decodes to at least 33 dB RGB PSNR per frame (34–39
// measured). Decoding them with the wrong matrix (BT.601) or range (full) measures 26–30 dB, so
// the bound also catches colour tags that disagree with the conversion.
constexpr double kMinPsnrDb = 33.0;

TEST(Mp4Sink, DecodesToTheFrameCountSizeRateAndColourTags) {
    Mp4Options o;
    o.fps = 24;
    const std::string path = encode("basic.mp4", 64, 48, 12, o);
    const std::string info = probe(path, "width,height,r_frame_rate,avg_frame_rate,nb_read_frames,pix_fmt,color_range,color_space,color_primaries");
    EXPECT_NE(info.find("width=64\n"), std::string::npos) << info;
    EXPECT_NE(info.find("height=48\n"), std::string::npos) << info;
    EXPECT_NE(info.find("r_frame_rate=24/1\n"), std::string::npos) << info;
    EXPECT_NE(info.find("avg_frame_rate=24/1\n"), std::string::npos) << info;
    EXPECT_NE(info.find("nb_read_frames=12\n"), std::string::npos) << info;
    EXPECT_NE(info.find("pix_fmt=yuv420p\n"), std::string::npos) << info;
    EXPECT_NE(info.find("color_range=tv\n"), std::string::npos) << info;
    EXPECT_NE(info.find("color_space=bt709\n"), std::string::npos) << info;
    EXPECT_NE(info.find("color_primaries=bt709\n"), std::string::npos) << info;

    // Frame timestamps: frame i at i/24 s exactly.
    const std::string pts = runCapture("ffprobe -v error -select_streams v:0 -show_entries frame=pts_time -of csv=p=0 '" + path + "'");
    int i = 0;
    std::string tok;
    for (char c : pts + "\n") {
        if (c == '\n' || c == ',') {
            if (!tok.empty()) {
                EXPECT_NEAR(std::stod(tok), i / 24.0, 1e-4) << "frame " << i;
                ++i;
            }
            tok.clear();
        } else {
            tok += c;
        }
    }
    EXPECT_EQ(i, 12);

    // faststart: the moov box comes before the media data.
    const std::string head = runCapture("head -c 4096 '" + path + "' | od -An -c | tr -d ' \\n'");
    EXPECT_LT(head.find("moov"), head.find("mdat")) << "moov must come first (faststart)";

    // Each decoded frame is close to what went in (ffmpeg converts back with the tagged matrix).
    const std::string raw = runCapture("ffmpeg -v error -i '" + path + "' -f rawvideo -pix_fmt rgb24 -");
    ASSERT_EQ(raw.size(), size_t(64) * 48 * 3 * 12);
    for (int f = 0; f < 12; ++f) {
        const auto src = synthetic(64, 48, f);
        const double db = psnr(reinterpret_cast<const uint8_t*>(raw.data()) + src.size() * f, src.data(), src.size());
        EXPECT_GE(db, kMinPsnrDb) << "frame " << f;
    }
}

TEST(Mp4Sink, LosslessDecodesBitForBit) {
    Mp4Options o;
    o.fps = 30;
    o.lossless = true;
    const std::string path = encode("lossless.mp4", 33, 17, 5, o);
    const std::string raw = runCapture("ffmpeg -v error -i '" + path + "' -f rawvideo -pix_fmt rgb24 -");
    ASSERT_EQ(raw.size(), size_t(33) * 17 * 3 * 5);
    for (int f = 0; f < 5; ++f) {
        const auto src = synthetic(33, 17, f);
        EXPECT_EQ(0, std::memcmp(raw.data() + src.size() * f, src.data(), src.size())) << "frame " << f;
    }
}

TEST(Mp4Sink, OddSizeIsPaddedByRepeatingTheEdge) {
    Mp4Options o;
    int w = 0, h = 0;
    mp4EncodedSize(21, 15, o, w, h);
    EXPECT_EQ(w, 22);
    EXPECT_EQ(h, 16);
    EXPECT_NE(checkMp4Options(21, 15, o).find("22x16"), std::string::npos);
    EXPECT_EQ(checkMp4Options(22, 16, o), "");
    // Smooth content: 4:2:0 chroma on a saturated 8-pixel square at this tiny size would
    // measure chroma subsampling, not padding.
    const std::string path = encode("odd.mp4", 21, 15, 3, o, false);
    const std::string raw = runCapture("ffmpeg -v error -i '" + path + "' -f rawvideo -pix_fmt rgb24 -");
    ASSERT_EQ(raw.size(), size_t(22) * 16 * 3 * 3);
    // The visible 21×15 region matches the source.
    for (int f = 0; f < 3; ++f) {
        const auto src = synthetic(21, 15, f, false);
        std::vector<uint8_t> crop;
        for (int y = 0; y < 15; ++y)
            crop.insert(crop.end(), raw.begin() + (size_t(f) * 16 * 22 + size_t(y) * 22) * 3,
                        raw.begin() + (size_t(f) * 16 * 22 + size_t(y) * 22 + 21) * 3);
        EXPECT_GE(psnr(crop.data(), src.data(), src.size()), kMinPsnrDb) << "frame " << f;
    }
}

TEST(Mp4Sink, BadOptionsAreRefusedUpFront) {
    Mp4Options o;
    o.preset = "warp-speed";
    EXPECT_THROW(checkMp4Options(64, 48, o), std::invalid_argument);
    o.preset = "medium";
    o.fps = 0;
    EXPECT_THROW(checkMp4Options(64, 48, o), std::invalid_argument);
}

// A GIF's delays are whole centiseconds in 16 bits: 100 fps and a frame every 625 s fit; 150
// fps (frames 0.67 cs apart, which the muxer refuses after the render) and 0.001 fps do not.
TEST(Mp4Sink, GifRatesAreTheOnesItsDelaysHold) {
    Mp4Options gif, mp4;
    gif.crf = -1;  // as `render -o x.gif` asks: a GIF has neither
    gif.preset = "";
    auto refusal = [&](double fps) {
        gif.fps = fps;
        try {
            checkMp4Options(64, 48, gif, "x.gif");
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    for (double fps : {100.0, 30.0, 0.0016}) EXPECT_EQ(refusal(fps), "") << fps;
    for (double fps : {150.0, 1000.0, 0.001}) {
        EXPECT_EQ(refusal(fps).rfind("a GIF's frame delays count hundredths of a second", 0), 0u) << fps << ": " << refusal(fps);
        mp4.fps = fps;
        EXPECT_NO_THROW(checkMp4Options(64, 48, mp4, "x.mp4")) << fps;
    }
}

TEST(Mp4Sink, UnwritablePathFailsAtOpen) {
    EXPECT_THROW(Mp4Sink("/nonexistent-dir/x.mp4", 16, 16, Mp4Options{}), std::runtime_error);
}

namespace {

/// Per-packet md5s of a file's video stream, copied without decoding (ffmpeg -c copy).
std::vector<std::string> packetMd5s(const std::string& file) {
    const std::string out = runCapture("ffmpeg -v error -i '" + file + "' -map 0:v -c copy -f framemd5 - | grep -v '^#'");
    std::vector<std::string> md5s;
    size_t start = 0;
    for (size_t nl; (nl = out.find('\n', start)) != std::string::npos; start = nl + 1) {
        const std::string line = out.substr(start, nl - start);
        md5s.push_back(line.substr(line.rfind(',') + 1));
    }
    return md5s;
}

/// Issue 14 #3: a copy of the file taken mid-film (what kill -9 would leave) plays every frame
/// the sink says it flushed; at close the file becomes faststart with the same packets.
void checkPlayableMidFilm(const std::string& name, Mp4Options o) {
    const std::string path = outDir() + "/" + name, partial = outDir() + "/partial_" + name;
    const int w = 64, h = 48;
    o.channels = 3;
    Mp4Sink sink(path, w, h, o);
    for (int f = 0; f < 10; ++f) sink.write(f, synthetic(w, h, f));
    const int flushed = sink.framesInOutput();
    std::filesystem::copy_file(path, partial, std::filesystem::copy_options::overwrite_existing);
    for (int f = 10; f < 20; ++f) sink.write(f, synthetic(w, h, f));
    sink.close();
    EXPECT_EQ(sink.framesInOutput(), 20);
    // The encoders here hold no frame back (x264 ultrafast, ProRes; VP9 at most its lag).
    EXPECT_GE(flushed, 1) << name;
    EXPECT_NE(probe(partial, "nb_read_frames").find("nb_read_frames=" + std::to_string(flushed) + "\n"), std::string::npos)
        << name << ": the copy taken after " << flushed << " flushed frames: " << probe(partial, "nb_read_frames");
    const std::vector<std::string> part = packetMd5s(partial), whole = packetMd5s(path);
    ASSERT_EQ(whole.size(), 20u) << name;
    ASSERT_EQ(part.size(), size_t(flushed)) << name;
    for (size_t i = 0; i < part.size(); ++i) EXPECT_EQ(part[i], whole[i]) << name << ": packet " << i << " changed at close";
    EXPECT_FALSE(std::filesystem::exists(path + ".remux")) << name;
}

/// The top-level boxes of an MP4/MOV file, in order.
std::vector<std::string> topBoxes(const std::string& file) {
    const std::string d = runCapture("cat '" + file + "'");
    std::vector<std::string> boxes;
    for (size_t i = 0; i + 8 <= d.size();) {
        uint64_t size = 0;
        for (int k = 0; k < 4; ++k) size = size << 8 | uint8_t(d[i + k]);
        if (size == 1)
            for (int k = 8; k < 16; ++k) size = size << 8 | uint8_t(d[i + k]);
        boxes.push_back(d.substr(i + 4, 4));
        if (size < 8) break;
        i += size;
    }
    return boxes;
}

}  // namespace

TEST(Mp4Sink, PlaysMidFilmAndBecomesFaststartWithTheSamePackets) {
    checkPlayableMidFilm("midfilm.mp4", Mp4Options{});
    const std::vector<std::string> boxes = topBoxes(outDir() + "/midfilm.mp4");
    const auto at = [&](const char* b) { return std::find(boxes.begin(), boxes.end(), b) - boxes.begin(); };
    EXPECT_LT(at("moov"), at("mdat"));
    EXPECT_EQ(std::count(boxes.begin(), boxes.end(), "moof"), 0) << "the finished file is not fragmented";
    EXPECT_EQ(std::count(boxes.begin(), boxes.end(), "mdat"), 1);
    // Mid-film it was fragmented: one moof per frame after an empty moov.
    const std::vector<std::string> early = topBoxes(outDir() + "/partial_midfilm.mp4");
    EXPECT_GE(std::count(early.begin(), early.end(), "moof"), 1);
}

/// The options as `render` leaves them when --preset and --crf are not given: the format's own.
Mp4Options formatDefaults() {
    Mp4Options o;
    o.preset = "";
    o.crf = -1;
    return o;
}

TEST(Mp4Sink, ProResMovPlaysMidFilm) { checkPlayableMidFilm("midfilm.mov", formatDefaults()); }

TEST(Mp4Sink, WebmPlaysMidFilm) { checkPlayableMidFilm("midfilm.webm", formatDefaults()); }

/// Issue 30 #1: the remux counts the packets it reads back against those the encoder wrote; a
/// file another process wrote into (two renders on one -o) is not renamed into a faststart one
/// that players would take for whole.
TEST(Mp4Sink, RemuxRefusesAFileWhosePacketCountIsNotWhatWasWritten) {
    const std::string path = outDir() + "/count.mp4";
    std::filesystem::remove(path);
    const int w = 64, h = 48;
    Mp4Options o = formatDefaults();
    o.channels = 3;
    {
        Mp4Sink sink(path, w, h, o);
        for (int f = 0; f < 12; ++f) sink.write(f, synthetic(w, h, f));
        sink.close();
    }
    const std::string before = runCapture("sha256sum < '" + path + "'");
    try {
        remuxFaststart(path, "mp4", 30, 1, 13);
        FAIL() << "a file of 12 packets passed as 13";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(path + ": read back 12 video packets, but 13 were written"), std::string::npos) << e.what();
    }
    EXPECT_EQ(runCapture("sha256sum < '" + path + "'"), before) << "the file was replaced after the mismatch";
    EXPECT_FALSE(std::filesystem::exists(remuxTempPath(path)));
    remuxFaststart(path, "mp4", 30, 1, 12);  // the right count passes, and the file still plays
    EXPECT_NE(probe(path, "nb_read_frames").find("nb_read_frames=12\n"), std::string::npos) << probe(path, "nb_read_frames");
}

// Issue 46 #4: the header is on disk at open (a kill -9 before the first frame leaves a file that
// opens, with no frames); a resume (keepEarlierUpTo) leaves the earlier video in place, byte for
// byte, until the new one holds as many frames, then takes its place; an interrupted one that
// did not catch up leaves the earlier video and no OUT.part; an earlier video longer than the
// film is still replaced by the whole film.
TEST(Mp4Sink, HeaderOnDiskAtOpenAndAResumeKeepsTheEarlierVideoUntilItHoldsAsMuch) {
    const int w = 64, h = 48;
    Mp4Options o;
    o.channels = 3;
    o.chunkFrames = 4;
    const std::string path = outDir() + "/resume_keeps.mp4", copy = outDir() + "/resume_keeps_open.mp4";
    std::filesystem::remove(path);
    {
        Mp4Sink fresh(path, w, h, o);
        std::filesystem::copy_file(path, copy, std::filesystem::copy_options::overwrite_existing);
        // ffprobe finds the stream (its frame count: N/A, none): the header was on disk.
        const std::string p = probe(copy, "nb_read_frames");
        EXPECT_TRUE(p == "nb_read_frames=N/A\n" || p == "nb_read_frames=0\n") << "a file killed before its first frame does not open: " << p;
        fresh.close();
    }
    const std::string earlier = encode("resume_keeps.mp4", w, h, 10, o);
    const std::string before = runCapture("md5sum < '" + earlier + "'");
    {
        Mp4Sink again(path, w, h, o, 20);
        for (int f = 0; f < 9; ++f) again.write(f, synthetic(w, h, f));
        EXPECT_EQ(runCapture("md5sum < '" + path + "'"), before) << "the earlier video changed before the new one caught up";
        EXPECT_EQ(again.framesInOutput(), 10) << "what the file at path plays: the earlier video";
        EXPECT_TRUE(std::filesystem::exists(path + ".part"));
        again.close();  // interrupted at 9 of the earlier video's 10
    }
    EXPECT_EQ(runCapture("md5sum < '" + path + "'"), before) << "an interrupted resume replaced a longer video";
    EXPECT_FALSE(std::filesystem::exists(path + ".part"));
    {
        Mp4Sink again(path, w, h, o, 20);
        for (int f = 0; f < 12; ++f) again.write(f, synthetic(w, h, f));
        EXPECT_NE(probe(path, "nb_read_frames").find("nb_read_frames=12"), std::string::npos) << probe(path, "nb_read_frames");
        EXPECT_FALSE(std::filesystem::exists(path + ".part")) << "renamed over the earlier video once it held as many";
        again.close();
    }
    // The earlier video is longer than this film (6 frames): the whole film replaces it.
    {
        Mp4Sink shorter(path, w, h, o, 6);
        for (int f = 0; f < 6; ++f) shorter.write(f, synthetic(w, h, f));
        shorter.close();
    }
    EXPECT_NE(probe(path, "nb_read_frames").find("nb_read_frames=6\n"), std::string::npos) << probe(path, "nb_read_frames");
    EXPECT_FALSE(std::filesystem::exists(path + ".part"));
}

// A resume through a symbolic link (-o link.mp4 -> films/real.mp4) replaces the file the link
// names, not the link: the side file is written beside the target and renamed over it, so the
// link still points at the video, which now holds the new film.
TEST(Mp4Sink, AResumeThroughASymbolicLinkReplacesItsTargetAndKeepsTheLink) {
    const int w = 64, h = 48;
    Mp4Options o;
    o.channels = 3;
    o.chunkFrames = 4;
    const std::string dir = outDir() + "/resume_link", real = dir + "/films/real.mp4", link = dir + "/link.mp4";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir + "/films");
    std::filesystem::create_symlink("films/real.mp4", link);
    {
        Mp4Sink first(link, w, h, o);
        for (int f = 0; f < 8; ++f) first.write(f, synthetic(w, h, f));
        first.close();
    }
    ASSERT_TRUE(std::filesystem::is_symlink(link));
    {
        Mp4Sink again(link, w, h, o, 12);
        for (int f = 0; f < 6; ++f) again.write(f, synthetic(w, h, f));
        EXPECT_TRUE(std::filesystem::exists(real + ".part")) << "the side file goes beside the link's target";
        EXPECT_FALSE(std::filesystem::exists(link + ".part"));
        for (int f = 6; f < 12; ++f) again.write(f, synthetic(w, h, f));
        again.close();
    }
    EXPECT_TRUE(std::filesystem::is_symlink(link)) << "the resume replaced the link with a file";
    EXPECT_NE(probe(real, "nb_read_frames").find("nb_read_frames=12\n"), std::string::npos) << probe(real, "nb_read_frames");
    EXPECT_FALSE(std::filesystem::exists(real + ".part"));
    EXPECT_FALSE(std::filesystem::exists(link + ".part"));
}
