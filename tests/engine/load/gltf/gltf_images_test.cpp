// glTF images: data URIs by MIME type, formats by their bytes, EXT_texture_webp through libwebp
// (a lossless WebP draws exactly as its PNG), KHR_texture_basisu's fallback, KTX2 refused.
#include <gtest/gtest.h>

#include <filesystem>

#include <stb_image.h>
#include <stb_image_write.h>
#include <webp/encode.h>

#include "tests/engine/engine_test_util.h"
#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_images.h"
#include "engine/load/gltf/gltf_loader.h"
#include "tests/engine/gltf_test_util.h"

using namespace rf;
using namespace gltftest;
using rf::test::render;

namespace {

const std::string kBox = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/";

/// The Cesium logo of BoxTextured, re-encoded as lossless WebP through libwebp.
std::string logoAsWebP() {
    const std::string png = readFile(kBox + "CesiumLogoFlat.png");
    int w = 0, h = 0, c = 0;
    unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()), int(png.size()), &w, &h, &c, 4);
    EXPECT_NE(px, nullptr);
    uint8_t* out = nullptr;
    const size_t n = WebPEncodeLosslessRGBA(px, w, h, w * 4, &out);
    stbi_image_free(px);
    std::string webp(reinterpret_cast<const char*>(out), n);
    WebPFree(out);
    return webp;
}

/// BoxTextured with its buffer copied next to it and its image replaced by `images`; textures[0]
/// gets `texture` merged in.
std::string boxWith(const TempDir& dir, const json& images, const json& texture, const json& extensionsUsed = json::array()) {
    json g = json::parse(readFile(kBox + "BoxTextured.gltf"));
    writeFile(dir / "BoxTextured0.bin", readFile(kBox + "BoxTextured0.bin"));
    g["images"] = images;
    g["textures"][0] = texture;
    if (!extensionsUsed.empty()) g["extensionsUsed"] = extensionsUsed;
    static int n = 0;
    const std::string path = dir / ("box" + std::to_string(n++) + ".gltf");
    writeFile(path, g.dump());
    return path;
}

Image renderModel(const std::string& path, std::vector<std::string>* notes = nullptr) {
    DiskFileSource files;
    SceneOptions o;
    o.width = 96;
    o.height = 72;
    Scene s = loadGltfScene(path, files, o);
    if (notes) *notes = s.notes;
    RenderSettings rs = s.settings;
    rs.spp = 1;
    return render(s, rs);
}

bool identical(const Image& a, const Image& b) {
    return a.width() == b.width() && a.height() == b.height() &&
           std::equal(a.data(), a.data() + size_t(a.width()) * a.height() * 3, b.data());
}

