// SceneGeometry::applyNodeTransforms: what an animated node does to its mesh's vertex data.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "tests/engine/engine_test_util.h"

namespace rf {
namespace {

/// One normal-mapped triangle in the plane z = 0 hanging on node 0 of model 0, tangent +X.
Scene animatedTriangle() {
    Scene s = test::emptyScene();
    TriangleMesh m;
    m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    m.normals = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1)};
    m.tangents = {Vec4(1, 0, 0, 1), Vec4(1, 0, 0, 1), Vec4(1, 0, 0, 1)};
    m.indices = {0, 1, 2};
    m.model = 0;
    m.node = 0;
    m.objectPositions = m.positions;
    m.objectNormals = m.normals;
    m.objectTangents = m.tangents;
    s.geometry.meshes.push_back(m);
    s.build();
    return s;
}

TEST(SceneAnimation, TangentsTurnWithTheirNode) {
    Scene s = animatedTriangle();
    // 90° about +Y: +X goes to −Z, the normal +Z to +X.
    s.geometry.applyNodeTransforms(0, {glm::rotate(DMat4(1.0), glm::radians(90.0), glm::dvec3(0, 1, 0))});
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(s.geometry.meshes[0].normals[i].x, 1.f, 1e-6f);
        EXPECT_NEAR(s.geometry.meshes[0].tangents[i].x, 0.f, 1e-6f);
        EXPECT_NEAR(s.geometry.meshes[0].tangents[i].z, -1.f, 1e-6f);
        EXPECT_EQ(s.geometry.meshes[0].tangents[i].w, 1.f);
        // The tangent stays perpendicular to the normal it is paired with.
        EXPECT_NEAR(glm::dot(Vec3(s.geometry.meshes[0].tangents[i]), s.geometry.meshes[0].normals[i]), 0.f, 1e-6f);
    }
}

TEST(SceneAnimation, ScaledTangentsStayUnitAndAMirrorFlipsTheirHandedness) {
    Scene s = animatedTriangle();
    s.geometry.applyNodeTransforms(0, {glm::scale(DMat4(1.0), glm::dvec3(-3, 2, 1))});  // mirrors x
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(s.geometry.meshes[0].tangents[i].x, -1.f, 1e-6f);
        EXPECT_NEAR(glm::length(Vec3(s.geometry.meshes[0].tangents[i])), 1.f, 1e-6f);
        EXPECT_EQ(s.geometry.meshes[0].tangents[i].w, -1.f);
    }
    // Back to the rest pose: the object-space tangents again, not a second flip.
    s.geometry.applyNodeTransforms(0, {DMat4(1.0)});
    EXPECT_EQ(s.geometry.meshes[0].tangents[0], Vec4(1, 0, 0, 1));
}

}  // namespace
}  // namespace rf
