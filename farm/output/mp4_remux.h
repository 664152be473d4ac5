#pragma once
/// The second pass of an MP4 or MOV written fragmented: while a film renders, Mp4Sink writes
/// one fragment per frame straight to the output (a moof/mdat pair flushed to disk as each
/// frame is encoded), so whatever ends the process, kill -9 included, the file plays every frame
/// flushed so far. Once the film is complete, remuxFaststart copies the same packets, not
/// re-encoded, into one moov placed before the media data (what players and web servers expect
/// of an MP4), and renames it over the fragmented file.
#include <limits>
#include <string>

namespace rf::farm {

/// Rewrites the fragmented file at `path` as a faststart file of muxer `muxer` ("mp4", "mov"):
/// packets are copied bit for bit, the stream keeps its codec parameters and the rate fps_num /
/// fps_den. Writes beside it (remuxTempPath) and renames, so `path` is a playable file at every
/// moment. expectedPackets (>= 0): the packets the encoder wrote; a file that reads back another
/// count, or a remuxed copy that does, is not renamed over it (another writer, lost writes).
/// Throws std::runtime_error "PATH: what failed: FFmpeg's reason".
void remuxFaststart(const std::string& path, const std::string& muxer, int fpsNum, int fpsDen, long expectedPackets = -1);

/// The temporary file of the second pass ("out.mp4.remux"); a crash between the two leaves it,
/// and the next run over the same output removes it.
std::string remuxTempPath(const std::string& path);

/// Video packets (a frame each) that can be read from the file at `path`, up to the first that
/// cannot (the torn last fragment of a killed run); 0 if it is missing or no video. Reading
/// stops at upTo (a long earlier video is not read through to learn it is long enough).
long readablePackets(const std::string& path, long upTo = std::numeric_limits<long>::max());

}  // namespace rf::farm
