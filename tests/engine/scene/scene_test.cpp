// Scene::build's sphere checks: which spheres nothing else reaches into (the inside-sphere fast
// path), found through the BVH rather than over every pair.
#include <gtest/gtest.h>

#include <random>

#include "engine/scene/scene.h"

using namespace rf;

namespace {

// The rule, over every pair, in double: no plane cuts the sphere and no other sphere overlaps
// it (touching is fine).
std::vector<uint8_t> aloneByEveryPair(const Scene& s) {
    std::vector<uint8_t> out(s.geometry.spheres.size(), 1);
    for (size_t i = 0; i < s.geometry.spheres.size(); ++i) {
        const Sphere& a = s.geometry.spheres[i];
        for (const Plane& pl : s.geometry.planes)
            if (std::abs(glm::dot(DVec3(pl.n), DVec3(a.center)) + double(pl.d)) < double(a.radius)) out[i] = 0;
        for (size_t j = 0; j < s.geometry.spheres.size(); ++j)
            if (j != i && glm::length(DVec3(a.center) - DVec3(s.geometry.spheres[j].center)) <
                              double(a.radius) + s.geometry.spheres[j].radius)
                out[i] = 0;
    }
    return out;
}

std::vector<uint8_t> aloneFlags(const Scene& s) {
    std::vector<uint8_t> out;
    for (size_t i = 0; i < s.geometry.spheres.size(); ++i) out.push_back(s.geometry.sphereAlone(i));
    return out;
}

}  // namespace

TEST(Scene, AloneSpheresMatchTheEveryPairRule) {
    std::mt19937 rng(30);
    std::uniform_real_distribution<float> pos(-40.f, 40.f), rad(0.05f, 3.f);
    for (int round = 0; round < 4; ++round) {
        Scene s;
        for (int i = 0; i < 1500; ++i)
            s.geometry.spheres.push_back(Sphere{Vec3(pos(rng), pos(rng), pos(rng)), rad(rng), 0});
        // Touching exactly (alone), a hair closer (not), a big one holding small ones, two coincident.
        s.geometry.spheres.push_back(Sphere{Vec3(100.f, 0.f, 0.f), 1.f, 0});
        s.geometry.spheres.push_back(Sphere{Vec3(102.f, 0.f, 0.f), 1.f, 0});
        s.geometry.spheres.push_back(Sphere{Vec3(100.f, 10.f, 0.f), 1.f, 0});
        s.geometry.spheres.push_back(Sphere{Vec3(101.99999f, 10.f, 0.f), 1.f, 0});
        s.geometry.spheres.push_back(Sphere{Vec3(0.f, 200.f, 0.f), 50.f, 0});
        s.geometry.spheres.push_back(Sphere{Vec3(30.f, 200.f, 0.f), 0.5f, 0});
        s.geometry.spheres.push_back(Sphere{Vec3(-300.f, 0.f, 0.f), 2.f, 0});
        s.geometry.spheres.push_back(Sphere{Vec3(-300.f, 0.f, 0.f), 2.f, 0});
        if (round % 2) s.geometry.planes.push_back(Plane{Vec3(0.f, 1.f, 0.f), 5.f, 0});
        s.build();
        const std::vector<uint8_t> want = aloneByEveryPair(s), got = aloneFlags(s);
        ASSERT_EQ(got.size(), want.size());
        for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(got[i], want[i]) << "round " << round << " sphere " << i;
        const size_t n = s.geometry.spheres.size();
        EXPECT_TRUE(got[n - 8] && got[n - 7]);    // touching
        EXPECT_FALSE(got[n - 6] || got[n - 5]);  // overlapping by 1e-5
        EXPECT_FALSE(got[n - 4] || got[n - 3]);  // one inside the other
        EXPECT_FALSE(got[n - 2] || got[n - 1]);  // coincident
    }
}

// 2·10⁵ touching spheres (a lattice of spacing 2, radius 1): every one alone; one more sphere
// poking into a single lattice sphere takes that one and itself out. Every pair would be 4·10¹⁰
// distance tests (10⁵ spheres took 37 s to load).
TEST(Scene, AloneSpheresOfALargeLatticeAreFoundPerSphere) {
    Scene s;
    for (int z = 0; z < 20; ++z)
        for (int y = 0; y < 100; ++y)
            for (int x = 0; x < 100; ++x) s.geometry.spheres.push_back(Sphere{Vec3(2.f * x, 2.f * y, 2.f * z), 1.f, 0});
    const size_t poked = 5 + 100 * (7 + 100 * 3);
    s.geometry.spheres.push_back(Sphere{s.geometry.spheres[poked].center + Vec3(0.f, 0.f, 0.5f), 0.25f, 0});
    s.build();
    size_t alone = 0;
    for (size_t i = 0; i < s.geometry.spheres.size(); ++i) alone += s.geometry.sphereAlone(i);
    EXPECT_EQ(alone, s.geometry.spheres.size() - 2);
    EXPECT_FALSE(s.geometry.sphereAlone(poked));
    EXPECT_FALSE(s.geometry.sphereAlone(s.geometry.spheres.size() - 1));
}
