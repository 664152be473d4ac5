#pragma once
/// Container and codec from the output's name, and what --codec, --crf, --preset and --lossless
/// mean for each: decided and checked before anything is rendered.
///   .mp4  H.264 (libx264): --crf 0–51 (18), --preset x264's (ultrafast); no alpha: a transparent
///         background is laid over the scene's background colour
///   .webm VP9 (libvpx-vp9): --crf 0–63 (32), --preset maps x264's names onto cpu-used 8…0;
///         yuva420p with alpha
///   .mov  ProRes (prores_ks): --preset is the profile, 4444 (default) or 4444xq, with alpha
///         (yuva444p10le), or hq, standard, lt, proxy (4:2:2, no alpha); no --crf
///   .gif  a palette made for the film (palettegen/paletteuse), looping: --preset is the dither
///         (sierra2_4a default, bayer, floyd_steinberg, none); one-bit transparency; no --crf
#include <string>
#include <utility>
#include <vector>

namespace rf::farm {

enum class Container { Mp4, Webm, Mov, Gif };

struct VideoRequest {
    std::string path;
    std::string codec;      ///< --codec, "" for the container's default
    int crf = -1;           ///< --crf, -1 if not given
    std::string preset;     ///< --preset, "" if not given
    bool lossless = false;  ///< --lossless
    bool alpha = false;     ///< the frames have a transparent background
};

struct VideoFormat {
    Container container = Container::Mp4;
    std::string muxer;        ///< libavformat's name
    std::string encoder;      ///< libavcodec's name
    std::string pixFmt;       ///< the encoder's pixel format (libavutil's name)
    bool alpha = false;       ///< the file carries alpha
    bool evenSize = true;     ///< chroma subsampled: an odd size is padded by one row/column
    std::vector<std::pair<std::string, std::string>> encoderOptions;
    std::string describe;     ///< "VP9 crf 32 cpu-used 6, yuva420p", for the log and the stats
};

/// Throws std::invalid_argument with one line for the user on an unknown extension or an
/// unsupported combination (e.g. --codec vp9 with .mp4, --crf with .mov, an encoder missing
/// from this FFmpeg).
VideoFormat videoFormatFor(const VideoRequest& r);

/// FFmpeg's text for an error code (av_strerror).
std::string avErrorText(int rc);

/// The container an output name asks for; throws std::invalid_argument for other names.
Container containerFor(const std::string& path);

}  // namespace rf::farm
