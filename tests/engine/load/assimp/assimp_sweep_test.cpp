// Every OBJ, STL, PLY, FBX, COLLADA and 3MF file of Debian's assimp-testmodels, as a default
// still (the bare model's framing, lights and environment) at a small size: it renders with the
// model in the picture and lit, or it is refused in one line naming the file. Never a crash, a
// hang, a sanitizer report, a non-finite pixel or a black model. Built with AddressSanitizer
// and UBSan by tests/run.sh (build-asan), and plainly in the main build; the pictures go to
// test-output/assimp-sweep/ to be looked at.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "engine/util/image.h"
#include "engine/util/model_path.h"
#include "engine/load/model_inspect.h"
#include "engine/load/scene_loader.h"
#include "engine/integrators/render.h"

using namespace rf;
namespace fs = std::filesystem;

namespace {

const std::string kRoot = "/usr/share/assimp/models/";

std::vector<std::string> sweepFiles() {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(kRoot))
        if (e.is_regular_file() && isAssimpPath(e.path().string())) out.push_back(e.path().string());
    std::sort(out.begin(), out.end());
    return out;
}

struct Result {
    bool rendered = false;
    std::string message;
    double coverage = 0.0;  ///< share of pixels whose camera ray meets the model
    double lit = 0.0;       ///< mean linear luminance over those pixels
    uint64_t triangles = 0; ///< triangles drawn (0: points and lines only)
};

/// Files whose picture shows nothing for a reason in the file, not in rayfarm.
const std::map<std::string, const char*> kKnown = {
    {"PLY_pond.0.ply", "its 70,051 points span ±3.4e38, the float range (garbage coordinates): at any framing the dots are "
                       "lost between points 10^38 apart"},
};

Result renderStill(const std::string& path, const std::string& png) {
    Result r;
    DiskFileSource files;
    SceneOptions opts;
    opts.width = 96;
    opts.height = 54;
    // Textures may reach across the package's folders (teapots.DAE uses the LWO folder's); a
    // texture outside the asset root is refused in the unit tests and assimp_models_test.sh.
    opts.assets.root = kRoot;
    // Points and lines 12 pixels wide at 640×360, so a point cloud's dots show at 96×54 too.
    opts.assets.pointSize = 12.f;
    try {
        LoadedScene loaded = loadScene(path, files, opts);
        r.triangles = inspectModel(path, files, opts.assets).drawnTriangles;
        const Scene& scene = loaded.scene;
        const RenderSettings& s = scene.settings;
        RayStats stats;
        const Image img = renderFrame(scene, {scene.camera, s}, 0, 2, stats);
        const CameraRays rays(scene.camera, s.width, s.height);
        size_t covered = 0;
        double sum = 0.0;
        for (int y = 0; y < s.height; ++y)
            for (int x = 0; x < s.width; ++x) {
                const float* p = img.data() + 3 * (size_t(y) * size_t(s.width) + size_t(x));
                for (int c = 0; c < 3; ++c)
                    if (!std::isfinite(p[c])) ADD_FAILURE() << path << ": non-finite pixel at " << x << "," << y;
                Hit hit;
                if (!scene.geometry.intersect(rays.generate(float(x) + 0.5f, float(y) + 0.5f), hit)) continue;
                ++covered;
                sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            }
        EXPECT_EQ(stats.nonFinite, 0u) << path << ": the tracer replaced non-finite samples";
        r.rendered = true;
        r.coverage = double(covered) / (double(s.width) * s.height);
        r.lit = covered ? sum / double(covered) : 0.0;
        writePng(png, s.width, s.height, toRgb8(img, s));
    } catch (const InputError& e) {
        r.message = e.what();
        EXPECT_EQ(r.message.rfind(path, 0), 0u) << "the message must start with the file: " << r.message;
        EXPECT_EQ(r.message.find('\n'), std::string::npos) << "one line: " << r.message;
    }
    return r;
}

}  // namespace

TEST(AssimpSweep, EveryTestModelRendersLitOrIsRefusedInOneLine) {
    const std::vector<std::string> files = sweepFiles();
    ASSERT_GE(files.size(), 60u) << "assimp-testmodels is not installed (tests/install-deps.sh)";
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/assimp-sweep";
    fs::create_directories(out);
    std::map<std::string, std::pair<int, int>> byFormat;  // extension -> (rendered, refused)
    int rendered = 0, refused = 0;
    for (const std::string& path : files) {
        std::string name = path.substr(kRoot.size());
        std::replace(name.begin(), name.end(), '/', '_');
        const Result r = renderStill(path, out + "/" + name + ".png");
        auto& [ok, no] = byFormat[lowerExtension(path)];
        if (r.rendered) {
            ++rendered, ++ok;
            std::printf("%-60s rendered: %4.1f%% of the picture, mean %.3f\n", path.c_str() + kRoot.size(), 100 * r.coverage, r.lit);
            if (const auto known = kKnown.find(name); known != kKnown.end()) {
                std::printf("%-60s   (allowed: %s)\n", "", known->second);
                continue;
            }
            // The default framing puts the whole model in the picture: a model of triangles
            // drawn in under 0.1% of it (a column of 64 boxes one box wide covers 0.27%), one of
            // points or lines in no pixel, or a black one, is a failure.
            EXPECT_GE(r.coverage, r.triangles ? 0.001 : 1e-9) << path << ": the model is not in the picture";
            EXPECT_GT(r.lit, 0.01) << path << ": the model is black";
        } else {
            ++refused, ++no;
            std::printf("%-60s refused: %s\n", path.c_str() + kRoot.size(), r.message.c_str());
        }
    }
    for (const auto& [ext, counts] : byFormat) std::printf("%s: %d rendered, %d refused\n", ext.c_str(), counts.first, counts.second);
    std::printf("%d files: %d rendered, %d refused; pictures in %s\n", int(files.size()), rendered, refused, out.c_str());
    // Each format renders most of its files (the broken ones among them may be refused).
    for (const auto& [ext, counts] : byFormat) EXPECT_GT(counts.first, counts.second) << ext;
}
