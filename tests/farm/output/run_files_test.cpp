// Issue 46 #3: an output named after one of the run's own files (its locks, the remux's
// temporary file, the frames folder's frames, manifest, checksum list, log) is refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "farm/output/run_files.h"
#include "farm/process/usage_error.h"

namespace rf::farm {
namespace {

TEST(RunFiles, NamesEachOfTheRunsOwnFiles) {
    EXPECT_EQ(runFileAt("out.mp4.lock", "out.mp4", "out.frames"), "the lock this run holds on -o (out.mp4)");
    EXPECT_EQ(runFileAt("out.frames.lock", "out.mp4", "out.frames/"), "the lock this run holds on its frames folder (out.frames/)");
    EXPECT_EQ(runFileAt("./out.mp4.remux", "out.mp4", "out.frames"), "the temporary file the video (out.mp4) is remuxed through");
    EXPECT_EQ(runFileAt("out.gif.part", "out.gif", ""), "the temporary file the video (out.gif) is written through");
    EXPECT_EQ(runFileAt("out.frames/frame_000003.png", "out.mp4", "out.frames"), "a frame kept in the frames folder (out.frames)");
    EXPECT_EQ(runFileAt("out.frames/frame_1234567.exr", "out.mp4", "out.frames"), "a frame kept in the frames folder (out.frames)");
    EXPECT_EQ(runFileAt("out.frames/frame_000003.png.part", "out.mp4", "out.frames"),
              "a frame's temporary file in the frames folder (out.frames)");
    EXPECT_EQ(runFileAt("out.frames/rayfarm-frames.json", "out.mp4", "out.frames"), "the frames folder's manifest (out.frames)");
    EXPECT_EQ(runFileAt("out.frames/rayfarm-frames.sha256", "out.mp4", "out.frames"), "the frames folder's checksum list (out.frames)");
    EXPECT_EQ(runFileAt("out.frames/rayfarm.log", "out.mp4", "out.frames"), "the frames folder's log (out.frames)");
    // The same folder by another name.
    const std::string abs = (std::filesystem::current_path() / "out.frames").string();
    EXPECT_EQ(runFileAt(abs + "/rayfarm-frames.json", "out.mp4", "out.frames"), "the frames folder's manifest (out.frames)");
}

TEST(RunFiles, LeavesOtherNamesAlone) {
    EXPECT_EQ(runFileAt("stats.json", "out.mp4", "out.frames"), "");
    EXPECT_EQ(runFileAt("out.frames/stats.json", "out.mp4", "out.frames"), "");
    EXPECT_EQ(runFileAt("out.frames/frame_12.png", "out.mp4", "out.frames"), "");
    EXPECT_EQ(runFileAt("other.frames/frame_000003.png", "out.mp4", "out.frames"), "");
    EXPECT_EQ(runFileAt("out.frames/frame_000003.png", "out.mp4", ""), "");  // --no-frames
    EXPECT_EQ(runFileAt("out.mp4.lock", "other.mp4", "out.frames"), "");
}

TEST(RunFiles, RefusesAnOutputNamingOne) {
    const std::vector<NamedOutput> outputs = {{"-o", "out.mp4"}, {"--frames-dir", "out.frames"}, {"--stats", "out.mp4.lock"}};
    try {
        checkOutputsAgainstRunFiles(outputs, "out.mp4", "out.frames");
        FAIL() << "--stats out.mp4.lock accepted";
    } catch (const UsageError& e) {
        EXPECT_STREQ(e.what(), "out.mp4.lock: --stats names the lock this run holds on -o (out.mp4); choose another name");
    }
    EXPECT_NO_THROW(checkOutputsAgainstRunFiles({{"-o", "out.mp4"}, {"--frames-dir", "out.frames"}, {"--stats", "s.json"}}, "out.mp4",
                                                "out.frames"));
}

}  // namespace
}  // namespace rf::farm
