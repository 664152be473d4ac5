#pragma once
/// glTF images as bytes become pixels: data URIs by their MIME type, formats told by their
/// magic bytes (PNG through libpng, JPEG through libjpeg-turbo, WebP through libwebp, BMP and
/// GIF through stb; KTX2 recognised and refused, Debian having no Basis decoder), sizes read
/// from the header before anything is decoded, and images over a side limit decoded straight to
/// a smaller size (PNG row by row, JPEG scaled in the DCT and row by row, WebP by its own
/// scaler) so a small file that declares a huge image never costs its texels. BMP and GIF are
/// decoded whole, so those over 8192² pixels are refused.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rf::gltf {

/// The MIME type of a data URI ("image/webp"; "" when it names none, "text/plain" by RFC 2397).
std::string dataUriMime(const std::string& uri);

/// The bytes of a data URI (base64 or percent-encoded); nullopt with *why on malformed data.
std::optional<std::string> decodeDataUri(const std::string& uri, std::string* mime, std::string* why);

enum class ImageFormat { Unknown, Png, Jpeg, WebP, Ktx2, Bmp, Gif, Tga };

/// The format by its first bytes, whatever the file name or MIME type claims.
ImageFormat sniffImage(const unsigned char* bytes, size_t size);
const char* formatName(ImageFormat f);

struct ImageHeader {
    ImageFormat format = ImageFormat::Unknown;
    int width = 0, height = 0;
};

/// Format and size from the header alone; false (with why) when the bytes are no image rayfarm
/// decodes. KTX2 is recognised (format set) but returns false.
bool readImageHeader(const unsigned char* bytes, size_t size, ImageHeader& header, std::string& why);

/// The side a w×h image is decoded to under maxSide: divided by the smallest whole factor k that
/// brings both sides within it (rounded up), k = 1 when it fits.
int downsampleFactor(int width, int height, int maxSide);

struct Rgba8Image {
    int width = 0, height = 0;
    int factor = 1;               ///< the whole factor it was shrunk by (1: full size)
    std::vector<uint8_t> pixels;  ///< RGBA, 8 bits each, row 0 at the top
};

/// Decodes to RGBA8, within maxSide on both sides (box-filtered down by downsampleFactor on the
/// way, JPEG first by its DCT scaling), so the full image is never held for PNG, JPEG and WebP;
/// nullopt with why when it cannot be decoded.
std::optional<Rgba8Image> decodeImage(const unsigned char* bytes, size_t size, int maxSide, std::string& why);

}  // namespace rf::gltf
