#pragma once
/// Render settings shared by the scene file, the CLI and the farm.

namespace rf {

enum class ToneMap {
    Clamp,       ///< the seed's: clip to [0, 1]
    Reinhard,    ///< x/(1 + x) per channel
    PbrNeutral,  ///< Khronos PBR Neutral: exact below 0.76, hue-preserving roll-off above (glTF default)
};
enum class ShadingModel { Phong, BlinnPhong };
/// Which Integrator (engine/integrators/integrator.h) turns rays into radiance.
enum class IntegratorKind { Whitted };

/// RenderSettings::bounce's default and the most it accepts.
constexpr int kDefaultBounce = 3;
constexpr int kMaxBounce = 1000;

struct RenderSettings {
    int width = 640;
    int height = 360;
    int spp = 1;              ///< samples per pixel: a square n×n, stratified
    int maxDepth = 5;         ///< ray generations, the primary ray counting as 1
    float minWeight = 1e-3f;  ///< the seed's pruning rule: skip secondary rays weighing less
    ToneMap toneMap = ToneMap::Clamp;
    float exposure = 0.f;        ///< EV: radiance is scaled by 2^exposure before tone mapping
    bool autoExposure = false;   ///< meter exposure once per film (the CLI resolves it into exposure)
    ShadingModel shading = ShadingModel::Phong;
    int tileSize = 32;
    /// Indirect light of glTF materials. 0 (the default): the environment's split sum,
    /// unshadowed and noise-free. N > 0: N stratified samples each of the diffuse and of the
    /// glossy lobe per shading point seen by a camera, mirror or refraction ray, traced
    /// against the scene: the environment where they escape (occlusion) and the shaded surface
    /// where they hit (one bounce), converging towards a path tracer as N grows.
    int indirectSamples = 0;
    /// Bounce light of glTF materials with indirectSamples 0 (bounce_cache.h): the punctual
    /// lights' and emission's diffuse bounce, cached on this many thousand surface points per
    /// film (rebuilt only when geometry or lights move). 0: none.
    int bounce = kDefaultBounce;
    /// Whether the bounce cache is made for films whose geometry moves too (skinned, morphed or
    /// animated meshes), built again for every frame that moves it: about 200,000 rays a frame
    /// at 3000 points, several times a small frame's own cost. Off by default; --bounce N or the
    /// scene file's render.bounce turns it on, and a still, which poses once, always has it.
    bool bounceMoving = false;
    IntegratorKind integrator = IntegratorKind::Whitted;
    /// Speed-ups that must never change a pixel, switchable so tests can show they do not:
    /// camera rays traced in packets of neighbouring pixels (render.cpp, SceneGeometry::intersectPacket),
    /// and each thread's cache of the triangle that last blocked a light (ShadowBlockers).
    bool packets = true;
    bool blockerCache = true;
};
/// The most --indirect (and the scene file's render.indirect) accepts.
constexpr int kMaxIndirectSamples = 1024;

}  // namespace rf
