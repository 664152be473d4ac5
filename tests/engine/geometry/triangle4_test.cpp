// engine/geometry/triangle4.*: the four-wide pre-test may only rule out triangles the scalar watertight
// test misses, and a triangles-only scene (every BVH leaf packed) finds exactly the hits of
// testing every triangle in order, shared-edge ties included.
#include <gtest/gtest.h>

#include <random>

#include "tests/engine/engine_test_util.h"
#include "engine/geometry/triangle4.h"

using namespace rf;

namespace {

Triangle4 pack(const Vec3 (&v)[4][3]) {
    Triangle4 b{};
    for (int l = 0; l < 4; ++l)
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) b.v[k][a][l] = v[l][k][a];
    return b;
}

}  // namespace

TEST(Triangle4, PretestNeverRulesOutAScalarHit) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    size_t hits = 0, kept = 0, lanes = 0;
    for (int i = 0; i < 20000; ++i) {
        Vec3 v[4][3];
        for (auto& tri : v)
            for (Vec3& p : tri) p = Vec3(u(rng), u(rng), u(rng));
        if (i % 2) v[1][0] = v[0][1], v[1][1] = v[0][0];  // a shared edge between lanes 0 and 1
        Ray r;
        r.o = Vec3(3.f * u(rng), 3.f * u(rng), 3.f * u(rng));
        // Aim at a vertex or an edge's midpoint of lane 0 half of the time: the on-edge cases.
        const Vec3 target = (i % 4 == 0) ? v[0][0] : (i % 4 == 1) ? 0.5f * (v[0][0] + v[0][1]) : Vec3(u(rng), u(rng), u(rng));
        r.d = glm::normalize(target - r.o);
        const WatertightRay wr(r);
        const uint32_t m = watertightCandidates4(wr, pack(v));
        for (int l = 0; l < 4; ++l) {
            TriangleHit h;
            const bool hit = intersectTriangleWatertight(wr, v[l][0], v[l][1], v[l][2], kInf, h);
            hits += hit;
            kept += (m >> l) & 1u;
            ++lanes;
            ASSERT_TRUE(!hit || ((m >> l) & 1u)) << "ray " << i << " lane " << l;
        }
    }
    EXPECT_GT(hits, lanes / 20);    // the rays do hit
    EXPECT_LT(kept, lanes * 3 / 4);  // and the pre-test does rule triangles out
}

TEST(Triangle4, PackedLeavesFindTheHitsOfEveryTriangleInOrder) {
    // A bumpy grid only: every leaf holds triangles, so every leaf is packed. Half of the rays go
    // through grid vertices, where several triangles meet at the same t.
    Scene s = test::emptyScene();
    TriangleMesh g = test::gridMesh(40, 5.f);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    for (Vec3& p : g.positions) p.y = 0.1f * u(rng);
    s.geometry.meshes.push_back(g);
    s.build();
    ASSERT_TRUE(s.geometry.usesBvh());
    const std::vector<uint32_t>& slots = s.geometry.bvh().primIndex();
    size_t hits = 0, ties = 0;
    for (int i = 0; i < 20000; ++i) {
        Ray r;
        const Vec3 v = g.positions[size_t(rng() % g.positions.size())];
        const Vec3 target = (i % 2) ? v : Vec3(5.f * u(rng), 0.1f * u(rng), 5.f * u(rng));
        r.o = Vec3(8.f * u(rng), 2.f + 3.f * u(rng), 8.f * u(rng));
        r.d = glm::normalize(target - r.o);
        Hit h;
        const bool hb = s.geometry.intersect(r, h);
        // Reference: the same BVH walked slot by slot with the scalar test (the path before the
        // pre-test existed). The same triangle and t, bit for bit, shared-vertex ties included.
        const WatertightRay wr(r);
        const auto scalarLeaf = [&](uint32_t slot, float& tm, uint32_t& id) {
            const uint32_t t = slots[slot];
            TriangleHit th;
            if (!intersectTriangleWatertight(wr, g.positions[g.indices[3 * t]], g.positions[g.indices[3 * t + 1]],
                                             g.positions[g.indices[3 * t + 2]], tm, th))
                return false;
            tm = th.t;
            id = t;
            return true;
        };
        uint32_t id = 0;
        float tBest = kInf;
        const bool hr = s.geometry.bvh().traverseSlots(r, kInf, false, [&](uint32_t slot, float& tm) {
            const bool hit = scalarLeaf(slot, tm, id);
            if (hit) tBest = tm;
            return hit;
        });
        ASSERT_EQ(hb, hr) << "ray " << i;
        if (!hb) continue;
        ++hits;
        ASSERT_EQ(h.t, tBest) << "ray " << i;
        ASSERT_EQ(h.prim, id) << "ray " << i;
        // And brute force over every triangle agrees up to rounding of the order-dependent
        // acceptance (a nearer triangle within an ulp may lose to one tested earlier).
        float tAll = kInf;
        uint32_t idAll = 0;
        for (uint32_t slot = 0; slot < slots.size(); ++slot) scalarLeaf(slot, tAll, idAll);
        ASSERT_NEAR(h.t, tAll, 1e-5f * tAll) << "ray " << i;
        ties += h.prim != idAll;
        ASSERT_EQ(s.geometry.occluded(r, h.t * 1.001f), true) << "ray " << i;
        ASSERT_EQ(s.geometry.occluded(r, h.t * 0.999f), false) << "ray " << i;
    }
    EXPECT_GT(hits, 10000u);
    EXPECT_LT(ties, hits / 2);  // shared vertices tie, but most hits have one nearest triangle
}
