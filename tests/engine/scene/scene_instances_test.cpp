// The scene's two-level acceleration structure (engine/geometry/scene_instance.h, scene_accel.cpp): a
// static set, rigid meshes moved by their node's matrix without touching their trees, a
// deforming mesh refitted from its anchor pose's tree; mirrored poses turning the facet normal.
#include <gtest/gtest.h>

#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "tests/engine/engine_test_util.h"
#include "engine/load/gltf/gltf_geometry.h"
#include "engine/geometry/skinning.h"

namespace rf {
namespace {

/// mesh on (model 0, node): a moving mesh with its object-space copy.
TriangleMesh onNode(TriangleMesh m, int node) {
    m.model = 0;
    m.node = node;
    m.objectPositions = m.positions;
    m.objectNormals = m.normals;
    return m;
}

/// A floor grid that never moves, a sphere on node 0 and a smaller one on node 1 (rigid), and a
/// morphed grid on node 2 (deforming: one target lifts its middle).
Scene mixedScene() {
    Scene s = test::emptyScene();
    s.geometry.meshes.push_back(test::gridMesh(12, 3.f));
    s.geometry.meshes.push_back(onNode(test::uvSphere(12, 16, 0.6f, Vec3(0.f), true), 0));
    s.geometry.meshes.push_back(onNode(test::uvSphere(8, 12, 0.3f, Vec3(0.f), true), 1));
    TriangleMesh bump = onNode(test::gridMesh(10, 1.f), 2);
    std::vector<Vec3> lift(bump.positions.size());
    for (size_t i = 0; i < lift.size(); ++i) lift[i] = Vec3(0.f, 1.f - glm::length(bump.positions[i]), 0.f);
    bump.morphPositions.push_back(lift);
    s.geometry.meshes.push_back(bump);
    SceneGraph g;
    g.nodes.resize(3);
    s.geometry.models.push_back(g);
    s.build();
    return s;
}

std::vector<DMat4> poseAt(double a) {
    const DMat4 m0 = glm::rotate(glm::translate(DMat4(1.0), DVec3(1.2, 0.8 + 0.3 * a, -0.5)), a, DVec3(0.3, 1.0, 0.2)) *
                     glm::scale(DMat4(1.0), DVec3(1.0, 1.6, 0.7));
    const DMat4 m1 = glm::translate(DMat4(1.0), DVec3(-1.5 + a, 0.5, 1.0));
    const DMat4 m2 = glm::translate(DMat4(1.0), DVec3(0.0, 0.05, -1.8));
    return {m0, m1, m2};
}

/// The same geometry as `posed`, baked: every mesh static, so one tree over render space.
Scene baked(const Scene& posed) {
    Scene s = test::emptyScene();
    for (TriangleMesh m : posed.geometry.meshes) {
        m.node = -1;
        m.model = -1;
        m.objectPositions.clear();
        m.morphPositions.clear();
        s.geometry.meshes.push_back(m);
    }
    s.build();
    return s;
}

TEST(SceneInstances, RigidMeshesAndAMorphedOneGetTheirOwnTrees) {
    Scene s = mixedScene();
    ASSERT_TRUE(s.geometry.twoLevel());
    ASSERT_EQ(s.geometry.instances().size(), 4u);
    EXPECT_EQ(s.geometry.instances()[0].kind, SceneInstance::Kind::Static);
    EXPECT_EQ(s.geometry.instances()[1].kind, SceneInstance::Kind::Rigid);
    EXPECT_TRUE(s.geometry.instances()[1].transformed);
    EXPECT_EQ(s.geometry.instances()[3].kind, SceneInstance::Kind::Deforming);
    EXPECT_FALSE(s.geometry.instances()[3].transformed);
    // A scene where nothing moves is one tree, with no top level.
    EXPECT_FALSE(baked(s).geometry.twoLevel());
}

TEST(SceneInstances, PosedInstancesHitWhatTheBakedGeometryHits) {
    Scene s = mixedScene();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    int hits = 0, instanced = 0;
    for (double a : {0.0, 0.7, 2.1}) {
        s.geometry.applyNodeTransforms(0, poseAt(a), {{}, {}, {0.8}});
        const Scene ref = baked(s);
        for (int i = 0; i < 4000; ++i) {
            Ray r{Vec3(4.f * u(rng), 3.f + u(rng), 4.f * u(rng)), glm::normalize(Vec3(u(rng), -1.f, u(rng)))};
            r.tMax = 100.f;
            Hit h, hr;
            const bool got = s.geometry.intersect(r, h), want = ref.geometry.intersect(r, hr);
            ASSERT_EQ(got, want) << "pose " << a << " ray " << i;
            if (!got) continue;
            ++hits;
            // Scene-wide prim ids are the same in both (meshes in the same order).
            EXPECT_EQ(h.prim, hr.prim) << "pose " << a << " ray " << i;
            EXPECT_NEAR(h.t, hr.t, 2e-5f * hr.t) << "pose " << a << " ray " << i;
            instanced +=
                s.geometry.instances()[1].prims.front() <= h.prim && h.prim <= s.geometry.instances()[1].prims.back();
            EXPECT_EQ(s.geometry.occluded(r, 100.f), ref.geometry.occluded(r, 100.f));
            const SurfaceInteraction si = s.geometry.interaction(r, h), sr = ref.geometry.interaction(r, hr);
            EXPECT_NEAR(glm::length(si.p - sr.p), 0.f, 1e-4f);
            EXPECT_GE(glm::dot(si.ng, sr.ng), 0.999f);
        }
    }
    EXPECT_GT(hits, 3000);
    EXPECT_GT(instanced, 100);  // the rigid sphere, moved by its matrix, was hit
}

TEST(SceneInstances, CameraPacketsFindWhatSingleRaysFind) {
    Scene s = mixedScene();
    s.geometry.applyNodeTransforms(0, poseAt(0.7), {{}, {}, {0.5}});
    std::vector<Ray> packet;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            Ray r{Vec3(0.f, 4.f, 6.f), glm::normalize(Vec3(-0.4f + 0.1f * x, -0.6f - 0.02f * y, -1.f))};
            r.tMax = 100.f;
            packet.push_back(r);
        }
    std::vector<Hit> hits(packet.size());
    bool met[Bvh::kPacketMax];
    s.geometry.intersectPacket(packet.data(), int(packet.size()), hits.data(), met);
    int found = 0, ties = 0;
    for (size_t i = 0; i < packet.size(); ++i) {
        Hit alone;
        ASSERT_EQ(met[i], s.geometry.intersect(packet[i], alone)) << i;
        if (!met[i]) continue;
        ++found;
        // The same t; the same primitive unless two tie there (the grid's diagonals: the packet
        // and the lone ray may visit the two halves of a quad in either order).
        EXPECT_EQ(hits[i].t, alone.t) << i;
        ties += hits[i].prim != alone.prim;
    }
    EXPECT_GT(found, 32);
    EXPECT_LT(ties, found / 4);
}

TEST(SceneInstances, PosingNeverTouchesTheStaticOrRigidTrees) {
    Scene s = mixedScene();
    auto boxes = [](const Bvh& b) {
        std::vector<float> out;
        for (const BvhNode& n : b.nodes())
            out.insert(out.end(), {n.box.lo.x, n.box.lo.y, n.box.lo.z, n.box.hi.x, n.box.hi.y, n.box.hi.z});
        return out;
    };
    const std::vector<float> staticBefore = boxes(s.geometry.instances()[0].bvh),
                             rigidBefore = boxes(s.geometry.instances()[1].bvh);
    const std::vector<float> deformBefore = boxes(s.geometry.instances()[3].bvh);
    for (double a : {0.3, 1.9}) {
        s.geometry.applyNodeTransforms(0, poseAt(a), {{}, {}, {1.0}});
        EXPECT_EQ(boxes(s.geometry.instances()[0].bvh), staticBefore);
        EXPECT_EQ(boxes(s.geometry.instances()[1].bvh), rigidBefore);  // object space: the matrix moves it
        EXPECT_NE(boxes(s.geometry.instances()[3].bvh), deformBefore);  // refitted to the lifted grid
    }
}

TEST(SceneInstances, ANodeScaledToNothingHidesItsInstance) {
    Scene s = mixedScene();
    std::vector<DMat4> pose = poseAt(0.0);
    pose[0] = glm::scale(DMat4(1.0), DVec3(0.0));
    s.geometry.applyNodeTransforms(0, pose, {{}, {}, {0.0}});
    EXPECT_TRUE(s.geometry.instances()[1].hidden);
    Ray r{Vec3(1.2f, 5.f, -0.5f), Vec3(0.f, -1.f, 0.f)};
    Hit h;
    ASSERT_TRUE(s.geometry.intersect(r, h));
    EXPECT_LT(h.prim, s.geometry.meshes[0].triangleCount());  // through where the sphere was, onto the floor
}

/// One triangle in z = 0, front +z (counter-clockwise seen from +z), on node 0.
Scene triangleOnNode(bool skinned) {
    Scene s = test::emptyScene();
    TriangleMesh m;
    m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    m.normals = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1)};
    m.indices = {0, 1, 2};
    m = onNode(m, 0);
    SceneGraph g;
    g.nodes.resize(1);
    if (skinned) {
        m.skin = 0;
        m.influences = 1;
        m.skinJoints = {0, 0, 0};
        m.skinWeights = {1.f, 1.f, 1.f};
        g.skins.push_back(Skin{"", {0}, {DMat4(1.0)}});
    }
    s.geometry.models.push_back(g);
    s.geometry.meshes.push_back(m);
    s.build();
    return s;
}

