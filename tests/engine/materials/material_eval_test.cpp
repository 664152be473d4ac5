// The material lookup shared by shading and the alpha-MASK test during traversal.
#include <gtest/gtest.h>

#include "tests/engine/engine_test_util.h"
#include "engine/materials/material_eval.h"

namespace rf {
namespace {

/// A 4×4-quad floor at y = 0 over [−1, 1]² (32 triangles: traversal goes through the BVH), with
/// TEXCOORD_0 = ((x + 1)/2, (z + 1)/2) and TEXCOORD_1 = TEXCOORD_0 + (0.5, 0). Its MASK material
/// reads a 2×1 texture whose left texel is opaque and right texel fully transparent.
Scene maskedFloor(const TextureTransform& transform) {
    Scene s = test::emptyScene();
    TriangleMesh m = test::gridMesh(4, 1.f, 0);
    for (const Vec3& p : m.positions) {
        m.uvs.emplace_back((p.x + 1.f) / 2.f, (p.z + 1.f) / 2.f);
        m.uvs1.push_back(m.uvs.back() + Vec2(0.5f, 0.f));
    }
    s.geometry.meshes.push_back(m);
    Texture t;
    t.width = 2;
    t.height = 1;
    t.texels = {Vec4(1.f, 1.f, 1.f, 1.f), Vec4(1.f, 1.f, 1.f, 0.f)};
    t.filter = Filter::Nearest;
    s.textures.push_back(t);
    Material& mat = s.materials[0];
    mat.alphaMode = AlphaMode::Mask;
    mat.alphaCutoff = 0.5f;
    mat.baseColorTexture = 0;
    mat.baseColorTransform = transform;
    s.build();
    return s;
}

/// Whether a ray straight down onto the floor at (x, ·, 0.1) finds it.
bool hitsAt(const Scene& s, float x) {
    Ray r;
    r.o = Vec3(x, 1.f, 0.1f);
    r.d = Vec3(0.f, -1.f, 0.f);
    Hit h;
    return s.geometry.intersect(r, h);
}

TEST(MaterialEval, AlphaMaskDuringTraversalAppliesTheTextureTransform) {
    TextureTransform shift;
    shift.offset = Vec2(0.5f, 0.f);  // u 0.25 reads the transparent texel, u 0.75 the opaque one
    const Scene s = maskedFloor(shift);
    ASSERT_TRUE(s.geometry.usesBvh());
    EXPECT_FALSE(hitsAt(s, -0.5f));  // raw u = 0.25: opaque, but the shifted lookup is transparent
    EXPECT_TRUE(hitsAt(s, 0.5f));    // raw u = 0.75: transparent, shifted (1.25 → 0.25) opaque
}

TEST(MaterialEval, AlphaMaskDuringTraversalReadsTheNamedTexCoordSet) {
    TextureTransform second;
    second.texCoord = 1;  // TEXCOORD_1 is TEXCOORD_0 moved by half a texture
    const Scene s = maskedFloor(second);
    EXPECT_FALSE(hitsAt(s, -0.5f));
    EXPECT_TRUE(hitsAt(s, 0.5f));
}

TEST(MaterialEval, TraversalAndShadingAgreeOnWhatIsCutOut) {
    TextureTransform t;
    t.offset = Vec2(0.3f, 0.f);
    t.rotation = 0.f;
    t.scale = Vec2(1.7f, 1.f);
    const Scene s = maskedFloor(t);
    Scene opaque = maskedFloor(t);
    opaque.materials[0].alphaMode = AlphaMode::Opaque;
    opaque.build();
    int cut = 0, kept = 0;
    for (int i = 0; i < 200; ++i) {
        const float x = -0.99f + 1.98f * (i + 0.5f) / 200.f;
        Ray r;
        r.o = Vec3(x, 1.f, 0.1f);
        r.d = Vec3(0.f, -1.f, 0.f);
        Hit h;
        ASSERT_TRUE(opaque.geometry.intersect(r, h));
        const SurfaceInteraction si = opaque.geometry.interaction(r, h);
        float alpha = 0.f;
        baseColor(opaque, si, &alpha);  // what shading sees at the same point
        const bool shown = alpha >= s.materials[0].alphaCutoff;
        EXPECT_EQ(hitsAt(s, x), shown) << "x = " << x;
        (shown ? kept : cut)++;
    }
    EXPECT_GT(cut, 20);  // both sides of the cut-out occur along the line
    EXPECT_GT(kept, 20);
}

}  // namespace
}  // namespace rf
