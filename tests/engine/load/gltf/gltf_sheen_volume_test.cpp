// KHR_materials_sheen and KHR_materials_volume against their specifications. Sheen: a colour of
// 0 is no sheen to the bit; the Charlie distribution is normalized; the albedo table is its
// quadrature; a sheen over black in a white furnace shows its albedo E(n·v) and never more than
// the light it gets; a white base under a white sheen gains no energy. Volume: light that
// crosses d of the inside keeps exp(−σ·d), σ = −ln(attenuationColor)/attenuationDistance, on
// camera paths (an orthographic camera looks straight through slabs of two heights) and on
// shadow rays; a thickness of 0 is thin-walled.
#include <gtest/gtest.h>

#include "engine/materials/brdf_gltf.h"
#include "engine/materials/brdf_sheen.h"
#include "tests/engine/engine_test_util.h"
#include "tests/engine/gltf_floor_scene.h"

using namespace rf;
using namespace gltftest;

namespace {

const json kBlack = {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0.5}};

json sheenMaterial(const json& sheen) {
    return {{"pbrMetallicRoughness", kBlack},
            {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}, {"KHR_materials_sheen", sheen}}}};
}

/// An axis-aligned box [lo, hi] of 12 outward-wound triangles with flat normals.
TriangleMesh box(const Vec3& lo, const Vec3& hi, int material) {
    TriangleMesh m;
    auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d, Vec3 n) {
        const uint32_t k = uint32_t(m.positions.size());
        for (const Vec3& p : {a, b, c, d}) m.positions.push_back(p), m.normals.push_back(n);
        m.indices.insert(m.indices.end(), {k, k + 1, k + 2, k, k + 2, k + 3});
    };
    const Vec3 l = lo, h = hi;
    quad({l.x, h.y, l.z}, {l.x, h.y, h.z}, {h.x, h.y, h.z}, {h.x, h.y, l.z}, {0, 1, 0});
    quad({l.x, l.y, l.z}, {h.x, l.y, l.z}, {h.x, l.y, h.z}, {l.x, l.y, h.z}, {0, -1, 0});
    quad({l.x, l.y, h.z}, {h.x, l.y, h.z}, {h.x, h.y, h.z}, {l.x, h.y, h.z}, {0, 0, 1});
    quad({l.x, l.y, l.z}, {l.x, h.y, l.z}, {h.x, h.y, l.z}, {h.x, l.y, l.z}, {0, 0, -1});
    quad({h.x, l.y, l.z}, {h.x, h.y, l.z}, {h.x, h.y, h.z}, {h.x, l.y, h.z}, {1, 0, 0});
    quad({l.x, l.y, l.z}, {l.x, l.y, h.z}, {l.x, h.y, h.z}, {l.x, h.y, l.z}, {-1, 0, 0});
    m.material = material;
    return m;
}

/// Clear glass that neither bends nor reflects (ior 1, no specular layer), so only the volume
/// changes the light through it.
Material clearVolume(const Color& sigma, float thickness) {
    Material m;
    m.gltfPbr = true;
    m.color = Color(1.f);
    m.metallic = 0.f;
    m.roughness = 0.f;
    m.ior = 1.f;
    m.specularWeight = 0.f;
    m.transmission = 1.f;
    m.diffuse = 0.f;
    m.thickness = thickness;
    m.attenuation = sigma;
    return m;
}

/// The centre pixel of a 9×9 render of the scene's camera, unpruned, 8 deep.
Color centrePixel(Scene& s) {
    s.build();
    RenderSettings rs = test::smallSettings(9, 9, 1, 8);
    rs.minWeight = 0.f;
    const Image img = test::render(s, rs);
    const float* p = img.pixel(4, 4);
    return Color(p[0], p[1], p[2]);
}

/// A slab of clear volume (material 1), x and z in [−1, 1], y in [0, height], over a uniform
/// white sky, seen straight down through an orthographic camera: every pixel's ray crosses it
/// vertically. Returns the centre pixel.
Color throughSlab(float height, const Color& sigma, float thickness = 1.f) {
    Scene s = test::emptyScene();
    s.materials.push_back(clearVolume(sigma, thickness));
    s.geometry.meshes.push_back(box(Vec3(-1.f, 0.f, -1.f), Vec3(1.f, height, 1.f), 1));
    s.environment = uniformEnvironment(1.f);
    s.camera.eye = Vec3(0.f, 10.f, 0.f);
    s.camera.target = Vec3(0.f);
    s.camera.up = Vec3(0.f, 0.f, -1.f);
    s.camera.orthographic = true;
    s.camera.orthoHalf = 0.5f;
    return centrePixel(s);
}

}  // namespace