TEST(SceneInstances, AMirroringPoseTurnsTheFacetNormalWithTheFaces) {
    for (bool skinned : {false, true}) {
        Scene s = triangleOnNode(skinned);
        // x mirrored: the triangle lies in the same plane, its front still faces +z, but its
        // corners now run clockwise seen from there.
        s.geometry.applyNodeTransforms(0, {glm::scale(DMat4(1.0), DVec3(-1.0, 1.0, 1.0))});
        for (float dz : {-1.f, 1.f}) {
            Ray r{Vec3(-0.2f, 0.2f, -3.f * dz), Vec3(0.f, 0.f, dz)};
            Hit h;
            ASSERT_TRUE(s.geometry.intersect(r, h)) << skinned;
            const SurfaceInteraction si = s.geometry.interaction(r, h);
            EXPECT_NEAR(si.ng.z, 1.f, 1e-6f) << (skinned ? "skinned" : "rigid") << ", ray from " << -dz;
            EXPECT_NEAR(si.ns.z, 1.f, 1e-6f) << (skinned ? "skinned" : "rigid");
        }
        // Back to the rest pose: not mirrored, the same front.
        s.geometry.applyNodeTransforms(0, {DMat4(1.0)});
        Ray r{Vec3(0.2f, 0.2f, 3.f), Vec3(0.f, 0.f, -1.f)};
        Hit h;
        ASSERT_TRUE(s.geometry.intersect(r, h));
        EXPECT_NEAR(s.geometry.interaction(r, h).ng.z, 1.f, 1e-6f);
    }
}

