#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli.h"
#include "frame_sink.h"
#include "image.h"
#include "png_sink.h"

using namespace rf;
using namespace rf::farm;

namespace {
std::string freshDir(const std::string& name) {
    const std::string d = std::string(RAYFARM_TEST_OUT) + "/" + name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}
}  // namespace

TEST(PngSink, WritesFramesByTimelineIndexAndReadsThemBack) {
    const std::string dir = freshDir("farm_png");
    AsyncSink sink(std::make_unique<PngSink>(dir, 5, 3), 2);
    std::vector<uint8_t> rgb(5 * 3 * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = uint8_t(i * 5);
    sink.write(12, rgb);
    sink.write(40, rgb);
    sink.close();
    EXPECT_EQ(sink.framesDone(), 2);
    int w = 0, h = 0;
    EXPECT_EQ(readImageRgb8(framePngPath(dir, 12), w, h), rgb);
    EXPECT_EQ(w, 5);
    EXPECT_EQ(h, 3);
    EXPECT_EQ(findKeptFrames(dir, {11, 12, 13, 40}, 5, 3), (std::set<int>{12, 40}));
}

TEST(PngSink, TruncatedOrWrongSizeFramesAreNotKept) {
    const std::string dir = freshDir("farm_png_bad");
    std::vector<uint8_t> rgb(4 * 4 * 3, 100);
    writePng(framePngPath(dir, 0), 4, 4, rgb);
    writePng(framePngPath(dir, 1), 4, 4, rgb);
    writePng(framePngPath(dir, 2), 5, 4, std::vector<uint8_t>(5 * 4 * 3, 1));
    std::filesystem::resize_file(framePngPath(dir, 1), std::filesystem::file_size(framePngPath(dir, 1)) - 5);
    EXPECT_EQ(findKeptFrames(dir, {0, 1, 2, 3}, 4, 4), (std::set<int>{0}));
}

TEST(PngSink, ManifestMustMatchToResume) {
    const std::string dir = freshDir("farm_manifest");
    EXPECT_THROW(checkFramesManifest(dir, "{\"a\":1}"), cli::UsageError);
    writeFramesManifest(dir, "{\"a\":1}");
    EXPECT_NO_THROW(checkFramesManifest(dir, "{\"a\":1}"));
    EXPECT_THROW(checkFramesManifest(dir, "{\"a\":2}"), cli::UsageError);
}

TEST(AsyncSink, ErrorsOnTheSinkThreadReachTheCaller) {
    struct Failing : FrameSink {
        void write(int, const std::vector<uint8_t>&) override { throw std::runtime_error("disk full"); }
        void close() override {}
    };
    AsyncSink sink(std::make_unique<Failing>(), 1);
    bool thrown = false;
    try {
        for (int i = 0; i < 10; ++i) sink.write(i, {1, 2, 3});
        sink.close();
    } catch (const std::runtime_error& e) {
        thrown = std::string(e.what()) == "disk full";
    }
    EXPECT_TRUE(thrown);
}
