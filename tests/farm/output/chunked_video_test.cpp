// Chunked encoding (video_chunk.h, chunk_encoder.h, chunk_muxer.h, Mp4Sink): a film whose
// chunks are encoded here, elsewhere, or some of each is the same file, byte for byte, in every
// format; the joins decode to the right frames and timestamps (checked with ffprobe).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "farm/output/chunk_encoder.h"
#include "farm/output/mp4_sink.h"
#include "tests/farm/output/tool_output.h"
#include "farm/output/video_chunk.h"

using namespace rf::farm;

namespace {

std::string outDir() { return rf::testing::testOutDir("farm_chunks"); }

using rf::testing::runCapture;

std::string fileBytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

/// Moving content with texture, so that every frame costs the encoder something; RGBA with a
/// soft alpha edge when channels is 4.
std::vector<uint8_t> frameOf(int w, int h, int f, int channels) {
    std::vector<uint8_t> px(size_t(w) * h * channels);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            uint8_t* p = &px[size_t(channels) * (size_t(y) * w + x)];
            p[0] = uint8_t(x * 4 + f * 3);
            p[1] = uint8_t(y * 5 + ((x ^ y) & 15));
            p[2] = uint8_t((f * 20 + x) % 256);
            if (channels == 4) p[3] = uint8_t(std::min(255, std::max(0, (x - f) * 16)));
        }
    return px;
}

struct Case {
    const char* name;
    Mp4Options options;
};

Mp4Options optionsFor(int channels, bool lossless = false, const char* preset = "") {
    Mp4Options o;
    o.preset = preset;
    o.crf = -1;
    o.channels = channels;
    o.lossless = lossless;
    o.chunkFrames = 4;
    return o;
}

constexpr int kW = 64, kH = 48, kFrames = 11;  // chunks of 4, 4 and 3 frames

/// The film written three ways: every frame through the sink; every chunk encoded apart and
/// joined; and alternating. Returns the three paths.
std::vector<std::string> writeThreeWays(const std::string& ext, const Mp4Options& o) {
    const ChunkPlan plan{0, kFrames - 1, o.chunkFrames};
    std::vector<std::string> paths;
    for (int way = 0; way < 3; ++way) {
        // Named by the test too: CTest runs the tests of one format side by side.
        const std::string path = outDir() + "/" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_way" +
                                 std::to_string(way) + "." + ext;
        std::filesystem::remove(path);
        Mp4Sink sink(path, kW, kH, o);
        for (int c = 0; c < plan.count(); ++c) {
            const bool apart = way == 1 || (way == 2 && c % 2 == 1);
            if (apart) {
                std::vector<std::vector<uint8_t>> frames;
                for (int f = plan.firstFrame(c); f <= plan.lastFrame(c); ++f) frames.push_back(frameOf(kW, kH, f, o.channels));
                // Through the wire format, as a worker's chunk reaches rank 0.
                sink.writeChunk(parseChunk(serializeChunk(encodeChunk(path, kW, kH, o, o.chunkFrames, c, frames))));
            } else {
                for (int f = plan.firstFrame(c); f <= plan.lastFrame(c); ++f) sink.write(f, frameOf(kW, kH, f, o.channels));
            }
        }
        sink.close();
        paths.push_back(path);
    }
    return paths;
}

/// "pts_time,key" per packet of the video stream, in file order.
std::vector<std::string> packets(const std::string& file) {
    std::istringstream in(runCapture("ffprobe -v error -select_streams v:0 -show_entries packet=pts,flags -of csv=p=0 '" + file + "'"));
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) out.push_back(line);
    return out;
}

void checkFormat(const std::string& ext, const Mp4Options& o) {
    const std::vector<std::string> p = writeThreeWays(ext, o);
    const std::string ref = fileBytes(p[0]);
    ASSERT_GT(ref.size(), 100u) << ext;
    EXPECT_EQ(fileBytes(p[1]), ref) << ext << ": the chunks encoded apart and joined differ from the frames encoded here";
    EXPECT_EQ(fileBytes(p[2]), ref) << ext << ": chunks from both sides, alternating, differ";
    // Decoded: every frame once, timestamps 0..10 frames without a gap or a repeat, a key frame
    // at each chunk's start (VP9 and ProRes may have more; H.264 exactly those).
    const std::string count = runCapture("ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames -of csv=p=0 '" +
                                         p[1] + "'");
    EXPECT_EQ(count, std::to_string(kFrames) + "\n") << ext;
    const std::vector<std::string> pk = packets(p[1]);
    ASSERT_EQ(pk.size(), size_t(kFrames)) << ext;
    std::vector<long> pts;
    for (size_t i = 0; i < pk.size(); ++i) {
        pts.push_back(std::stol(pk[i].substr(0, pk[i].find(','))));
        const bool key = pk[i].find(",K") != std::string::npos;
        if (i % 4 == 0) {
            EXPECT_TRUE(key) << ext << ": packet " << i << " starts a chunk and is no key frame";
        } else if (ext == "mp4") {
            EXPECT_FALSE(key) << ext << ": packet " << i << " is a key frame inside a chunk";
        }
    }
    // One frame apart: equal steps, within one tick where the container's clock does not divide
    // the frame rate (WebM counts milliseconds: 33 or 34 at 30 fps).
    std::sort(pts.begin(), pts.end());
    long lo = pts[1] - pts[0], hi = lo;
    for (size_t i = 1; i < pts.size(); ++i) lo = std::min(lo, pts[i] - pts[i - 1]), hi = std::max(hi, pts[i] - pts[i - 1]);
    EXPECT_GT(lo, 0) << ext << ": two frames at one time";
    EXPECT_LE(hi - lo, 1) << ext << ": a gap (steps from " << lo << " to " << hi << " ticks)";
}

}  // namespace