TEST(SceneInstances, MorphTargetsMoveTangentsToo) {
    TriangleMesh m;
    m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    m.normals = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1)};
    m.tangents = {Vec4(1, 0, 0, -1), Vec4(1, 0, 0, -1), Vec4(1, 0, 0, -1)};
    m.indices = {0, 1, 2};
    m.morphPositions = {std::vector<Vec3>(3, Vec3(0.f))};
    m.morphNormals = {{}};
    m.morphTangents = {std::vector<Vec3>(3, Vec3(-1.f, 1.f, 0.f))};  // at weight 1: +y
    // Baked by the loader at weight 0.5: (0.5, 0.5, 0) normalized, w kept.
    TriangleMesh baked = m;
    ASSERT_TRUE(gltf::placePrimitive(baked, DMat4(1.0), {0.5}));
    EXPECT_NEAR(baked.tangents[0].x, std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(baked.tangents[0].y, std::sqrt(0.5f), 1e-6f);
    EXPECT_EQ(baked.tangents[0].w, -1.f);
    // Posed per frame (a moving mesh) at weight 1: +y.
    TriangleMesh moving = m;
    moving.objectPositions = m.positions;
    moving.objectNormals = m.normals;
    moving.objectTangents = m.tangents;
    const std::vector<double> w = {1.0};
    poseMesh(moving, DMat4(1.0), nullptr, &w);
    EXPECT_NEAR(moving.tangents[1].y, 1.f, 1e-6f);
    EXPECT_NEAR(moving.tangents[1].x, 0.f, 1e-6f);
    EXPECT_EQ(moving.tangents[1].w, -1.f);
}

/// Rays down onto the morphed grid (and what lies around it) hit as in the baked geometry.
void expectHitsAsBaked(const Scene& posed, unsigned seed) {
    const Scene ref = baked(posed);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    for (int i = 0; i < 2000; ++i) {
        const Ray r{Vec3(u(rng), 3.f, -1.8f + u(rng)), glm::normalize(Vec3(0.1f * u(rng), -1.f, 0.1f * u(rng)))};
        Hit h, hr;
        const bool met = posed.geometry.intersect(r, h);
        ASSERT_EQ(met, ref.geometry.intersect(r, hr)) << i;
        if (met) {
            EXPECT_NEAR(h.t, hr.t, 1e-4f) << i;
        }
    }
}

/// A deforming grid whose one morph target lifts the middle, anchored at weights k / 4.
SceneGeometry::PoseAnchor anchorAt(int k) {
    SceneGeometry::PoseAnchor a;
    a.clip = 0;
    a.index = k;
    a.pose = [k](std::vector<DMat4>& n, std::vector<std::vector<double>>& w) {
        n = poseAt(0.0);
        w = {{}, {}, {0.25 * k}};
    };
    return a;
}

