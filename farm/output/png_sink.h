#pragma once
/// The frames directory: one PNG per frame (frame_000012.png, the timeline's index), written as
/// each frame completes, plus a manifest naming the settings, so --resume can trust what it finds.
#include <map>
#include <set>
#include <string>
#include <vector>

#include "engine/util/file_source.h"
#include "anim/frame_ranges.h"
#include "farm/output/frame_sink.h"
#include "farm/output/png_encoder.h"

namespace rf::farm {

/// DIR/frame_NNNNNN.png
std::string framePngPath(const std::string& dir, int frame);

/// Writes each frame to a temporary name and renames it, so a frame file is either whole or
/// absent even if the run is killed mid-write; then records its SHA-256 in the manifest's
/// checksum list.
class PngSink : public FrameSink {
public:
    /// channels: the 8-bit plane's, 3 (RGB) or 4 (straight RGBA); a linear plane after it is ignored.
    PngSink(std::string dir, int width, int height, int channels = 3)
        : dir_(std::move(dir)), width_(width), height_(height), channels_(channels) {}
    void write(int frame, const std::vector<uint8_t>& rgb) override;
    /// A frame compressed where it was rendered: written as it is, with the digest sent along.
    void writePng(int frame, const std::string& png, const std::string& sha256) override;
    void close() override {}

private:
    std::string dir_;
    int width_, height_, channels_;
    std::unique_ptr<PngEncoder> encoder_;  ///< made on the sink's thread, at the first frame
};

/// SHA-256 of every file of the scene bundle (the scene, its models, buffers, textures,
/// timeline), by path: what --resume compares to refuse frames of a changed input.
std::map<std::string, std::string> inputDigests(const FileBundle& bundle);

/// The manifest: what the frames in a directory were rendered from (scene, size, quality, the
/// digest of every input file). Writes DIR/rayfarm-frames.json and starts an empty
/// DIR/rayfarm-frames.sha256, to which PngSink adds each frame's digest.
void writeFramesManifest(const std::string& dir, const std::string& identity, const std::map<std::string, std::string>& inputs);
/// Throws UsageError naming the directory if its manifest is missing or differs, in one
/// line that names the setting or the input file that changed.
void checkFramesManifest(const std::string& dir, const std::string& identity, const std::map<std::string, std::string>& inputs);

/// A fresh run starts from an empty frames directory: frames left by an earlier job must not be
/// mistaken for this one's by a later --resume. Creates dir if needed; throws UsageError
/// when it holds frame PNGs without rayfarm's manifest (someone else's files).
void prepareFramesDir(const std::string& dir);

/// Appends whole lines to DIR/rayfarm.log, the frames directory's log: each run's plan and how
/// it ended (the resume command included), readable there when stderr is gone (a dropped ssh
/// session, `| head`). Best effort: a failure to log is not the run's failure.
void appendFramesLog(const std::string& dir, const std::string& lines);

/// A run without --resume (or --overwrite) must not throw away an earlier run's frames without
/// a word: throws UsageError naming dir and both ways on when it holds finished frames.
void refuseEarlierFrames(const std::string& dir);

/// The frame a file of the frames directory holds: "frame_000012.png" -> 12, "frame_1234567.png"
/// -> 1234567 (%06d grows past six digits); -1 for any name this rayfarm does not write
/// ("frame_12.png", "frame_0000012.png", another extension).
int frameOfFileName(const std::string& name, const std::string& extension);
/// The frames of `frames` that have a file frame_NNNNNN.EXTENSION in dir, in increasing order:
/// one pass over the directory, whatever the selection's length.
std::vector<int> framesInDir(const std::string& dir, const std::string& extension, const anim::FrameRanges& frames);

/// Frames of `frames` already in dir as complete PNGs of width × height whose SHA-256 matches
/// the one recorded when they were written. Frames present but failing that check are listed
/// in `corrupt` (they are rendered again). channels: 3 (RGB PNGs) or 4 (RGBA).
anim::FrameRanges findKeptFrames(const std::string& dir, const anim::FrameRanges& frames, int width, int height,
                                 std::vector<int>* corrupt = nullptr, int channels = 3);

/// The notes for the damaged frames a resume renders again, one line each: a PNG of `corrupt`
/// that does not match its checksum or has none recorded (one line for them all when the
/// checksum list itself is missing), or anything but a regular file in place of a PNG (of
/// `corrupt`) or, with exr, of an EXR frame of `frames`. Such a thing is moved out of the
/// frame's way first: a directory renamed FRAME.not-a-frame (its contents kept), anything else
/// (a FIFO, a socket, a device node) removed from the frames directory. Throws
/// std::runtime_error naming it if it cannot be moved.
std::vector<std::string> damagedFrameNotes(const std::string& dir, const std::vector<int>& corrupt, const anim::FrameRanges& frames,
                                           bool exr);

}  // namespace rf::farm
