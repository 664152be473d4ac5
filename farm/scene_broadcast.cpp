#include "scene_broadcast.h"

#include <chrono>
#include <cstring>

#include "cli.h"
#include "errors.h"
#include "file_source.h"
#include "scene_loader.h"

namespace rf::farm {

namespace {

// Broadcast layout: status byte ('0' ok, '1'/'2' failed with that exit code), then for ok:
// 8-byte job length, job, bundle.
std::string packOk(const std::string& job, const std::string& bundle) {
    std::string out = "0";
    const uint64_t n = job.size();
    out.append(reinterpret_cast<const char*>(&n), sizeof n);
    out += job;
    out += bundle;
    return out;
}

}  // namespace

SharedScene shareScene(Transport& t, const std::string& path, const std::function<void()>& preLoad,
                       const std::function<std::string(Scene&, const FileBundle&)>& makeJob, const SceneOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    SharedScene out;
    std::string payload;
    if (t.rank() == 0) {
        try {
            if (preLoad) preLoad();
            DiskFileSource fs;
            out.scene = loadScene(path, fs, options);
            out.job = makeJob ? makeJob(out.scene, fs.bundle()) : std::string();
            const std::string bundle = fs.bundle().serialize();
            out.bundleBytes = bundle.size();
            payload = packOk(out.job, bundle);
        } catch (const InputError&) {
            std::string fail = "2";
            t.broadcast(fail, 0);
            throw;
        } catch (const cli::UsageError&) {
            std::string fail = "2";
            t.broadcast(fail, 0);
            throw;
        } catch (...) {
            std::string fail = "1";
            t.broadcast(fail, 0);
            throw;
        }
        if (t.size() > 1) t.broadcast(payload, 0);
    } else {
        t.broadcast(payload, 0);
        if (payload.empty() || payload[0] != '0') throw PeerFailed(payload == "2" ? 2 : 1);
        uint64_t n = 0;
        if (payload.size() < 1 + sizeof n) throw std::runtime_error("malformed scene broadcast");
        std::memcpy(&n, payload.data() + 1, sizeof n);
        out.job = payload.substr(1 + sizeof n, n);
        const size_t bundleAt = 1 + sizeof n + n;
        out.bundleBytes = payload.size() - bundleAt;
        FileBundle bundle = FileBundle::deserialize(payload.substr(bundleAt));
        payload.clear();
        payload.shrink_to_fit();
        BundleFileSource fs(std::move(bundle));
        out.scene = loadScene(path, fs, options);
    }
    out.loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

}  // namespace rf::farm
