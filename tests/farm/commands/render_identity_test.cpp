// Issue 46 #1: a frames directory's identity (RenderJob::identity()) holds every render option
// that changes a pixel, so that --resume cannot mix two renders. Every option render declares
// must be classified in renderOptionRoles(); each that changes pixels must change the identity.
#include <gtest/gtest.h>

#include <cstddef>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "farm/cli/cli.h"
#include "farm/cluster/render_job.h"
#include "farm/commands/render_options.h"

namespace rf::cli {
namespace {

/// The identity of a job made from these render options, as render makes it before the scene:
/// jobFromOptions, then the quality options over default settings. --fps reaches the timeline's
/// rate through anim::Timeline::fromScene in decideJob; here it is set the same way by hand.
std::string identityOf(const std::vector<std::string>& args) {
    ArgParser p("render");
    declareRenderOptions(p);
    std::vector<std::string> all = {"scene.json", "-o", "out.mp4"};
    all.insert(all.end(), args.begin(), args.end());
    p.parse(all);
    farm::RenderJob j = jobFromOptions(p, "scene.json", "");
    applyQualityOptions(p, j.settings);
    if (j.fpsOption > 0.0) j.timelineFps = j.fpsOption;
    return j.identity();
}

/// A value for each option that changes the picture, unlike its default.
const std::map<std::string, std::vector<std::string>> kSamples = {
    {"--size", {"64x36"}},
    {"--spp", {"4"}},
    {"--depth", {"3"}},
    {"--min-weight", {"0.5"}},
    {"--indirect", {"4"}},
    {"--bounce", {"5"}},
    {"--tonemap", {"reinhard"}},
    {"--exposure", {"1.5"}},
    {"--fps", {"24"}},
    {"--background", {"transparent"}},
    {"--frames-format", {"exr"}},
    {"--environment", {"sky.hdr"}},
    {"--environment-rotation", {"90"}},
    {"--environment-intensity", {"2"}},
    {"--ground", {"shadow"}},
    {"--animation", {"walk"}},
    {"--camera", {"1"}},
    {"--scene", {"1"}},
    {"--variant", {"red"}},
    {"--max-texture-size", {"512"}},
    {"--point-size", {"3"}},
};

TEST(RenderIdentity, EveryDeclaredOptionIsClassified) {
    ArgParser p("render");
    declareRenderOptions(p);
    std::map<std::string, int> roles;
    for (const OptionRole& r : renderOptionRoles()) {
        ++roles[r.option];
        EXPECT_TRUE(r.why && *r.why) << r.option << ": say why";
    }
    std::set<std::string> declared;
    for (const std::string& o : p.declared()) {
        declared.insert(o);
        EXPECT_EQ(roles[o], 1) << o << ": a render option must be classified once in renderOptionRoles() (render_options.cpp): "
                               << "part of RenderJob::identity() (it changes pixels), or not (and why)";
    }
    for (const auto& [option, n] : roles) EXPECT_TRUE(declared.count(option)) << option << ": classified but not declared";
}

TEST(RenderIdentity, EveryPictureOptionChangesTheIdentity) {
    const std::string plain = identityOf({});
    for (const OptionRole& r : renderOptionRoles()) {
        if (!r.identityKeys) continue;
        const auto sample = kSamples.find(r.option);
        ASSERT_NE(sample, kSamples.end()) << r.option << ": changes pixels; give it a sample value in kSamples";
        std::vector<std::string> args = {r.option};
        args.insert(args.end(), sample->second.begin(), sample->second.end());
        const std::string with = identityOf(args);
        EXPECT_NE(with, plain) << r.option << " " << sample->second[0] << " leaves the identity as it is";
        std::istringstream keys(r.identityKeys);
        for (std::string key; keys >> key;)
            EXPECT_NE(with.find("\"" + key + "\":"), std::string::npos) << r.option << ": no key " << key << " in " << with;
    }
}

// Issue 42: the camera and the scene are told apart by their number, not only by being given.
TEST(RenderIdentity, CameraAndSceneNumbersDiffer) {
    EXPECT_NE(identityOf({"--camera", "0"}), identityOf({"--camera", "1"}));
    EXPECT_NE(identityOf({"--camera", "0"}), identityOf({}));
    EXPECT_NE(identityOf({"--scene", "0"}), identityOf({"--scene", "1"}));
    EXPECT_NE(identityOf({"--scene", "0"}), identityOf({}));
}

TEST(RenderIdentity, OptionsThatChangeNoPixelLeaveItAlone) {
    const std::string plain = identityOf({});
    const std::vector<std::vector<std::string>> others = {
        {"--mode", "pixel"}, {"--frames", "0:3"},   {"--crf", "30"},        {"--preset", "slow"},
        {"--threads", "3"},  {"--timeout", "20"},   {"--chunk-frames", "4"}, {"--stats", "s.json"},
        {"--lossless"},      {"--poster", "p.png"}, {"--asset-root", "."},  {"--frames-dir", "elsewhere"},
    };
    for (const auto& args : others) EXPECT_EQ(identityOf(args), plain) << args[0];
}

// A field added to RenderSettings is either part of the identity or listed as changing no pixel
// in RenderJob::identity(); this size changes with any new field, to send its author there.
TEST(RenderIdentity, RenderSettingsFieldsAreAccountedFor) {
    EXPECT_EQ(sizeof(RenderSettings), std::size_t(60))
        << "RenderSettings changed: classify the new field in RenderJob::identity() (render_job.cpp), then update this size";
}

}  // namespace
}  // namespace rf::cli
