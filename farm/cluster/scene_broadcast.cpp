#include "farm/cluster/scene_broadcast.h"

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <set>
#include <thread>

#include "farm/cluster/build_beats.h"
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

[[noreturn]] void failBroadcast(Transport& t, const char* code) {
    std::string fail = code;
    t.broadcast(fail, 0);
    throw;  // NOLINT: only called from a catch block
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
                       const std::function<void(LoadedScene&)>& headStart, std::shared_ptr<SceneCacheSlot> bounceSlot) {
    const auto t0 = std::chrono::steady_clock::now();
    SharedScene out;
    out.bounceSlot = bounceSlot ? std::move(bounceSlot) : std::make_shared<SceneCacheSlot>();
    std::string payload;
    if (t.rank() == 0) {
        // Two broadcasts: the files as soon as the loader has read them (before the BVH and the
        // environment maps are built), so the workers build their scenes while rank 0 builds its
        // own; then the job, with any file read after the first. One failure code takes the
        // place of whichever broadcast is next.
        DiskFileSource fs;
        std::set<std::string> sent;
        bool filesShared = false;
        auto shareFiles = [&] {
            if (filesShared) return;
            filesShared = true;
            for (const auto& [p, bytes] : fs.bundle().files) sent.insert(p);
            if (t.size() > 1) {
                std::string files(1, '0');
                files += fs.bundle().serialize();
                t.broadcast(files, 0);
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
        } catch (const InputError&) {
            failBroadcast(t, "2");
        } catch (const UsageError&) {
            failBroadcast(t, "2");
        } catch (...) {
            failBroadcast(t, "1");
        }
        if (t.size() > 1) t.broadcast(payload, 0);
    } else {
        auto receive = [&] {
            t.broadcast(payload, 0);
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
