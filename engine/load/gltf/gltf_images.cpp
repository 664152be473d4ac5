#include "engine/load/gltf/gltf_images.h"

#include <csetjmp>
#include <cstring>

#include <cstdio>

#include <jpeglib.h>
#include <png.h>
#include <stb_image.h>
#include <webp/decode.h>

#include "engine/util/load_control.h"

namespace rf::gltf {

namespace {

bool startsWith(const unsigned char* b, size_t n, const char* magic, size_t m, size_t at = 0) {
    return n >= at + m && std::memcmp(b + at, magic, m) == 0;
}

int base64Value(char c) {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+' || c == '-') return 62;  // '-' and '_': the URL-safe alphabet
    if (c == '/' || c == '_') return 63;
    return -1;
}

int hexValue(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

/// Sums k×k blocks of RGBA8 rows into a smaller image, one input row at a time.
class BoxShrinker {
public:
    BoxShrinker(int width, int height, int k) : w_(width), h_(height), k_(k) {
        out_.width = (width + k - 1) / k;
        out_.height = (height + k - 1) / k;
        out_.factor = k;
        out_.pixels.resize(size_t(out_.width) * out_.height * 4);
        acc_.assign(size_t(out_.width) * 4, 0);
    }
    void addRow(int y, const uint8_t* row) {
        // Column block by column block: no division per sample (a 16384² image is a billion).
        for (int ox = 0, x = 0; ox < out_.width; ++ox) {
            uint32_t sum[4] = {0, 0, 0, 0};
            for (const int end = std::min(w_, x + k_); x < end; ++x)
                for (int c = 0; c < 4; ++c) sum[c] += row[size_t(x) * 4 + c];
            for (int c = 0; c < 4; ++c) acc_[size_t(ox) * 4 + c] += sum[c];
        }
        if ((y + 1) % k_ != 0 && y != h_ - 1) return;
        const uint32_t rows = uint32_t(y % k_ + 1);
        uint8_t* dst = out_.pixels.data() + size_t(y / k_) * out_.width * 4;
        for (int ox = 0; ox < out_.width; ++ox) {
            const uint32_t n = rows * uint32_t(std::min(k_, w_ - ox * k_));
            for (int c = 0; c < 4; ++c) dst[ox * 4 + c] = uint8_t((acc_[size_t(ox) * 4 + c] + n / 2) / n);
        }
        std::fill(acc_.begin(), acc_.end(), 0u);
    }
    Rgba8Image take() { return std::move(out_); }

private:
    int w_, h_, k_;
    std::vector<uint32_t> acc_;
    Rgba8Image out_;
};

struct PngReadState {
    const unsigned char* data;
    size_t size, at;
    char message[200];
};

void pngRead(png_structp png, png_bytep out, png_size_t n) {
    auto* s = static_cast<PngReadState*>(png_get_io_ptr(png));
    if (n > s->size - s->at) png_error(png, "truncated PNG data");
    std::memcpy(out, s->data + s->at, n);
    s->at += n;
}

void pngError(png_structp png, png_const_charp msg) {
    auto* s = static_cast<PngReadState*>(png_get_io_ptr(png));
    std::snprintf(s->message, sizeof s->message, "%s", msg);
    png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {}

/// libpng row by row into a BoxShrinker: memory is one row and the (shrunk) result. Every C++
/// object lives outside the setjmp region, so libpng's longjmp on bad data skips no destructor.
std::optional<Rgba8Image> decodePng(const unsigned char* bytes, size_t size, int maxSide, std::string& why) {
    PngReadState state{bytes, size, 0, {0}};
    std::vector<uint8_t> row;
    std::optional<BoxShrinker> shrink;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, &pngError, &pngWarning);
    if (!png) return why = "out of memory", std::nullopt;
    png_infop info = png_create_info_struct(png);
    bool interlaced = false;
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
        why = state.message[0] ? state.message : "PNG decode failed";
        return std::nullopt;
    }
    png_set_read_fn(png, &state, &pngRead);
    png_set_user_limits(png, 1u << 20, 1u << 20);
    png_read_info(png, info);
    const int w = int(png_get_image_width(png, info)), h = int(png_get_image_height(png, info));
    interlaced = png_get_interlace_type(png, info) != PNG_INTERLACE_NONE;
    if (!interlaced) {
        png_set_expand(png);  // palette, low-bit grey and tRNS to 8-bit RGB(A)
        png_set_strip_16(png);
        png_set_gray_to_rgb(png);
        png_set_filler(png, 0xff, PNG_FILLER_AFTER);
        png_read_update_info(png, info);
        if (png_get_rowbytes(png, info) != size_t(w) * 4) png_error(png, "unexpected PNG row layout");
        row.resize(size_t(w) * 4);
        shrink.emplace(w, h, downsampleFactor(w, h, maxSide));
        for (int y = 0; y < h; ++y) {
            // A cancelled load stops here and throws below, once libpng's state is freed.
            if (y % 64 == 0 && loadCancelSignal() != 0) break;
            png_read_row(png, row.data(), nullptr);
            shrink->addRow(y, row.data());
        }
    }
    png_destroy_read_struct(&png, &info, nullptr);
    pollLoadCancel();
    if (shrink) return shrink->take();
    // Interlaced: its rows come in seven passes, so the whole image is decoded first.
    if (uint64_t(w) * uint64_t(h) > uint64_t(8192) * 8192) {
        why = "interlaced PNG of " + std::to_string(w) + "x" + std::to_string(h) + " is too large to decode whole";
        return std::nullopt;
    }
    return std::nullopt;  // the caller falls back to stb
}

std::optional<Rgba8Image> decodeWebP(const unsigned char* bytes, size_t size, int maxSide, std::string& why) {
    WebPDecoderConfig config;
    if (!WebPInitDecoderConfig(&config)) return why = "libwebp version mismatch", std::nullopt;
    if (WebPGetFeatures(bytes, size, &config.input) != VP8_STATUS_OK) return why = "not a readable WebP file", std::nullopt;
    const int w = config.input.width, h = config.input.height, k = downsampleFactor(w, h, maxSide);
    Rgba8Image out;
    out.factor = k;
    out.width = (w + k - 1) / k;
    out.height = (h + k - 1) / k;
    if (k > 1) {
        config.options.use_scaling = 1;
        config.options.scaled_width = out.width;
        config.options.scaled_height = out.height;
    }
    out.pixels.resize(size_t(out.width) * out.height * 4);
    config.output.colorspace = MODE_RGBA;
    config.output.is_external_memory = 1;
    config.output.u.RGBA.rgba = out.pixels.data();
    config.output.u.RGBA.stride = out.width * 4;
    config.output.u.RGBA.size = out.pixels.size();
    const VP8StatusCode status = WebPDecode(bytes, size, &config);
    WebPFreeDecBuffer(&config.output);
    if (status != VP8_STATUS_OK) return why = "WebP decode failed (status " + std::to_string(int(status)) + ")", std::nullopt;
    return out;
}

struct JpegError {
    jpeg_error_mgr mgr;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
};

void jpegErrorExit(j_common_ptr c) {
    auto* e = reinterpret_cast<JpegError*>(c->err);
    (*c->err->format_message)(c, e->message);
    std::longjmp(e->jump, 1);
}

void jpegSilent(j_common_ptr, int) {}

/// What libjpeg may allocate for one image: a baseline JPEG needs a few rows of blocks, so only
/// a progressive one of ~16k² (its coefficients, 2 bytes each, all kept) comes near.
constexpr long kJpegMemory = 512l << 20;

/// libjpeg-turbo, scaled in the DCT by the largest of 1/2, 1/4, 1/8 the downsampling allows,
/// scanline by scanline into a BoxShrinker for the rest: a huge JPEG never costs its full
/// texels, and a reduced-size IDCT is cheaper than decoding them. As decodePng, every C++ object
/// lives outside the setjmp region.
std::optional<Rgba8Image> decodeJpeg(const unsigned char* bytes, size_t size, int maxSide, std::string& why) {
    jpeg_decompress_struct cinfo;
    JpegError err;
    std::vector<uint8_t> rgb, rgba;
    std::optional<BoxShrinker> shrink;
    cinfo.err = jpeg_std_error(&err.mgr);
    err.mgr.error_exit = &jpegErrorExit;
    err.mgr.emit_message = &jpegSilent;
    err.message[0] = 0;
    if (setjmp(err.jump)) {
        jpeg_destroy_decompress(&cinfo);
        why = err.message[0] ? err.message : "JPEG decode failed";
        return std::nullopt;
    }
    jpeg_create_decompress(&cinfo);
    cinfo.mem->max_memory_to_use = kJpegMemory;
    jpeg_mem_src(&cinfo, bytes, static_cast<unsigned long>(size));
    jpeg_read_header(&cinfo, TRUE);
    const int w = int(cinfo.image_width), h = int(cinfo.image_height);
    const int k = downsampleFactor(w, h, maxSide);
    cinfo.scale_num = 1;
    cinfo.scale_denom = k >= 8 ? 8 : k >= 4 ? 4 : k >= 2 ? 2 : 1;
    cinfo.out_color_space = JCS_RGB;  // greyscale and YCbCr alike; CMYK is refused by libjpeg here
    jpeg_calc_output_dimensions(&cinfo);
    const int sw = int(cinfo.output_width), sh = int(cinfo.output_height);
    rgb.resize(size_t(sw) * 3);
    rgba.resize(size_t(sw) * 4);
    shrink.emplace(sw, sh, downsampleFactor(sw, sh, maxSide));
    jpeg_start_decompress(&cinfo);
    for (int y = 0; y < sh; ++y) {
        JSAMPROW row = rgb.data();
        if (jpeg_read_scanlines(&cinfo, &row, 1) != 1) {
            std::snprintf(err.message, sizeof err.message, "JPEG data ends at row %d of %d", y, sh);
            std::longjmp(err.jump, 1);
        }
        for (int x = 0; x < sw; ++x) {
            std::memcpy(&rgba[size_t(x) * 4], &rgb[size_t(x) * 3], 3);
            rgba[size_t(x) * 4 + 3] = 255;
        }
        shrink->addRow(y, rgba.data());
    }
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
    Rgba8Image out = shrink->take();
    out.factor = cinfo.scale_denom * out.factor;
    return out;
}

/// BMP and GIF have no scaled or row-by-row decoder here: stb decodes them whole, so beyond this
/// many pixels (256 MB of RGBA) they are refused from their header rather than decoded.
constexpr uint64_t kMaxWholeDecodePixels = uint64_t(8192) * 8192;

/// stb (BMP, GIF, interlaced PNG): the whole image, then box-filtered if it is too large.
std::optional<Rgba8Image> decodeStb(const unsigned char* bytes, size_t size, int maxSide, std::string& why) {
    int w = 0, h = 0, comp = 0;
    unsigned char* px = stbi_load_from_memory(bytes, int(size), &w, &h, &comp, 4);
    if (!px) return why = stbi_failure_reason(), std::nullopt;
    const int k = downsampleFactor(w, h, maxSide);
    Rgba8Image out;
    if (k == 1) {
        out.width = w;
        out.height = h;
        out.pixels.assign(px, px + size_t(w) * h * 4);
    } else {
        BoxShrinker s(w, h, k);
        for (int y = 0; y < h; ++y) s.addRow(y, px + size_t(y) * w * 4);
        out = s.take();
    }
    stbi_image_free(px);
    return out;
}

}  // namespace

std::string dataUriMime(const std::string& uri) {
    if (uri.rfind("data:", 0) != 0) return "";
    const size_t end = uri.find_first_of(";,", 5);
    return end == std::string::npos ? "" : uri.substr(5, end - 5);
}

std::optional<std::string> decodeDataUri(const std::string& uri, std::string* mime, std::string* why) {
    const size_t comma = uri.find(',');
    if (uri.rfind("data:", 0) != 0 || comma == std::string::npos) {
        if (why) *why = "malformed data URI (no ',')";
        return std::nullopt;
    }
    if (mime) *mime = dataUriMime(uri);
    const std::string params = uri.substr(5, comma - 5);
    const bool b64 = params.size() >= 7 && params.compare(params.size() - 7, 7, ";base64") == 0;
    std::string out;
    if (b64) {
        out.reserve((uri.size() - comma) / 4 * 3);
        uint32_t acc = 0;
        int bits = 0;
        for (size_t i = comma + 1; i < uri.size(); ++i) {
            const char c = uri[i];
            if (c == '=') break;
            if (c == '\n' || c == '\r') continue;
            const int v = base64Value(c);
            if (v < 0) {
                if (why) *why = std::string("data URI: '") + c + "' is not base64";
                return std::nullopt;
            }
            acc = (acc << 6) | uint32_t(v);
            bits += 6;
            if (bits >= 8) {
                bits -= 8;
                out += char((acc >> bits) & 0xff);
            }
        }
    } else {
        for (size_t i = comma + 1; i < uri.size(); ++i) {
            if (uri[i] == '%' && i + 2 < uri.size() && hexValue(uri[i + 1]) >= 0 && hexValue(uri[i + 2]) >= 0) {
                out += char(hexValue(uri[i + 1]) * 16 + hexValue(uri[i + 2]));
                i += 2;
            } else {
                out += uri[i];
            }
        }
    }
    return out;
}

namespace {

/// TGA has no signature: its 18-byte header must be one stb_image decodes (a colour map only
/// with a colour-mapped type, types 1-3 and 9-11 (run-length coded), a size, 8-32 bits). Asked
/// last, after every format that has one. glTF names PNG, JPEG (and WebP by extension) only;
/// TGA comes with the models assimp reads (COLLADA's and OBJ's textures).
bool looksLikeTga(const unsigned char* b, size_t n) {
    if (n < 18) return false;
    const unsigned colourMap = b[1], type = b[2], bits = b[16];
    const bool mapped = type == 1 || type == 9;
    if (colourMap > 1 || (mapped && colourMap != 1)) return false;
    if (!(mapped || type == 2 || type == 3 || type == 10 || type == 11)) return false;
    if (colourMap == 1 && !(b[7] == 15 || b[7] == 16 || b[7] == 24 || b[7] == 32)) return false;
    const unsigned width = b[12] | unsigned(b[13]) << 8, height = b[14] | unsigned(b[15]) << 8;
    if (width == 0 || height == 0) return false;
    if (mapped ? !(bits == 8 || bits == 16) : !(bits == 8 || bits == 15 || bits == 16 || bits == 24 || bits == 32)) return false;
    return (b[17] & 0xc0) == 0;  // no interleaving
}

}  // namespace

ImageFormat sniffImage(const unsigned char* b, size_t n) {
    if (startsWith(b, n, "\x89PNG\r\n\x1a\n", 8)) return ImageFormat::Png;
    if (startsWith(b, n, "\xff\xd8\xff", 3)) return ImageFormat::Jpeg;
    if (startsWith(b, n, "RIFF", 4) && startsWith(b, n, "WEBP", 4, 8)) return ImageFormat::WebP;
    if (startsWith(b, n, "\xabKTX 20\xbb\r\n\x1a\n", 12)) return ImageFormat::Ktx2;
    if (startsWith(b, n, "BM", 2)) return ImageFormat::Bmp;
    if (startsWith(b, n, "GIF8", 4)) return ImageFormat::Gif;
    if (looksLikeTga(b, n)) return ImageFormat::Tga;
    return ImageFormat::Unknown;
}

const char* formatName(ImageFormat f) {
    switch (f) {
        case ImageFormat::Png: return "PNG";
        case ImageFormat::Jpeg: return "JPEG";
        case ImageFormat::WebP: return "WebP";
        case ImageFormat::Ktx2: return "KTX2";
        case ImageFormat::Bmp: return "BMP";
        case ImageFormat::Gif: return "GIF";
        case ImageFormat::Tga: return "TGA";
        default: return "unknown";
    }
}

bool readImageHeader(const unsigned char* bytes, size_t size, ImageHeader& h, std::string& why) {
    h = ImageHeader{};
    h.format = sniffImage(bytes, size);
    int comp = 0;
    switch (h.format) {
        case ImageFormat::Unknown: why = "not a PNG, JPEG, WebP, BMP, GIF or TGA image"; return false;
        case ImageFormat::Ktx2:
            why = "a KTX2 (Basis Universal) image, which rayfarm cannot decode (Debian has no KTX2/Basis decoder)";
            return false;
        case ImageFormat::WebP:
            if (!WebPGetInfo(bytes, size, &h.width, &h.height)) return why = "unreadable WebP header", false;
            return true;
        default:
            if (size > size_t(INT32_MAX) || !stbi_info_from_memory(bytes, int(size), &h.width, &h.height, &comp))
                return why = std::string("unreadable ") + formatName(h.format) + " header", false;
            return true;
    }
}

int downsampleFactor(int width, int height, int maxSide) {
    const int side = std::max(width, height);
    if (maxSide <= 0 || side <= maxSide) return 1;
    return (side + maxSide - 1) / maxSide;
}

std::optional<Rgba8Image> decodeImage(const unsigned char* bytes, size_t size, int maxSide, std::string& why) {
    ImageHeader h;
    if (!readImageHeader(bytes, size, h, why)) return std::nullopt;
    if (h.format == ImageFormat::WebP) return decodeWebP(bytes, size, maxSide, why);
    if (h.format == ImageFormat::Png) {
        why.clear();
        if (auto img = decodePng(bytes, size, maxSide, why)) return img;
        if (!why.empty()) return std::nullopt;  // else interlaced: stb below
    }
    if (h.format == ImageFormat::Jpeg) return decodeJpeg(bytes, size, maxSide, why);
    if (size > size_t(INT32_MAX)) return why = "image over 2 GB", std::nullopt;
    if (uint64_t(h.width) * uint64_t(h.height) > kMaxWholeDecodePixels) {
        why = std::string(formatName(h.format)) + " of " + std::to_string(h.width) + "x" + std::to_string(h.height) +
              " is decoded whole and is too large for that (at most 8192x8192; PNG, JPEG and WebP are downsampled as they decode)";
        return std::nullopt;
    }
    return decodeStb(bytes, size, maxSide, why);
}

}  // namespace rf::gltf
