#pragma once
/// Render settings shared by the scene file, the CLI and the farm.

namespace rf {

enum class ToneMap { Clamp, Reinhard };
enum class ShadingModel { Phong, BlinnPhong };
/// Which Integrator (engine/integrator.h) turns rays into radiance.
enum class IntegratorKind { Whitted };

struct RenderSettings {
    int width = 640;
    int height = 360;
    int spp = 1;              ///< samples per pixel: a square n×n, stratified
    int maxDepth = 5;         ///< ray generations, the primary ray counting as 1
    float minWeight = 1e-3f;  ///< the seed's pruning rule: skip secondary rays weighing less
    ToneMap toneMap = ToneMap::Clamp;
    ShadingModel shading = ShadingModel::Phong;
    int tileSize = 32;
    IntegratorKind integrator = IntegratorKind::Whitted;
};

}  // namespace rf
