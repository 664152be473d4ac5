#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "farm/process/usage_error.h"
#include "farm/output/frame_sink.h"
#include "engine/util/image.h"
#include "farm/output/png_sink.h"

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
    EXPECT_EQ(findKeptFrames(dir, {11, 12, 13, 40}, 5, 3), (anim::FrameRanges{12, 40}));
}

TEST(PngSink, TruncatedCorruptOrUnrecordedFramesAreNotKept) {
    const std::string dir = freshDir("farm_png_bad");
    writeFramesManifest(dir, "{}", {});
    {
        AsyncSink sink(std::make_unique<PngSink>(dir, 4, 4), 2);
        for (int f : {0, 1, 3}) sink.write(f, std::vector<uint8_t>(4 * 4 * 3, uint8_t(40 * f + 7)));
        sink.close();
    }
    writePng(framePngPath(dir, 2), 5, 4, std::vector<uint8_t>(5 * 4 * 3, 1));  // wrong size, not recorded
    writePng(framePngPath(dir, 4), 4, 4, std::vector<uint8_t>(4 * 4 * 3, 1));  // whole, but not recorded
    std::filesystem::resize_file(framePngPath(dir, 1), std::filesystem::file_size(framePngPath(dir, 1)) - 5);
    // Issue 14 #9: a byte flipped in the middle keeps the header and IEND intact.
    {
        std::fstream f(framePngPath(dir, 3), std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(40);
        f.put(char(0x5a));
    }
    std::vector<int> corrupt;
    EXPECT_EQ(findKeptFrames(dir, {0, 1, 2, 3, 4, 5}, 4, 4, &corrupt), (anim::FrameRanges{0}));
    EXPECT_EQ(corrupt, (std::vector<int>{1, 2, 3, 4}));
}

TEST(PngSink, ManifestMustMatchToResume) {
    const std::string dir = freshDir("farm_manifest");
    const std::map<std::string, std::string> inputs = {{"s.json", "aa"}, {"m.glb", "bb"}};
    EXPECT_THROW(checkFramesManifest(dir, "{\"a\":1}", inputs), UsageError);
    writeFramesManifest(dir, "{\"a\":1}", inputs);
    EXPECT_NO_THROW(checkFramesManifest(dir, "{\"a\":1}", inputs));
    EXPECT_THROW(checkFramesManifest(dir, "{\"a\":2}", inputs), UsageError);
    // Issue 14 #5: the same settings over a changed input file are refused, naming the file.
    auto messageFor = [&](const std::map<std::string, std::string>& now) -> std::string {
        try {
            checkFramesManifest(dir, "{\"a\":1}", now);
        } catch (const UsageError& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_NE(messageFor({{"s.json", "ab"}, {"m.glb", "bb"}}).find("the scene changed since its frames were rendered (s.json changed)"), std::string::npos);
    EXPECT_NE(messageFor({{"s.json", "aa"}}).find("m.glb is no longer used"), std::string::npos);
    EXPECT_NE(messageFor({{"s.json", "aa"}, {"m.glb", "bb"}, {"t.png", "cc"}}).find("t.png is new"), std::string::npos);
}

// Issue 46 #1: a resume with other settings names each setting that differs, old and new.
TEST(PngSink, ResumeWithOtherSettingsNamesThem) {
    const std::string dir = freshDir("farm_manifest_settings");
    writeFramesManifest(dir, R"({"spp":1,"exposure":0.0})", {});
    std::string message;
    try {
        checkFramesManifest(dir, R"({"spp":1,"exposure":0.5,"environment_rotation":90.0})", {});
    } catch (const UsageError& e) {
        message = e.what();
    }
    EXPECT_NE(message.find(dir + ": cannot resume: its frames were rendered with other settings (exposure was 0.0, now 0.5, "
                           "environment_rotation was not given, now 90.0); resume with the first run's settings"),
              std::string::npos)
        << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(PngSink, InputDigestsAreSha256OfEachBundleFile) {
    FileBundle b;
    b.files["a.json"] = "abc";
    const auto d = inputDigests(b);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d.at("a.json"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");  // FIPS 180-2 example
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

// A caller that has caught the sink's error and writes again (frame mode writing the frames
// after the last whole chunk once the run has failed) must get the error again: the stopped
// thread takes nothing off the queue, so a write that waited for room would wait for ever.
TEST(AsyncSink, WritesAfterTheThreadStoppedOnAnErrorThrowItAgain) {
    struct Failing : FrameSink {
        void write(int, const std::vector<uint8_t>&) override { throw std::runtime_error("File too large"); }
        void close() override {}
    };
    AsyncSink sink(std::make_unique<Failing>(), 2);
    auto writesUntilThrown = [&] {
        for (int i = 0; i < 100; ++i) {
            try {
                sink.write(i, {1, 2, 3});
            } catch (const std::runtime_error& e) {
                return std::string(e.what());
            }
        }
        return std::string("no error in 100 writes");
    };
    EXPECT_EQ(writesUntilThrown(), "File too large");
    // Far more writes than the queue holds: each throws at once.
    for (int round = 0; round < 10; ++round) EXPECT_EQ(writesUntilThrown(), "File too large");
    // The error reached the caller already; closing reports it no second time.
    EXPECT_NO_THROW(sink.close());
}

// Issue 30 #2: kept frames are found from one pass over the directory, so a selection of 10⁹
// frames costs no look-up per frame; only names this rayfarm writes count.
TEST(PngSink, KeptFramesOfABillionFrameSelectionComeFromTheListing) {
    const std::string dir = freshDir("farm_png_long");
    writeFramesManifest(dir, "{}", {});
    const std::vector<uint8_t> rgb(2 * 2 * 3, 9);
    {
        AsyncSink sink(std::make_unique<PngSink>(dir, 2, 2), 2);
        for (int f : {3, 1234567, 999999999}) sink.write(f, rgb);
        sink.close();
    }
    writePng(dir + "/frame_12.png", 2, 2, rgb);       // not the name frame 12 gets
    writePng(dir + "/frame_0000012.png", 2, 2, rgb);  // nor this
    writePng(dir + "/frame_000013.png.part", 2, 2, rgb);
    EXPECT_EQ(framesInDir(dir, "png", anim::FrameRanges::span(0, 999999999)), (std::vector<int>{3, 1234567, 999999999}));
    EXPECT_EQ(findKeptFrames(dir, anim::FrameRanges::span(0, 999999999), 2, 2), (anim::FrameRanges{3, 1234567, 999999999}));
    EXPECT_EQ(findKeptFrames(dir, anim::FrameRanges::span(4, 999999998), 2, 2), (anim::FrameRanges{1234567}));
}

// Seen in issue 30: the clean-up of a fresh run and the refusal to throw an earlier run's frames
// away matched six-digit names only, so frames from 10⁶ on were left behind (and later taken for
// this run's by --resume) and went uncounted.
TEST(PngSink, FramesPastSixDigitsAreClearedAndCountedLikeTheOthers) {
    EXPECT_EQ(frameOfFileName("frame_000012.png", "png"), 12);
    EXPECT_EQ(frameOfFileName("frame_1000000.png", "png"), 1000000);
    EXPECT_EQ(frameOfFileName("frame_2147483647.exr", "exr"), 2147483647);
    EXPECT_EQ(frameOfFileName("frame_2147483648.png", "png"), -1);
    EXPECT_EQ(frameOfFileName("frame_0000012.png", "png"), -1);
    EXPECT_EQ(frameOfFileName("frame_000012.exr", "png"), -1);

    const std::string dir = freshDir("farm_png_seven_digits");
    writeFramesManifest(dir, "{}", {});
    const std::vector<uint8_t> rgb(2 * 2 * 3, 9);
    for (const char* name : {"frame_000003.png", "frame_1000000.png", "frame_1234567.exr", "frame_12345678.png.part"})
        writePng(dir + "/" + name, 2, 2, rgb);
    writePng(dir + "/frame_0000004.png", 2, 2, rgb);  // not a name rayfarm writes: someone else's
    try {
        refuseEarlierFrames(dir);
        ADD_FAILURE() << "earlier frames were not refused";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("holds 3 frame files"), std::string::npos) << e.what();
    }
    prepareFramesDir(dir);
    std::vector<std::string> left;
    for (const auto& e : std::filesystem::directory_iterator(dir)) left.push_back(e.path().filename().string());
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, (std::vector<std::string>{"frame_0000004.png", "rayfarm-frames.json", "rayfarm-frames.sha256"}));
}
