#include "engine/scene/scene.h"

namespace rf {

SceneFeatures Scene::features() const {
    SceneFeatures f;
    for (const Material& m : materials) {
        f.reflection |= m.reflection > 0.f;
        f.transmission |= m.seesThrough();
        f.textures |= m.baseColorTexture >= 0 || m.normalTexture >= 0;
    }
    for (const Light& l : lights) f.shadows |= l.castShadows;
    for (const TriangleMesh& m : geometry.meshes) f.animated |= m.node >= 0;
    return f;
}

}  // namespace rf
