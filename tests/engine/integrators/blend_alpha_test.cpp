// alphaMode BLEND as glTF defines it, on a file Blender's own exporter wrote
// (tests/reference/make_blend_alpha.py): a pane whose alpha is in its base-colour texture only
// (0.25, 0.75 and 1 in thirds; the factor is 1). A blended surface covers its alpha's share of
// a ray and lets the rest on, unbent and untinted: over a transparent background the pixel's
// alpha is the texel's, and a shadow ray through the pane keeps 1 − alpha of the light. Before,
// only the alpha factor counted and this pane rendered (and shadowed) as opaque.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "engine/geometry/camera.h"
#include "engine/integrators/integrator.h"
#include "engine/integrators/light_eval.h"
#include "engine/integrators/material_gltf.h"
#include "engine/integrators/shading_frame.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/load/scene_loader.h"
#include "engine/materials/material_eval.h"
#include "engine/util/sampler.h"

using namespace rf;

namespace {

Scene paneScene() {
    DiskFileSource fs;
    LoadedScene loaded = loadScene(std::string(RAYFARM_SOURCE_DIR) + "/tests/reference/blend_alpha.gltf", fs, SceneOptions{});
    Scene s = std::move(loaded.scene);
    useGltfCamera(s, 0);
    return s;
}

int materialNamed(const Scene& s, const std::string& name) {
    for (size_t i = 0; i < s.materials.size(); ++i)
        if (s.materials[i].name == name) return int(i);
    return -1;
}

/// The pane's alpha where r first meets it (unfiltered, as the file's texel), or -1 where r's
/// first hit is something else.
float paneAlpha(const Scene& s, int pane, const Ray& r, SurfaceInteraction* at = nullptr) {
    Hit hit;
    if (!s.geometry.intersect(r, hit)) return -1.f;
    const SurfaceInteraction si = s.geometry.interaction(r, hit);
    if (si.material != pane) return -1.f;
    if (at) *at = si;
    return materialAlpha(s.textures, s.materials[size_t(pane)], si.uv, si.uv1);
}

/// Whether the ray from just past si along d meets anything more.
bool meetsMore(const Scene& s, const SurfaceInteraction& si, const Vec3& d) {
    Ray on;
    on.o = si.p + 1e-3f * d;
    on.d = d;
    Hit hit;
    return s.geometry.intersect(on, hit);
}

/// The pane's three alphas, and which of them a texel's is (-1: a texel between two thirds).
constexpr float levels[3] = {0.25f, 0.75f, 1.f};
int levelOf(float a) {
    for (int k = 0; k < 3; ++k)
        if (std::abs(a - levels[k]) < 1e-3f) return k;
    return -1;
}

}  // namespace

TEST(BlendAlpha, TheFileBlendsWithItsTextureAlphaOnly) {
    const Scene s = paneScene();
    const int pane = materialNamed(s, "blended pane");
    ASSERT_GE(pane, 0);
    const Material& m = s.materials[size_t(pane)];
    EXPECT_EQ(m.alphaMode, AlphaMode::Blend);
    EXPECT_EQ(m.alpha, 1.f) << "the alpha must come from the texture alone for this test to mean anything";
    EXPECT_GE(m.baseColorTexture, 0);
    EXPECT_EQ(m.transmission, 0.f);
}

TEST(BlendAlpha, OverATransparentBackgroundThePixelAlphaIsTheTexelAlpha) {
    Scene s = paneScene();
    s.transparentBackground = true;
    const int pane = materialNamed(s, "blended pane");
    ASSERT_GE(pane, 0);
    const int w = 160, h = 90;
    const CameraRays rays(s.camera, w, h);
    const std::unique_ptr<Integrator> tracer = makeIntegrator(s, RenderSettings{});
    int counted[3] = {0, 0, 0}, wrong = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Ray r = rays.generate(x + 0.5f, y + 0.5f);
            SurfaceInteraction si;
            const float a = paneAlpha(s, pane, r, &si);
            // The pane over nothing (above the horizon): the pixel's alpha is the pane's alone.
            if (a < 0.f || meetsMore(s, si, r.d)) continue;
            const int level = levelOf(a);
            if (level < 0) continue;  // a texel between two thirds
            RayStats st;
            float coverage = -1.f;
            tracer->Li(r, kNoSampleSeed, st, &coverage);
            ++counted[level];
            if (std::abs(coverage - a) > 0.02f) {
                if (++wrong <= 5) ADD_FAILURE() << "pixel (" << x << ", " << y << "): alpha " << coverage << ", texel " << a;
            }
        }
    for (int k = 0; k < 3; ++k) EXPECT_GT(counted[k], 50) << "too few pixels of the pane at alpha " << levels[k];
    EXPECT_EQ(wrong, 0);
}

TEST(BlendAlpha, AShadowRayThroughThePaneKeepsOneMinusItsAlphaUntinted) {
    const Scene s = paneScene();
    const int pane = materialNamed(s, "blended pane");
    ASSERT_GE(pane, 0);
    ASSERT_FALSE(s.lights.empty());
    const Light& sun = s.lights[0];
    int counted[3] = {0, 0, 0}, wrong = 0;
    // Floor points on a grid behind the pane, each seen from straight above.
    for (float x = -3.f; x <= 3.f; x += 0.1f)
        for (float z = -4.f; z <= 4.f; z += 0.1f) {
            Ray down;
            down.o = Vec3(x, 10.f, z);
            down.d = Vec3(0.f, -1.f, 0.f);
            Hit hit;
            if (!s.geometry.intersect(down, hit)) continue;
            const SurfaceInteraction si = s.geometry.interaction(down, hit);
            if (s.materials[size_t(si.material)].name != "floor") continue;
            const ShadingFrame frame = shadingFrame(s, si, -down.d);
            LightIncidence li;
            if (!lightIncidence(sun, si.p, frame.ns, li)) continue;
            // What lies towards the sun: the pane first, and nothing past it.
            Ray toSun;
            toSun.o = si.p + 1e-3f * li.dir;
            toSun.d = li.dir;
            SurfaceInteraction ps;
            const float a = paneAlpha(s, pane, toSun, &ps);
            if (a < 0.f || meetsMore(s, ps, li.dir)) continue;
            const int level = levelOf(a);
            if (level < 0) continue;
            ShadowRays shadows(s, si, frame, nullptr);
            RayStats st;
            const Color t = shadows.transmittance(sun, li, false, st, true);
            ++counted[level];
            const float want = 1.f - a;
            if (std::abs(t.r - want) > 1e-3f || std::abs(t.g - want) > 1e-3f || std::abs(t.b - want) > 1e-3f) {
                if (++wrong <= 5)
                    ADD_FAILURE() << "floor (" << x << ", " << z << "): light kept (" << t.r << ", " << t.g << ", " << t.b
                                  << "), want " << want << " (pane alpha " << a << ")";
            }
        }
    for (int k = 0; k < 3; ++k) EXPECT_GT(counted[k], 20) << "too few floor points behind the pane at alpha " << levels[k];
    EXPECT_EQ(wrong, 0);
}
