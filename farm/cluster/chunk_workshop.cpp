#include "farm/cluster/chunk_workshop.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <map>
#include <stdexcept>

#include <fcntl.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "farm/output/chunk_encoder.h"
#include "farm/output/digest.h"
#include "farm/output/png_encoder.h"
#include "farm/output/video_chunk.h"

namespace rf::farm {

namespace {

/// Complete frames a rank holds for its encoder before it holds back its own engine's results
/// (and so the credit rank 0 gives back for them): enough that the encoder never waits, few
/// enough that a rank rendering its own chunk far faster than x264 encodes (near-free work:
/// bench_coordinator.sh) does not pile its frames up. Frames other ranks render for its chunks
/// are not held back (they come as those ranks run out of work of their own).
constexpr int kFramesAhead = 3;

/// Appends a message, its payload moved in. (Not push_back of a braced Outgoing: GCC 12's LTO
/// warns of a string copy reading past a 16-byte buffer there, -Wstringop-overread.)
void addOutgoing(std::vector<ChunkWorkshop::Outgoing>& out, int dest, int tag, std::string bytes) {
    ChunkWorkshop::Outgoing& o = out.emplace_back();
    o.dest = dest;
    o.tag = tag;
    o.bytes = std::move(bytes);
}

/// Test hook (mpi_render_test.sh lost-encoder, docs/testing.md): RAYFARM_TEST_STOP_ENCODING=F:FILE
/// stops (SIGSTOP) the first worker whose encoder has taken frame F into its chunk, the chunk
/// not yet finished, once it has written its pid to FILE; the test then kill -9's it there. The
/// file, created exclusively, makes it one rank only: the chunk opened again elsewhere
/// encodes on. Nothing when unset.
void stopMidChunkForTests(int rank, int frame) {
    static const char* const hook = std::getenv("RAYFARM_TEST_STOP_ENCODING");
    if (!hook || !*hook || rank == 0) return;
    const char* colon = std::strchr(hook, ':');
    if (!colon || std::atoi(hook) != frame) return;
    const int fd = ::open(colon + 1, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) return;  // another rank was stopped here already
    const std::string pid = std::to_string(::getpid()) + "\n";
    [[maybe_unused]] const ssize_t n = ::write(fd, pid.data(), pid.size());
    ::close(fd);
    std::raise(SIGSTOP);
}

}  // namespace

std::string encodeChunkVideoSpec(const ChunkVideoSpec& s) {
    const Mp4Options& o = s.options;
    // nlohmann writes doubles with enough digits to read back the same value: fps round-trips.
    const nlohmann::json j = {{"path", s.path},
                              {"width", s.width},
                              {"height", s.height},
                              {"fps", o.fps},
                              {"crf", o.crf},
                              {"preset", o.preset},
                              {"lossless", o.lossless},
                              {"codec", o.codec},
                              {"channels", o.channels},
                              {"over", {o.flattenOver[0], o.flattenOver[1], o.flattenOver[2]}},
                              {"chunk_frames", o.chunkFrames}};
    return j.dump();
}

ChunkVideoSpec decodeChunkVideoSpec(const std::string& bytes) {
    try {
        const nlohmann::json j = nlohmann::json::parse(bytes);
        ChunkVideoSpec s;
        s.path = j.at("path").get<std::string>();
        s.width = j.at("width").get<int>();
        s.height = j.at("height").get<int>();
        Mp4Options& o = s.options;
        o.fps = j.at("fps").get<double>();
        o.crf = j.at("crf").get<int>();
        o.preset = j.at("preset").get<std::string>();
        o.lossless = j.at("lossless").get<bool>();
        o.codec = j.at("codec").get<std::string>();
        o.channels = j.at("channels").get<int>();
        for (int c = 0; c < 3; ++c) o.flattenOver[c] = j.at("over").at(size_t(c)).get<uint8_t>();
        o.chunkFrames = j.at("chunk_frames").get<int>();
        return s;
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(std::string("malformed video settings in the job broadcast: ") + e.what());
    }
}

/// The encoder thread's own: made and used there only. A chunk's encoder lives from its first
/// frame to its last; several are open when frames of several chunks come in turn.
struct ChunkWorkshop::EncoderState {
    std::unique_ptr<PngEncoder> png;
    struct Open {
        std::unique_ptr<ChunkEncoder> video;
        EncodedChunk chunk;
    };
    std::map<int, Open> open;  ///< by chunk
};

ChunkWorkshop::ChunkWorkshop(RenderEngine& engine, ChunkVideoSpec spec, int rank)
    : engine_(engine), spec_(std::move(spec)), enc_(std::make_unique<EncoderState>()), rank_(rank) {
    thread_ = std::thread([this] { encoderLoop(); });
}

ChunkWorkshop::~ChunkWorkshop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
        tasks_.clear();
    }
    cv_.notify_all();
    thread_.join();
}

