#include "farm/cluster/chunk_collector.h"

#include <stdexcept>

namespace rf::farm {

void ChunkCollector::add(int chunk, std::string bytes) {
    if (chunk < next_ || chunk >= plan_.count()) throw std::runtime_error("chunk " + std::to_string(chunk) + ": not a chunk being rendered");
    if (!waiting_.emplace(chunk, std::move(bytes)).second) throw std::runtime_error("chunk " + std::to_string(chunk) + " came twice");
}

bool ChunkCollector::popReady(int& chunk, std::string& bytes) {
    auto it = waiting_.find(next_);
    if (it == waiting_.end()) return false;
    chunk = next_++;
    bytes = std::move(it->second);
    waiting_.erase(it);
    framesPopped_ += plan_.framesIn(chunk);
    return true;
}

void ChunkCollector::holdPixels(int frame, std::vector<uint8_t> pixels) { pixels_[frame] = std::move(pixels); }

std::vector<std::pair<int, std::vector<uint8_t>>> ChunkCollector::takePixels(int chunk) {
    std::vector<std::pair<int, std::vector<uint8_t>>> out;
    auto it = pixels_.lower_bound(plan_.firstFrame(chunk));
    while (it != pixels_.end() && it->first <= plan_.lastFrame(chunk)) {
        out.emplace_back(it->first, std::move(it->second));
        it = pixels_.erase(it);
    }
    return out;
}

}  // namespace rf::farm