TEST(Sheen, ColourZeroIsNoSheenToTheBit) {
    // The layer's formulas: a zero colour returns the base untouched...
    pbr::Surface s;
    s.baseColor = Color(0.6f, 0.3f, 0.2f);
    s.sheenRoughness = 0.4f;
    const Vec3 n(0, 0, 1), v = glm::normalize(Vec3(0.5f, 0, 1)), l = glm::normalize(Vec3(-0.2f, 0.3f, 1));
    const Color base = pbr::directLight(s, n, v, l, Color(2.f));
    EXPECT_EQ(pbr::sheenDirect(s, n, v, l, base, Color(2.f)), base);
    EXPECT_EQ(pbr::sheenEnvironment(s, 0.7f, base, Color(1.f)), base);
    // ...and a file's sheen of colour 0 renders as the same file without the extension.
    const json plain = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.6, 0.3, 0.2, 1}}, {"roughnessFactor", 0.4}, {"metallicFactor", 0}}}};
    json zero = plain;
    zero["extensions"]["KHR_materials_sheen"] = {{"sheenColorFactor", {0, 0, 0}}, {"sheenRoughnessFactor", 0.8}};
    Scene a = loadFloor(plain), b = loadFloor(zero);
    a.environment = b.environment = uniformEnvironment(0.5f);
    const Image ia = renderFromAbove(a), ib = renderFromAbove(b);
    for (int i = 0; i < 65 * 65 * 3; ++i) ASSERT_EQ(ia.data()[i], ib.data()[i]) << i;
    for (const std::string& note : b.notes) EXPECT_EQ(note.find("KHR_materials_sheen"), std::string::npos) << note;
}

TEST(Sheen, CharlieDistributionIsNormalized) {
    // ∫ D(h)·cos θh dω over the hemisphere = 1, in double by the midpoint rule in cos θh.
    for (float r : {0.1f, 0.3f, 0.6f, 1.f}) {
        const float alpha = pbr::sheenAlpha(r);
        double sum = 0.0;
        constexpr int kSteps = 20000;
        for (int i = 0; i < kSteps; ++i) {
            const double c = (i + 0.5) / kSteps;
            sum += double(pbr::charlieD(float(c), alpha)) * c;
        }
        EXPECT_NEAR(sum * 2.0 * kPi / kSteps, 1.0, 2e-3) << "roughness " << r;
    }
}

TEST(Sheen, AlbedoTableIsItsQuadratureAndAtMostOne) {
    for (float r : {0.07f, 0.2f, 0.45f, 0.8f, 1.f})
        for (float nv : {0.05f, 0.3f, 0.55f, 0.9f, 1.f}) {
            const float table = pbr::sheenAlbedo(nv, r);
            const float fine = pbr::sheenAlbedoQuadrature(nv, r, 400, 200);
            EXPECT_NEAR(table, fine, 0.02f) << "n·v " << nv << " roughness " << r;
            EXPECT_LE(table, 1.f);
            EXPECT_GE(table, 0.f);
        }
    // A rough sheen reflects visibly more towards grazing views than face on.
    EXPECT_GT(pbr::sheenAlbedo(0.1f, 0.5f), pbr::sheenAlbedo(1.f, 0.5f));
}

TEST(Sheen, OverBlackInAWhiteFurnaceShowsItsAlbedo) {
    // Nothing but the sheen reflects; under uniform radiance 1 a pixel is E(n·v) of its colour.
    Scene s = loadFloor(sheenMaterial({{"sheenColorFactor", {1, 0.5, 0.25}}, {"sheenRoughnessFactor", 0.5}}));
    s.lights.clear();
    s.environment = uniformEnvironment(1.f);
    const Image img = renderFromAbove(s);
    for (int y = 0; y < 65; y += 8)
        for (int x = 0; x < 65; x += 8) {
            const float e = pbr::sheenAlbedoQuadrature(cosineAt(x, y), 0.5f, 400, 200);
            EXPECT_NEAR(img.pixel(x, y)[0], e, 0.02f) << x << "," << y;
            EXPECT_NEAR(img.pixel(x, y)[1], 0.5f * e, 0.01f) << x << "," << y;
            EXPECT_NEAR(img.pixel(x, y)[2], 0.25f * e, 0.005f) << x << "," << y;
            EXPECT_LE(img.pixel(x, y)[0], 1.f);
        }
    // The sheen roughness texture's alpha and the colour texture (sRGB) multiply the factors.
    EXPECT_EQ(s.materials[0].sheenColorTexture, -1);
}