bool anyNoteHas(const std::vector<std::string>& notes, const std::string& needle) {
    for (const std::string& n : notes)
        if (n.find(needle) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST(GltfImages, DataUrisDecodeByTheirEncoding) {
    std::string mime, why;
    EXPECT_EQ(gltf::decodeDataUri("data:image/webp;base64," + base64("RIFF\x01\x02WEBP"), &mime, &why), "RIFF\x01\x02WEBP");
    EXPECT_EQ(mime, "image/webp");
    EXPECT_EQ(gltf::decodeDataUri("data:text/plain,a%20b%2c", &mime, &why), "a b,");
    EXPECT_EQ(mime, "text/plain");
    EXPECT_EQ(gltf::dataUriMime("data:image/ktx2;base64,AAAA"), "image/ktx2");
    EXPECT_FALSE(gltf::decodeDataUri("data:image/png;base64,QU*=", &mime, &why));
    EXPECT_NE(why.find("not base64"), std::string::npos);
    EXPECT_FALSE(gltf::decodeDataUri("data:image/png;base64", &mime, &why));
}

TEST(GltfImages, FormatsAreToldByTheirBytes) {
    const std::string png = readFile(kBox + "CesiumLogoFlat.png"), webp = logoAsWebP();
    auto header = [](const std::string& b, gltf::ImageHeader& h) {
        std::string why;
        return gltf::readImageHeader(reinterpret_cast<const unsigned char*>(b.data()), b.size(), h, why);
    };
    gltf::ImageHeader hp, hw, hk;
    ASSERT_TRUE(header(png, hp));
    ASSERT_TRUE(header(webp, hw));
    EXPECT_EQ(hp.format, gltf::ImageFormat::Png);
    EXPECT_EQ(hw.format, gltf::ImageFormat::WebP);
    EXPECT_EQ(hw.width, hp.width);
    EXPECT_EQ(hw.height, hp.height);
    EXPECT_FALSE(header(std::string("\xabKTX 20\xbb\r\n\x1a\n", 12) + std::string(80, '\0'), hk));
    EXPECT_EQ(hk.format, gltf::ImageFormat::Ktx2);
}

// TGA, which has no signature, told by its header: the textures of assimp's models (COLLADA's
// duck). Written by stb_image_write run-length coded and not, read back pixel for pixel.
TEST(GltfImages, TgaIsToldByItsHeaderAndDecodesExactly) {
    const int w = 5, h = 3;
    std::vector<uint8_t> px(size_t(w) * h * 4);
    for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(i % 4 == 3 ? 200 + i % 7 : (i * 37) % 256);
    for (int rle : {0, 1}) {
        stbi_write_tga_with_rle = rle;
        std::string tga;
        stbi_write_tga_to_func([](void* ctx, void* data, int size) { static_cast<std::string*>(ctx)->append(static_cast<char*>(data), size_t(size)); },
                               &tga, w, h, 4, px.data());
        SCOPED_TRACE(rle ? "run-length coded" : "plain");
        const auto* b = reinterpret_cast<const unsigned char*>(tga.data());
        EXPECT_EQ(gltf::sniffImage(b, tga.size()), gltf::ImageFormat::Tga);
        std::string why;
        const auto img = gltf::decodeImage(b, tga.size(), 0, why);
        ASSERT_TRUE(img) << why;
        EXPECT_EQ(img->width, w);
        EXPECT_EQ(img->height, h);
        EXPECT_EQ(img->pixels, px);
    }
    stbi_write_tga_with_rle = 1;
    // Not a TGA: a type TGA does not have, a zero width, 12 bits a pixel.
    std::string bad(18 + 16, '\0');
    bad[2] = 2, bad[12] = 4, bad[14] = 4, bad[16] = 24;
    auto sniff = [](const std::string& b) { return gltf::sniffImage(reinterpret_cast<const unsigned char*>(b.data()), b.size()); };
    EXPECT_EQ(sniff(bad), gltf::ImageFormat::Tga);
    for (auto [at, value] : {std::pair{2, 5}, std::pair{12, 0}, std::pair{16, 12}}) {
        std::string b = bad;
        b[size_t(at)] = char(value);
        if (at == 12) b[13] = 0;
        EXPECT_EQ(sniff(b), gltf::ImageFormat::Unknown) << "byte " << at;
    }
    // assimp-testmodels' duck texture, a real file: yellow.
    const std::string duck = "/usr/share/assimp/models/Collada/duckCM.tga";
    if (!std::filesystem::exists(duck)) return;
    const std::string bytes = readFile(duck);
    std::string why;
    const auto img = gltf::decodeImage(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), 0, why);
    ASSERT_TRUE(img) << why;
    double r = 0, g = 0, bl = 0;
    for (size_t i = 0; i < img->pixels.size(); i += 4) r += img->pixels[i], g += img->pixels[i + 1], bl += img->pixels[i + 2];
    EXPECT_GT(r, 2 * bl);
    EXPECT_GT(g, 1.5 * bl);
}

TEST(GltfImages, LosslessWebPTextureRendersExactlyAsItsPng) {
    TempDir dir;
    writeFile(dir / "logo.png", readFile(kBox + "CesiumLogoFlat.png"));
    writeFile(dir / "logo.webp", logoAsWebP());
    const std::string png = boxWith(dir, {{{"uri", "logo.png"}}}, {{"sampler", 0}, {"source", 0}});
    // EXT_texture_webp with the PNG as fallback, required, and as a data URI.
    const json webpTex = {{"sampler", 0}, {"source", 0}, {"extensions", {{"EXT_texture_webp", {{"source", 1}}}}}};
    const std::string webp = boxWith(dir, {{{"uri", "logo.png"}}, {{"uri", "logo.webp"}}}, webpTex, {"EXT_texture_webp"});
    json g = json::parse(readFile(webp));
    g["extensionsRequired"] = {"EXT_texture_webp"};
    g["images"][1] = {{"uri", "data:image/webp;base64," + base64(logoAsWebP())}};
    g["images"][0] = {{"uri", "missing-fallback.png"}};  // must not be needed
    writeFile(dir / "required.gltf", g.dump());

    const Image a = renderModel(png);
    std::vector<std::string> notes;
    const Image b = renderModel(webp, &notes);
    const Image c = renderModel(dir / "required.gltf");
    EXPECT_TRUE(identical(a, b));
    EXPECT_TRUE(identical(a, c));
    EXPECT_FALSE(anyNoteHas(notes, "EXT_texture_webp"));
    // Control: the untextured box differs, so the texture shows.
    const Image plain = renderModel(boxWith(dir, {{{"uri", "logo.png"}}}, {{"sampler", 0}, {"source", 5}}));
    EXPECT_FALSE(identical(a, plain));
}

TEST(GltfImages, UnknownDataUriTypeIsNamedInTheNote) {
    TempDir dir;
    const std::string path = boxWith(dir, {{{"uri", "data:image/x-foo;base64," + base64("not an image at all")}}}, {{"source", 0}});
    std::vector<std::string> notes;
    renderModel(path, &notes);
    EXPECT_TRUE(anyNoteHas(notes, "image/x-foo")) << (notes.empty() ? "" : notes[0]);
}

TEST(GltfImages, BasisuUsesTheFallbackOrRefusesSayingWhatIsNeeded) {
    TempDir dir;
    writeFile(dir / "logo.png", readFile(kBox + "CesiumLogoFlat.png"));
    const std::string ktx2 = "data:image/ktx2;base64," + base64(std::string("\xabKTX 20\xbb\r\n\x1a\n", 12) + std::string(80, '\0'));
    const json images = {{{"uri", "logo.png"}}, {{"uri", ktx2}}};
    const json withFallback = {{"sampler", 0}, {"source", 0}, {"extensions", {{"KHR_texture_basisu", {{"source", 1}}}}}};
    const std::string png = boxWith(dir, {{{"uri", "logo.png"}}}, {{"sampler", 0}, {"source", 0}});
    EXPECT_TRUE(identical(renderModel(boxWith(dir, images, withFallback, {"KHR_texture_basisu"})), renderModel(png)));

    const json ktxOnly = {{"sampler", 0}, {"extensions", {{"KHR_texture_basisu", {{"source", 1}}}}}};
    const std::string only = boxWith(dir, images, ktxOnly, {"KHR_texture_basisu"});
    try {
        renderModel(only);
        ADD_FAILURE() << "a KTX2-only texture loaded";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("KTX2"), std::string::npos) << m;
        EXPECT_NE(m.find("needs a PNG, JPEG or WebP"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos);
    }
    // A KTX2 image as a plain texture source is refused the same way.
    EXPECT_THROW(renderModel(boxWith(dir, images, {{"source", 1}})), InputError);
}

TEST(GltfImages, LargeTexturesAreDownsampledFromTheHeaderAndTheBudgetRefusesTheRest) {
    TempDir dir;
    std::vector<uint8_t> px(size_t(300) * 200 * 3);
    for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(i * 31 % 251);
    writePng(dir / "big.png", 300, 200, px);
    const std::string path = boxWith(dir, {{{"uri", "big.png"}}}, {{"sampler", 0}, {"source", 0}});
    DiskFileSource files;
    SceneOptions o;
    o.assets.maxTextureSize = 64;  // 300 on a side: divided by 5, to 60x40
    const Scene s = loadGltfScene(path, files, o);
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.textures[0].width, 60);
    EXPECT_EQ(s.textures[0].height, 40);
    EXPECT_TRUE(anyNoteHas(s.notes, "300x200 downsampled to 60x40 on load (--max-texture-size 64)"));
    // A 5x5 box average of the sRGB bytes, then decoded: texel (1, 0) from pixels x 5..9, y 0..4.
    uint32_t sum = 0;
    for (int y = 0; y < 5; ++y)
        for (int x = 5; x < 10; ++x) sum += px[(size_t(y) * 300 + x) * 3];
    EXPECT_NEAR(s.textures[0].texels[1].r, srgbDecode(float((sum + 12) / 25) / 255.f), 1e-6f);

    // The total budget: 300x200 float RGBA with mip-maps is 1.28 MB; a 1 MB budget refuses it.
    SceneOptions tight;
    tight.assets.textureBudgetBytes = 1 << 20;
    try {
        loadGltfScene(path, files, tight);
        ADD_FAILURE() << "over the budget, loaded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("over the budget of 1 MB"), std::string::npos) << e.what();
    }
    tight.assets.textureBudgetBytes = 2 << 20;
    EXPECT_EQ(loadGltfScene(path, files, tight).textures.size(), 1u);
}