TEST(SceneInstances, ADeformingTreeIsItsAnchorsRefittedWhateverCameBefore) {
    Scene direct = mixedScene(), after = mixedScene();
    const SceneGeometry::PoseAnchor a1 = anchorAt(1), a3 = anchorAt(3);
    // `after` has seen another anchor and pose first; `direct` goes straight to the frame.
    after.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.7}}, &a3);
    EXPECT_EQ(after.geometry.lastUpdateCost().anchorsBuilt, 1);
    after.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.3}}, &a1);
    direct.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.3}}, &a1);
    const Bvh& x = after.geometry.instances()[3].bvh;
    const Bvh& y = direct.geometry.instances()[3].bvh;
    EXPECT_EQ(x.primIndex(), y.primIndex());
    ASSERT_EQ(x.nodes().size(), y.nodes().size());
    for (size_t i = 0; i < x.nodes().size(); ++i) {
        EXPECT_EQ(x.nodes()[i].box.lo, y.nodes()[i].box.lo);
        EXPECT_EQ(x.nodes()[i].box.hi, y.nodes()[i].box.hi);
    }
    // A second frame near anchor 1 reuses its tree: nothing built, and it still hits right.
    direct.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.2}}, &a1);
    EXPECT_EQ(direct.geometry.lastUpdateCost().anchorsBuilt, 0);
    expectHitsAsBaked(direct, 3);
}

/// Two trees alike in every box, binary and 4-wide, and in their leaves' order.
void expectSameTree(const Bvh& x, const Bvh& y) {
    EXPECT_EQ(x.primIndex(), y.primIndex());
    ASSERT_EQ(x.nodes().size(), y.nodes().size());
    for (size_t i = 0; i < x.nodes().size(); ++i) {
        EXPECT_EQ(x.nodes()[i].box.lo, y.nodes()[i].box.lo) << i;
        EXPECT_EQ(x.nodes()[i].box.hi, y.nodes()[i].box.hi) << i;
    }
    ASSERT_EQ(x.nodes4().size(), y.nodes4().size());
    for (size_t i = 0; i < x.nodes4().size(); ++i) {
        const Bvh4Node &a = x.nodes4()[i], &b = y.nodes4()[i];
        EXPECT_EQ(a.valid, b.valid) << i;
        for (int c = 0; c < 4; ++c) {
            EXPECT_EQ(a.child[c], b.child[c]) << i;
            EXPECT_EQ(a.count[c], b.count[c]) << i;
            for (int ax = 0; ax < 3; ++ax) {
                EXPECT_EQ(a.lo[ax][c], b.lo[ax][c]) << i;
                EXPECT_EQ(a.hi[ax][c], b.hi[ax][c]) << i;
            }
        }
    }
}

TEST(SceneInstances, ARefitInPlaceGivesTheTreeOfAFreshCopy) {
    // Frames refitted from the same starting tree one after another rewrite the boxes in place
    // (no copy); the tree must be the one a scene going straight to the frame gets, 4-wide
    // shape included (collapsed from the starting tree's boxes, never the frame's).
    const SceneGeometry::PoseAnchor a1 = anchorAt(1), a3 = anchorAt(3);
    Scene chain = mixedScene(), direct = mixedScene(), back = mixedScene();
    chain.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.9}}, &a1);
    chain.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.2}}, &a1);  // in place
    direct.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.2}}, &a1);
    expectSameTree(chain.geometry.instances()[3].bvh, direct.geometry.instances()[3].bvh);
    // Through another anchor and back: copied again, the same tree.
    back.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.9}}, &a1);
    back.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.7}}, &a3);
    back.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.2}}, &a1);
    expectSameTree(back.geometry.instances()[3].bvh, direct.geometry.instances()[3].bvh);
    // (Anchor 1's topology is not build()'s nor anchor 3's, so a tree left uncopied would show.)
    const SceneInstance& in = back.geometry.instances()[3];
    ASSERT_NE(in.anchors.at({0, 1}).tree.primIndex(), in.built.primIndex());
    ASSERT_NE(in.anchors.at({0, 1}).tree.primIndex(), in.anchors.at({0, 3}).tree.primIndex());
    EXPECT_EQ(in.bvh.primIndex(), in.anchors.at({0, 1}).tree.primIndex());
    // Without anchors: build()'s tree refitted, in place the second time.
    Scene chainRest = mixedScene(), directRest = mixedScene();
    chainRest.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {1.0}});
    chainRest.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.4}});
    directRest.geometry.applyNodeTransforms(0, poseAt(0.0), {{}, {}, {0.4}});
    expectSameTree(chainRest.geometry.instances()[3].bvh, directRest.geometry.instances()[3].bvh);
    // And the rays agree with the baked mesh.
    expectHitsAsBaked(chain, 5);
}

}  // namespace
}  // namespace rf