void ChunkWorkshop::submitAssembly(ChunkOrder order) {
    auto sp = std::make_shared<const ChunkOrder>(std::move(order));
    const WorkItem& c = sp->item;
    for (int f = c.frame; f < c.frame + c.frames; ++f) {
        Pending p;
        p.order = sp;
        p.frame = f;
        for (const auto& [frame, png] : sp->kept)
            if (frame == f) p.keptPng = &png;
        if (!p.keptPng) p.pixelsLeft = int64_t(spec_.width) * spec_.height;
        pending_.push_back(std::move(p));
    }
    ++chunksOut_;
    std::vector<TileResult> early = std::exchange(early_, {});
    for (TileResult& t : early)
        if (!placeTile(t)) early_.push_back(std::move(t));
}

bool ChunkWorkshop::placeTile(TileResult& tile) {
    const auto it = std::find_if(pending_.begin(), pending_.end(),
                                 [&](const Pending& p) { return !p.keptPng && p.frame == tile.item.frame; });
    if (it == pending_.end()) return false;
    const int w = spec_.width, h = spec_.height, ch = spec_.options.channels;
    const TileRect& r = tile.item.rect;
    const std::string bad = "a tile of frame " + std::to_string(tile.item.frame) + " ";
    if (r.x0 < 0 || r.y0 < 0 || r.x1 > w || r.y1 > h || r.x0 >= r.x1 || r.y0 >= r.y1 || tile.layout.channels != ch ||
        tile.rgb.size() != size_t(r.pixels()) * size_t(ch))
        throw std::runtime_error(bad + "does not fit the frame");
    // A frame or tile that came before: rendered again after its rank was lost (rank 0 had not
    // heard it was done), the same pixels, so the copy is dropped.
    if (it->pixelsLeft == 0) return true;
    if (it->pixelsLeft == r.pixels() && it->pixels.empty()) {  // the whole frame at once (frame mode): taken as it is
        it->pixels = std::move(tile.rgb);
        it->pixelsLeft = 0;
        return true;
    }
    if (it->pixels.empty()) {
        it->pixels.resize(size_t(w) * size_t(h) * size_t(ch));
        it->covered.resize(size_t(w) * size_t(h));
    }
    const auto rowOf = [&](int y) { return it->covered.begin() + long(size_t(y) * size_t(w) + size_t(r.x0)); };
    int64_t seen = 0;
    for (int y = r.y0; y < r.y1; ++y) seen += std::count(rowOf(y), rowOf(y) + r.width(), uint8_t{1});
    if (seen == r.pixels()) return true;  // the same tile again (above)
    if (seen > 0) throw std::runtime_error(bad + "overlaps one placed before");
    const size_t row = size_t(r.width()) * size_t(ch);
    for (int y = r.y0; y < r.y1; ++y) {
        std::copy_n(tile.rgb.data() + size_t(y - r.y0) * row, row, it->pixels.data() + (size_t(y) * size_t(w) + size_t(r.x0)) * size_t(ch));
        std::fill_n(rowOf(y), r.width(), uint8_t{1});
    }
    it->pixelsLeft -= r.pixels();
    return true;
}

void ChunkWorkshop::addTile(TileResult tile) {
    if (!placeTile(tile)) early_.push_back(std::move(tile));
    queueReady();
}

int ChunkWorkshop::encoderBacklog() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return int(tasks_.size()) + (working_ ? 1 : 0);
}

/// Hands the encoder thread every frame whose turn in its chunk has come: kept frames at once,
/// the others once their last tile (or their whole frame) is here. Chunks do
/// not wait for each other: a rank assembling two chunks whose frames come in turn encodes both
/// as they come (each has its own encoder), rather than holding the later chunk's frames.
void ChunkWorkshop::queueReady() {
    std::vector<Task> ready;
    std::vector<int> waiting;  ///< chunks with an earlier frame not ready yet
    for (auto it = pending_.begin(); it != pending_.end();) {
        Pending& p = *it;
        const int chunk = p.order->item.chunk;
        if (std::find(waiting.begin(), waiting.end(), chunk) != waiting.end()) {
            ++it;
            continue;
        }
        Task t;
        bool here = false;
        if (p.keptPng) {
            t.keptPng = p.keptPng;
            here = true;
        } else if (p.pixelsLeft == 0) {
            t.result.rgb = std::move(p.pixels);
            p.covered = {};
            here = true;
        }
        if (!here) {
            waiting.push_back(chunk);
            ++it;
            continue;
        }
        t.order = p.order;
        t.frame = p.frame;
        t.first = p.frame == p.order->item.frame;
        t.last = p.frame == p.order->item.frame + p.order->item.frames - 1;
        ready.push_back(std::move(t));
        it = pending_.erase(it);
    }
    if (ready.empty()) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (Task& t : ready) tasks_.push_back(std::move(t));
    }
    cv_.notify_all();
}