TEST(ChunkedVideo, H264JoinsAreTheSameFileHoweverTheChunksWereEncoded) { checkFormat("mp4", optionsFor(3)); }
TEST(ChunkedVideo, H264WithBFramesJoinsTheSame) { checkFormat("mp4", optionsFor(3, false, "medium")); }
TEST(ChunkedVideo, LosslessH264JoinsTheSame) { checkFormat("mp4", optionsFor(3, true)); }
TEST(ChunkedVideo, Vp9WithAlphaJoinsTheSame) { checkFormat("webm", optionsFor(4)); }
TEST(ChunkedVideo, ProResJoinsTheSame) { checkFormat("mov", optionsFor(4)); }

TEST(ChunkedVideo, ChunkSurvivesTheWireWithSideData) {
    EncodedChunk c;
    c.index = 7;
    c.frames = 3;
    c.encodeSeconds = 0.25;
    c.extradata = std::string("\0\1\2", 3);
    c.packets.push_back({-1, -2, 1, 1, std::string("abc\0def", 7), {{15, "alpha"}}});
    c.packets.push_back({0, -1, 1, 0, "", {}});
    const EncodedChunk d = parseChunk(serializeChunk(c));
    EXPECT_EQ(d.index, 7);
    EXPECT_EQ(d.frames, 3);
    EXPECT_EQ(d.encodeSeconds, 0.25);
    EXPECT_EQ(d.extradata, c.extradata);
    ASSERT_EQ(d.packets.size(), 2u);
    EXPECT_EQ(d.packets[0].pts, -1);
    EXPECT_EQ(d.packets[0].dts, -2);
    EXPECT_EQ(d.packets[0].data, c.packets[0].data);
    ASSERT_EQ(d.packets[0].side.size(), 1u);
    EXPECT_EQ(d.packets[0].side[0].first, 15);
    EXPECT_EQ(d.packets[0].side[0].second, "alpha");
    const std::string bytes = serializeChunk(c);
    for (size_t cut : {size_t(0), size_t(5), bytes.size() / 2, bytes.size() - 1})
        EXPECT_THROW(parseChunk(bytes.substr(0, cut)), std::runtime_error) << "cut at " << cut;
    std::string corrupt = bytes;
    corrupt[34] = '\x7f';  // the packet count's high byte (after 20 + 8 + 3 bytes): a count no payload holds
    EXPECT_THROW(parseChunk(corrupt), std::runtime_error);
}

TEST(ChunkedVideo, AChunkOutOfOrderOrFromAnotherStreamIsRefused) {
    const Mp4Options o = optionsFor(3);
    const std::string path = outDir() + "/refuse.mp4";
    Mp4Sink sink(path, kW, kH, o);
    std::vector<std::vector<uint8_t>> frames;
    for (int f = 0; f < 4; ++f) frames.push_back(frameOf(kW, kH, f, 3));
    EXPECT_THROW(sink.writeChunk(encodeChunk(path, kW, kH, o, 4, 1, frames)), std::runtime_error) << "chunk 1 before chunk 0";
    // Another size has another SPS: its packets would not decode under this file's header.
    std::vector<std::vector<uint8_t>> other;
    for (int f = 0; f < 4; ++f) other.push_back(frameOf(kW * 2, kH, f, 3));
    EXPECT_THROW(sink.writeChunk(encodeChunk(path, kW * 2, kH, o, 4, 0, other)), std::runtime_error);
    sink.write(0, frames[0]);
    EXPECT_THROW(sink.writeChunk(encodeChunk(path, kW, kH, o, 4, 0, frames)), std::runtime_error) << "a chunk mid-chunk";
}

TEST(ChunkedVideo, PlanCutsTheFilmIntoChunksOfK) {
    const ChunkPlan p{10, 20, 4};
    EXPECT_EQ(p.count(), 3);
    EXPECT_EQ(p.firstFrame(2), 18);
    EXPECT_EQ(p.lastFrame(2), 20);
    EXPECT_EQ(p.framesIn(2), 3);
    EXPECT_EQ(p.chunkOf(17), 1);
    EXPECT_EQ(defaultChunkFrames(30.0, 3000), 60) << "two seconds of a long film";
    EXPECT_EQ(defaultChunkFrames(23.976, 3000), 48);
    EXPECT_EQ(defaultChunkFrames(0.5, 3000), 2) << "never under 2 frames";
    EXPECT_EQ(defaultChunkFrames(30.0, 120), 15) << "a 4 s film: an eighth of it";
    EXPECT_EQ(defaultChunkFrames(120.0, 120), 15) << "the same frames at another rate";
    EXPECT_EQ(defaultChunkFrames(30.0, 121), 16) << "rounded up: 8 chunks at most";
    EXPECT_EQ(defaultChunkFrames(30.0, 5), 2);
    EXPECT_EQ(defaultChunkFrames(30.0, 1), 2);
    EXPECT_EQ(defaultChunkFrames(30.0, 2147483647), 60) << "the largest film: no overflow";
}
