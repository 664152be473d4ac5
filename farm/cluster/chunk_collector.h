#pragma once
/// Rank 0's reorder buffer with chunked encoding: encoded chunks arrive in any order from the
/// ranks that encoded them and leave in film order, to be joined into the video
/// (Mp4Sink::writeChunk). It holds compressed chunks only, and the few frames' pixels the
/// contact sheet and poster want until their chunk's turn.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "farm/output/video_chunk.h"

namespace rf::farm {

class ChunkCollector {
public:
    explicit ChunkCollector(ChunkPlan plan) : plan_(plan) {}

    /// A chunk's encoded bytes (serializeChunk), as they arrived. Throws std::runtime_error for a
    /// chunk outside the film, already passed on, or already here.
    void add(int chunk, std::string bytes);
    /// The next chunk in film order, if it is here.
    bool popReady(int& chunk, std::string& bytes);
    /// Pixels of a frame that rank 0's pictures (contact sheet, poster) want, held until its chunk leaves.
    void holdPixels(int frame, std::vector<uint8_t> pixels);
    /// The held frames of a chunk that left, in order.
    std::vector<std::pair<int, std::vector<uint8_t>>> takePixels(int chunk);
    bool finished() const { return next_ >= plan_.count(); }
    /// Frames of the chunks passed on.
    int framesPopped() const { return framesPopped_; }
    /// Chunks waiting for an earlier one.
    int held() const { return int(waiting_.size()); }
    const ChunkPlan& plan() const { return plan_; }

private:
    ChunkPlan plan_;
    int next_ = 0;
    int framesPopped_ = 0;
    std::map<int, std::string> waiting_;
    std::map<int, std::vector<uint8_t>> pixels_;
};

}  // namespace rf::farm
