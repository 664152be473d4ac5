#include "farm/cluster/scene_broadcast.h"

#include <algorithm>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <cstdio>
#include <exception>
#include <optional>
#include <set>
#include <thread>

#include <unistd.h>

#include "farm/cluster/build_beats.h"
#include "farm/cluster/master_watch.h"
#include "farm/cluster/messages.h"
#include "engine/util/load_control.h"
#include "farm/process/usage_error.h"
#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "engine/load/scene_loader.h"

namespace rf::farm {

namespace {

// Two broadcasts, each led by a status byte ('0' ok, '1'/'2' failed with that exit code). The
// first, if ok: the serialized file bundle. The second (packOk): 8-byte job length, job, the
// bundle of files read after the first.
std::string packOk(const std::string& job, const std::string& bundle) {
    std::string out = "0";
    const uint64_t n = job.size();
    out.append(reinterpret_cast<const char*>(&n), sizeof n);
    out += job;
    out += bundle;
    return out;
}

/// Rank 0's side of a broadcast: beats to every worker while it waits for the broadcast to
/// leave (a large scene), as while it loads.
void sendWatched(Transport& t, std::string& bytes) {
    auto last = std::chrono::steady_clock::now();
    t.broadcastWatched(bytes, 0, [&t, &last] {
        const auto now = std::chrono::steady_clock::now();
        if (std::chrono::duration<double>(now - last).count() < kHeartbeatSeconds) return;
        last = now;
        sayAlive(t);
    });
}

[[noreturn]] void failBroadcast(Transport& t, std::optional<BuildBeats>& beats, const char* code) {
    beats.reset();  // joined: this thread uses the transport
    std::string fail = code;
    sendWatched(t, fail);
    throw;  // NOLINT: only called from a catch block
}

/// Test hook (mpi_render_test.sh lost-master-load): RAYFARM_TEST_MASTER_HOLD=files (or job)
/// holds rank 0 before it broadcasts the scene's files (the job), beating as it does while it
/// loads a huge model, so that the test can kill it there. Off unless set; lasts at most 120 s.
void testMasterHold(const char* stage) {
    static const char* hold = std::getenv("RAYFARM_TEST_MASTER_HOLD");
    if (!hold || std::strcmp(hold, stage) != 0) return;
    char line[128];
    std::snprintf(line, sizeof line, "rayfarm: test: rank 0 holds before broadcasting the %s\n", stage);
    [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, line, std::strlen(line));
    LoadStep step("holding (test)");
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (std::chrono::steady_clock::now() < end) {
        pollLoadCancel();
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

/// A worker's side of a broadcast: rank 0's beats read while it waits, and rank 0 given up
/// (MasterLost) when master_watch.h says so.
void receiveWatched(Transport& t, std::string& bytes, MasterWatch& watch) {
    t.broadcastWatched(bytes, 0, [&t, &watch] {
        const auto now = std::chrono::steady_clock::now();
        Message m;
        while (t.take(0, kTagAlive, m)) watch.heard(now);
        if (const std::string line = watch.lost(now); !line.empty()) {
            [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, line.data(), line.size());
            throw MasterLost(line);
        }
    });
}

/// Test hook (tests/farm/cluster/load_signal_test.sh): RAYFARM_TEST_WORKER_BUILD_SECONDS makes a
/// worker's build last that much longer, as a slow machine or a huge scene would, so the test can
/// show rank 0 counting a building worker alive. Off unless set; a cancelled load ends it.
void testBuildDelay() {
    static const char* seconds = std::getenv("RAYFARM_TEST_WORKER_BUILD_SECONDS");
    if (!seconds) return;
    LoadStep step("building the scene (test delay)");
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(std::atof(seconds));
    while (std::chrono::steady_clock::now() < end) {
        pollLoadCancel();
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

/// The files in `all` that `sent` does not hold.
FileBundle filesSince(const FileBundle& all, const std::set<std::string>& sent) {
    FileBundle out;
    for (const auto& [path, bytes] : all.files)
        if (!sent.count(path)) out.files.emplace(path, bytes);
    return out;
}

}  // namespace

SharedScene shareScene(Transport& t, const std::string& path, const std::function<void()>& preLoad,
                       const std::function<std::string(LoadedScene&, const FileBundle&)>& makeJob, const SceneOptions& options,
                       const std::function<void(LoadedScene&)>& headStart, std::shared_ptr<SceneCacheSlot> bounceSlot,
                       double masterSilence) {
    const auto t0 = std::chrono::steady_clock::now();
    SharedScene out;
    out.bounceSlot = bounceSlot ? std::move(bounceSlot) : std::make_shared<SceneCacheSlot>();
    std::string payload;
    if (t.rank() == 0) {
        // Two broadcasts: the files as soon as the loader has read them (before the BVH and the
        // environment maps are built), so the workers build their scenes while rank 0 builds its
        // own; then the job, with any file read after the first. One failure code takes the
        // place of whichever broadcast is next.
        // While it loads, rank 0 tells the workers waiting for it that it runs (its beats stop
        // while this thread broadcasts, which beats by itself).
        DiskFileSource fs;
        std::set<std::string> sent;
        bool filesShared = false;
        std::optional<BuildBeats> beats;
        beats.emplace(t);
        auto shareFiles = [&] {
            if (filesShared) return;
            filesShared = true;
            for (const auto& [p, bytes] : fs.bundle().files) sent.insert(p);
            if (t.size() > 1) {
                testMasterHold("files");
                std::string files(1, '0');
                files += fs.bundle().serialize();
                beats.reset();
                sendWatched(t, files);
                beats.emplace(t);
            }
            if (options.inputsRead) options.inputsRead();
        };
        try {
            if (preLoad) preLoad();
            SceneOptions opts = options;
            opts.inputsRead = shareFiles;
            out.loaded() = loadScene(path, fs, opts);
            shareFiles();  // a loader that has no such point shares them here
            out.job = makeJob ? makeJob(out, fs.bundle()) : std::string();
            out.bundleBytes = fs.bundle().totalBytes();
            payload = packOk(out.job, filesSince(fs.bundle(), sent).serialize());
            if (t.size() > 1) testMasterHold("job");
        } catch (const InputError&) {
            failBroadcast(t, beats, "2");
        } catch (const UsageError&) {
            failBroadcast(t, beats, "2");
        } catch (...) {
            failBroadcast(t, beats, "1");
        }
        beats.reset();
        if (t.size() > 1) sendWatched(t, payload);
    } else {
        // Rank 0 may load a huge model for minutes before each broadcast: the wait lasts as
        // long as its beats come, and ends when it is gone (master_watch.h). Before its first
        // beat the limit is longer: in a batch, a worker waits here for the next film while
        // rank 0, not beating, finishes the last one (its own frame, stats, the next set-up).
        MasterWatch watch(t, masterSilence, std::max(24.0, 6.0 * masterSilence));
        auto receive = [&] {
            receiveWatched(t, payload, watch);
            if (payload.empty() || payload[0] != '0') throw PeerFailed(payload == "2" ? 2 : 1);
        };
        receive();
        BundleFileSource fs(FileBundle::deserialize(payload.substr(1)));
        payload.clear();
        payload.shrink_to_fit();
        // Built from the files while rank 0 decides the job; a failure here is told only if
        // rank 0 succeeded (else rank 0 reports its own).
        std::exception_ptr failed;
        {
            BuildBeats beats(t);  // rank 0 hears this rank builds; joined before the next MPI call
            try {
                out.loaded() = loadScene(path, fs, options);
                testBuildDelay();
            } catch (...) {
                failed = std::current_exception();
            }
            if (!failed && headStart) {
                try {
                    headStart(out);
                } catch (...) {
                    // Only a head start: the job, when it comes, decides.
                }
            }
        }
        receive();
        uint64_t n = 0;
        if (payload.size() < 1 + sizeof n) throw std::runtime_error("malformed scene broadcast");
        std::memcpy(&n, payload.data() + 1, sizeof n);
        if (n > payload.size() - 1 - sizeof n) throw std::runtime_error("malformed scene broadcast");
        out.job = payload.substr(1 + sizeof n, n);
        FileBundle late = FileBundle::deserialize(payload.substr(1 + sizeof n + n));
        payload.clear();
        payload.shrink_to_fit();
        if (!late.files.empty()) {
            // Rank 0's loader read more after it shared the files: load again with all of them.
            fs.add(std::move(late));
            BuildBeats beats(t);
            out.loaded() = loadScene(path, fs, options);
        } else if (failed) {
            std::rethrow_exception(failed);
        }
        out.bundleBytes = fs.bundleBytes();
    }
    out.loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

}  // namespace rf::farm