// Issue 30 #9: a data:image/webp URI was reported as "would leave the model's folder". As a
// texture's own source (without EXT_texture_webp, which glTF asks for) and through the
// extension, it is read from its bytes: no URI check, no file, the same picture as the PNG.
TEST(GltfImages, WebPDataUriIsReadFromItsBytesNeverAsAPath) {
    TempDir dir;
    writeFile(dir / "logo.png", readFile(kBox + "CesiumLogoFlat.png"));
    const std::string webpUri = "data:image/webp;base64," + base64(logoAsWebP());
    std::vector<std::string> notes;
    const Image plain = renderModel(boxWith(dir, {{{"uri", webpUri}}}, {{"sampler", 0}, {"source", 0}}), &notes);
    for (const std::string& n : notes) EXPECT_EQ(n.find("folder"), std::string::npos) << n;
    const Image png = renderModel(boxWith(dir, {{{"uri", "logo.png"}}}, {{"sampler", 0}, {"source", 0}}));
    EXPECT_TRUE(identical(plain, png));
    const json viaExtension = {{"sampler", 0}, {"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}};
    EXPECT_TRUE(identical(renderModel(boxWith(dir, {{{"uri", webpUri}}}, viaExtension, {"EXT_texture_webp"})), png));
}

TEST(GltfImages, LargeJpegsAreScaledAsTheyDecode) {
    // A 1200x800 JPEG (left half red, right half blue, a 16-pixel black grid) under
    // --max-texture-size 128: libjpeg-turbo decodes it at 1/8 (150x100) in the DCT, then the box
    // filter halves it (75x50). The halves keep their colours; nothing decodes 1200x800.
    const int w = 1200, h = 800;
    std::vector<uint8_t> px(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            uint8_t* p = &px[(size_t(y) * w + x) * 3];
            const bool line = x % 16 == 0 || y % 16 == 0;
            p[0] = line ? 0 : x < w / 2 ? 220 : 20;
            p[1] = line ? 0 : 30;
            p[2] = line ? 0 : x < w / 2 ? 20 : 220;
        }
    std::string jpeg;
    stbi_write_jpg_to_func([](void* ctx, void* data, int n) { static_cast<std::string*>(ctx)->append(static_cast<char*>(data), size_t(n)); },
                           &jpeg, w, h, 3, px.data(), 95);
    const auto* bytes = reinterpret_cast<const unsigned char*>(jpeg.data());
    std::string why;
    const std::optional<gltf::Rgba8Image> img = gltf::decodeImage(bytes, jpeg.size(), 128, why);
    ASSERT_TRUE(img) << why;
    EXPECT_EQ(img->width, 75);
    EXPECT_EQ(img->height, 50);
    EXPECT_EQ(img->factor, 16);
    auto at = [&](int x, int y, int c) { return int(img->pixels[(size_t(y) * img->width + x) * 4 + c]); };
    // Each output texel averages a 16x16 cell: its one black row and column darken it by 31/256.
    EXPECT_NEAR(at(10, 25, 0), 220 * 225 / 256, 12);
    EXPECT_NEAR(at(10, 25, 2), 20 * 225 / 256, 12);
    EXPECT_NEAR(at(60, 25, 2), 220 * 225 / 256, 12);
    EXPECT_EQ(at(60, 25, 3), 255);
    // Within the limit, the whole image at full size, as stb decodes it (to JPEG's rounding).
    const std::optional<gltf::Rgba8Image> full = gltf::decodeImage(bytes, jpeg.size(), 8192, why);
    ASSERT_TRUE(full) << why;
    EXPECT_EQ(full->width, w);
    EXPECT_EQ(full->height, h);
    int sw = 0, sh = 0, sc = 0;
    unsigned char* ref = stbi_load_from_memory(bytes, int(jpeg.size()), &sw, &sh, &sc, 4);
    ASSERT_NE(ref, nullptr);
    int worst = 0;
    for (size_t i = 0; i < size_t(w) * h * 4; ++i) worst = std::max(worst, std::abs(int(ref[i]) - int(full->pixels[i])));
    stbi_image_free(ref);
    EXPECT_LE(worst, 8) << "libjpeg-turbo and stb disagree beyond IDCT rounding";
    // A truncated JPEG is refused with libjpeg's reason, not a crash.
    const std::optional<gltf::Rgba8Image> cut = gltf::decodeImage(bytes, 200, 128, why);
    EXPECT_FALSE(cut);
    EXPECT_FALSE(why.empty());
}

TEST(GltfImages, HugeBmpsAndGifsAreRefusedFromTheirHeader) {
    // stb decodes BMP whole: one that declares 9000x9000 is refused before any decoding.
    std::string bmp = "BM";
    put<uint32_t>(bmp, {uint32_t(54), 0u, 54u, 40u, 9000u, 9000u});
    put<uint16_t>(bmp, {1, 24});
    put<uint32_t>(bmp, {0u, 0u, 0u, 0u, 0u, 0u});
    std::string why;
    EXPECT_FALSE(gltf::decodeImage(reinterpret_cast<const unsigned char*>(bmp.data()), bmp.size(), 8192, why));
    EXPECT_NE(why.find("BMP of 9000x9000 is decoded whole and is too large"), std::string::npos) << why;
}