std::vector<ChunkWorkshop::Outgoing> ChunkWorkshop::poll(double waitSeconds) {
    std::vector<Outgoing> out;
    for (auto r = engine_.takeResult(waitSeconds); r; r = engine_.takeResult()) {
        if (r->item.assembler == rank_) {
            own_.push_back(std::move(*r));  // placed below
        } else if (r->item.assembler >= 0) {
            // A frame or tile another rank assembles: its pixels there, word of it to rank 0.
            addOutgoing(out, 0, kTagTileDone, encodeTileDone(*r));
            addOutgoing(out, r->item.assembler, kTagTile, encodeTileResult(*r));
        } else {
            addOutgoing(out, 0, kTagResult, encodeTileResult(*r));  // a single item: as runWorker sends it
        }
    }
    // Results this rank assembles itself are placed, and rank 0 told of them (which frees their
    // credit for more work), while the encoder keeps up: it has fewer than kFramesAhead whole
    // frames waiting.
    while (!own_.empty() && encoderBacklog() < kFramesAhead) {
        addOutgoing(out, 0, kTagTileDone, encodeTileDone(own_.front()));
        addTile(std::move(own_.front()));
        own_.pop_front();
    }
    queueReady();
    std::vector<Outgoing> posted;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        posted.swap(outbox_);
    }
    for (Outgoing& m : posted) {
        if (m.tag == kTagChunkDone) --chunksOut_;
        out.push_back(std::move(m));
    }
    return out;
}

int ChunkWorkshop::outstanding() const { return chunksOut_; }

std::string ChunkWorkshop::error() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return error_.empty() ? engine_.error() : error_;
}

void ChunkWorkshop::cancel() {
    pending_.clear();
    own_.clear();
    early_.clear();
    chunksOut_ = 0;
    std::lock_guard<std::mutex> lock(mutex_);
    tasks_.clear();
}

void ChunkWorkshop::post(int tag, std::string bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    addOutgoing(outbox_, 0, tag, std::move(bytes));
}

void ChunkWorkshop::encoderLoop() {
    for (;;) {
        Task t;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            cv_.wait(lock, [&] { return stop_ || !tasks_.empty(); });
            if (stop_) return;
            t = std::move(tasks_.front());
            tasks_.pop_front();
            working_ = true;  // still a frame waiting for the encoder (encoderBacklog)
        }
        try {
            encodeTask(t);
        } catch (const std::exception& e) {
            std::lock_guard<std::mutex> lock(mutex_);
            error_ = "frame " + std::to_string(t.frame) + ": " + e.what();
            tasks_.clear();
            return;
        }
        std::lock_guard<std::mutex> lock(mutex_);
        working_ = false;
    }
}

/// One frame: its PNG and pixels for rank 0 if asked for, then into the chunk's encoder; the
/// chunk goes out after its last frame.
void ChunkWorkshop::encodeTask(Task& t) {
    EncoderState& st = *enc_;
    const ChunkOrder& o = *t.order;
    const int w = spec_.width, h = spec_.height, ch = spec_.options.channels;
    const size_t planeBytes = size_t(w) * h * size_t(ch);
    std::vector<uint8_t> decoded;
    const std::vector<uint8_t>* pixels = &t.result.rgb;
    ChunkFrame cf;
    cf.item = o.item;
    cf.frame = t.frame;
    if (t.keptPng) {
        decoded = decodePngFrame(*t.keptPng, "kept frame " + std::to_string(t.frame), w, h, ch);
        pixels = &decoded;
        cf.wasKept = 1;
    } else {
        if (pixels->size() < planeBytes) throw std::runtime_error("rendered frame has the wrong size");
        if (o.sendPngs) {
            if (!st.png) st.png = std::make_unique<PngEncoder>(w, h, ch);
            cf.png = st.png->encode(*pixels);
            cf.pngSha256 = sha256Hex(cf.png);  // here, not on rank 0: its CPU is the farm's ceiling
        }
    }
    if (std::find(o.rawWanted.begin(), o.rawWanted.end(), t.frame) != o.rawWanted.end())
        cf.pixels.assign(pixels->begin(), pixels->begin() + long(planeBytes));
    post(kTagChunkFrame, encodeChunkFrame(cf));

    const auto t0 = std::chrono::steady_clock::now();
    const int index = o.item.chunk;
    if (t.first) {
        EncoderState::Open& c = st.open[index];
        c.video = std::make_unique<ChunkEncoder>(spec_.path, w, h, spec_.options, spec_.options.chunkFrames);
        c.chunk = EncodedChunk{};
        c.chunk.index = index;
        c.chunk.frames = o.item.frames;
    }
    const auto it = st.open.find(index);
    if (it == st.open.end()) throw std::runtime_error("chunk " + std::to_string(index) + " began mid-chunk");
    EncoderState::Open& c = it->second;
    for (ChunkPacket& p : c.video->add(*pixels)) c.chunk.packets.push_back(std::move(p));
    if (!t.last) stopMidChunkForTests(rank_, t.frame);
    if (t.last) {
        for (ChunkPacket& p : c.video->finish()) c.chunk.packets.push_back(std::move(p));
        c.chunk.extradata = c.video->extradata();
    }
    c.chunk.encodeSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (t.last) {
        post(kTagChunkDone, encodeChunkDone(o.item, serializeChunk(c.chunk)));
        st.open.erase(it);
    }
}

}  // namespace rf::farm