TEST(Sheen, WhiteSheenOverAWhiteBaseGainsNoEnergy) {
    // A white Lambertian base (no specular layer) with a white sheen in a white furnace: the
    // base gives up what the sheen takes, 1 − E + E = 1 face on and at every angle: the picture
    // is the bare base's (whatever the environment's irradiance map makes of a uniform sky).
    json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
              {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}};
    Scene bare = loadFloor(m);
    m["extensions"]["KHR_materials_sheen"] = {{"sheenColorFactor", {1, 1, 1}}, {"sheenRoughnessFactor", 0.3}};
    Scene s = loadFloor(m);
    for (Scene* x : {&bare, &s}) {
        x->lights.clear();
        x->environment = uniformEnvironment(1.f);
    }
    const Image img = renderFromAbove(s), base = renderFromAbove(bare);
    EXPECT_NEAR(base.pixel(32, 32)[1], 1.f, 0.03f);
    for (int y = 0; y < 65; y += 8)
        for (int x = 0; x < 65; x += 8) EXPECT_NEAR(img.pixel(x, y)[1], base.pixel(x, y)[1], 1e-4f) << x << "," << y;
    // Under a light, too: over the hemisphere of view directions the layer never adds energy
    // to what the base alone reflects (the min of the two scalings keeps it reciprocal).
    pbr::Surface w;
    w.baseColor = Color(1.f);
    w.specular = 0.f;
    w.sheenColor = Color(1.f);
    w.sheenRoughness = 0.3f;
    const Vec3 n(0, 0, 1), l = glm::normalize(Vec3(0.3f, 0.1f, 1));
    double sum = 0.0;
    constexpr int kSteps = 200;
    for (int i = 0; i < kSteps; ++i)
        for (int j = 0; j < kSteps; ++j) {
            const float c = (i + 0.5f) / kSteps, phi = 2.f * kPi * (j + 0.5f) / kSteps, sn = std::sqrt(1.f - c * c);
            const Vec3 v(sn * std::cos(phi), sn * std::sin(phi), c);
            const Color base = pbr::directLight(w, n, v, l, Color(1.f));
            sum += double(pbr::sheenDirect(w, n, v, l, base, Color(1.f)).g) * c;  // reflected flux
        }
    const double albedo = sum * 2.0 * kPi / (kSteps * kSteps) / double(glm::dot(n, l));
    EXPECT_LE(albedo, 1.0 + 1e-3) << "white sheen over white base reflects more than it receives";
    EXPECT_GT(albedo, 0.9);
}

TEST(Sheen, DirectLightIsTheExtensionsLayering) {
    pbr::Surface s;
    s.baseColor = Color(0.5f);
    s.sheenColor = Color(0.8f, 0.4f, 0.2f);
    s.sheenRoughness = 0.6f;
    const Vec3 n(0, 0, 1), v = glm::normalize(Vec3(0.9f, 0, 0.3f)), l = glm::normalize(Vec3(-0.8f, 0.2f, 0.4f));
    const Color base = pbr::directLight(s, n, v, l, Color(1.f));
    const float nv = glm::dot(n, v), nl = glm::dot(n, l), alpha = 0.36f;
    const Vec3 h = glm::normalize(v + l);
    // The extension's formulas, written out here: Charlie D, the fitted visibility, albedo scaling.
    const double invA = 1.0 / alpha, sin2 = 1.0 - double(glm::dot(n, h)) * glm::dot(n, h);
    const double D = (2.0 + invA) * std::pow(sin2, 0.5 * invA) / (2.0 * kPi);
    auto lf = [&](double x) {
        const double t = (1 - alpha) * (1 - alpha);
        return (21.5473 + (25.3245 - 21.5473) * t) / (1 + (3.82987 + (3.32435 - 3.82987) * t) * std::pow(x, 0.19823 + (0.16801 - 0.19823) * t)) +
               (-1.97760 + (-1.27393 + 1.97760) * t) * x + (-4.32054 + (-4.85967 + 4.32054) * t);
    };
    auto lambda = [&](double c) { return c < 0.5 ? std::exp(lf(c)) : std::exp(2 * lf(0.5) - lf(1 - c)); };
    const double V = std::min(1.0, 1.0 / ((1 + lambda(nv) + lambda(nl)) * 4 * nv * nl));
    const double scaling = std::min(1.0 - 0.8 * pbr::sheenAlbedo(nv, 0.6f), 1.0 - 0.8 * pbr::sheenAlbedo(nl, 0.6f));
    const Color got = pbr::sheenDirect(s, n, v, l, base, Color(1.f));
    for (int c = 0; c < 3; ++c) {
        const double want = s.sheenColor[c] * D * V * nl + base[c] * scaling;
        EXPECT_NEAR(got[c], want, 1e-4 * want) << c;
    }
}

