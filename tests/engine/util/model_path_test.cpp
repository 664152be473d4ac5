#include <gtest/gtest.h>

#include "engine/util/model_path.h"

using namespace rf;

TEST(ModelPath, GltfAndGlbInAnyCaseAreModels) {
    for (const char* p : {"a.gltf", "dir/b.glb", "C.GLB", "x.y/Model.GlTf"}) EXPECT_TRUE(isGltfPath(p)) << p;
}

TEST(ModelPath, OtherExtensionsAreNotModels) {
    for (const char* p : {"scene.json", "model.gltf.json", "glb", "dir.glb/scene", "a.gl", ""}) EXPECT_FALSE(isGltfPath(p)) << p;
}

TEST(ModelPath, LowerExtensionKeepsTheDot) {
    EXPECT_EQ(lowerExtension("dir/Scene.JSON"), ".json");
    EXPECT_EQ(lowerExtension("noext"), "");
}