TEST(Volume, LoadsSigmaFromAttenuationColourAndDistance) {
    json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}}},
              {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                              {"KHR_materials_volume", {{"thicknessFactor", 0.5}, {"attenuationColor", {0.5, 0.25, 1}}, {"attenuationDistance", 2}}}}}};
    const Scene s = loadFloor(m);
    const Material& mat = s.materials[0];
    EXPECT_TRUE(mat.volume());
    EXPECT_FLOAT_EQ(mat.thickness, 0.5f);
    EXPECT_NEAR(mat.attenuation.r, std::log(2.0) / 2, 1e-6);
    EXPECT_NEAR(mat.attenuation.g, std::log(4.0) / 2, 1e-6);
    EXPECT_EQ(mat.attenuation.b, 0.f);
    for (const std::string& note : s.notes) EXPECT_EQ(note.find("KHR_materials_volume"), std::string::npos) << note;
    // No distance: nothing absorbs. No transmission: no volume.
    m["extensions"]["KHR_materials_volume"].erase("attenuationDistance");
    EXPECT_EQ(loadFloor(m).materials[0].attenuation, Color(0.f));
    m["extensions"].erase("KHR_materials_transmission");
    EXPECT_FALSE(loadFloor(m).materials[0].volume());
}

TEST(Volume, CameraPathsKeepExpMinusSigmaTimesTheirLengthInside) {
    const Color sigma(std::log(2.f), 0.5f, 0.f);
    const Color clear = throughSlab(1.f, Color(0.f));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(clear[c], 1.f, 1e-5f) << "clear glass at ior 1 shows the sky";
    for (float d : {1.f, 3.f}) {
        const Color got = throughSlab(d, sigma);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], std::exp(-sigma[c] * d), 1e-5f) << "height " << d << " channel " << c;
    }
    // Thickness 0 is thin-walled: the attenuation does not apply.
    const Color thin = throughSlab(3.f, sigma, 0.f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(thin[c], 1.f, 1e-5f);
}

TEST(Volume, ShadowRaysThroughAVolumeKeepExpMinusSigmaTimesTheWayInside) {
    // A white floor lit from straight above through a slab 2 high: at its centre the light is
    // exp(−σ·2) of what reaches it through the same slab without absorption.
    auto floorUnder = [](const Color& sigma) {
        Scene s = test::emptyScene();
        Material floor;
        floor.gltfPbr = true;
        floor.color = Color(1.f);
        floor.metallic = 0.f;
        floor.roughness = 1.f;
        floor.specularWeight = 0.f;
        s.materials[0] = floor;
        s.materials.push_back(clearVolume(sigma, 1.f));
        s.geometry.meshes.push_back(test::gridMesh(1, 10.f, 0));
        s.geometry.meshes.push_back(box(Vec3(-1.f, 1.f, -1.f), Vec3(1.f, 3.f, 1.f), 1));
        Light L;
        L.type = LightType::Point;
        L.position = Vec3(0.f, 6.f, 0.f);
        L.intensity = 36.f;
        L.attenuation = Vec3(0.f, 0.f, 1.f);
        s.lights.push_back(L);
        // Seen from beside the slab, so the camera ray meets the floor without crossing it.
        s.camera.eye = Vec3(0.f, 0.5f, 6.f);
        s.camera.target = Vec3(0.f, 0.f, 0.f);
        s.camera.fovDeg = 10.f;
        return centrePixel(s);
    };
    const Color sigma(0.3f, 0.1f, 0.f);
    const Color lit = floorUnder(Color(0.f)), dim = floorUnder(sigma);
    ASSERT_GT(lit.r, 0.1f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(dim[c] / lit[c], std::exp(-2.f * sigma[c]), 1e-4f) << c;
}
