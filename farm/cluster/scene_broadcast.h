#pragma once
/// The scene travels once: rank 0 reads the scene file and every file it references, the bytes
/// are broadcast (in chunks, so scenes beyond 2 GiB work) and every rank loads the same scene
/// from memory and builds its own BVH. Workers never open the scene files. The files go out as
/// soon as rank 0's loader has read them (SceneOptions::inputsRead), so the workers build while
/// rank 0 builds and decides the job; the job follows in a second broadcast.
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

#include "engine/util/file_source.h"
#include "engine/load/loaded_scene.h"
#include "engine/scene/scene_cache.h"
#include "engine/scene/scene_options.h"
#include "farm/cluster/transport.h"

namespace rf::farm {

/// Thrown on a worker when rank 0 failed before the broadcast (rank 0 reports the error).
class PeerFailed : public std::runtime_error {
public:
    explicit PeerFailed(int code) : std::runtime_error("rank 0 failed"), code_(code) {}
    int code() const { return code_; }

private:
    int code_;
};

/// The scene and its timeline source (LoadedScene), as every rank loaded them.
struct SharedScene : LoadedScene {
    /// The job's bounce cache (RenderView::bounceSlot): a worker's head start and rank 0's
    /// metering fill it before the job, and the rank's RenderEngine renders every frame with it.
    std::shared_ptr<SceneCacheSlot> bounceSlot;
    std::string job;          ///< rank 0's job description, opaque here
    size_t bundleBytes = 0;   ///< the scene's files that travel: their paths' and contents' bytes
    double loadSeconds = 0.0; ///< reading, broadcast and loading on this rank

    LoadedScene& loaded() { return *this; }
};

/// Collective over all ranks. On rank 0: runs preLoad (output checks), loads path from disk,
/// then makeJob(scene, the files it read). If any of those throws, the other ranks are told (they throw PeerFailed
/// with exit code 2 for input errors, 1 otherwise) and rank 0 rethrows. options.inputsRead, if
/// set, is called on every rank once its loader has read the files (on rank 0 after sending them).
/// options (the command line's environment) apply on every rank; files they name travel in the
/// bundle with the scene's. headStart, if set, runs on each worker once its scene is built,
/// while rank 0 is still deciding the job (work a worker can begin before the job comes; an
/// exception from it is dropped). bounceSlot: the one makeJob and headStart fill, handed back
/// as SharedScene::bounceSlot (null: a new one). Rank 0 tells the workers it runs while it
/// loads and broadcasts; a worker waiting for a broadcast gives rank 0 up (prints why, throws
/// MasterLost) once it sees rank 0's process has ended or rank 0 has been silent for
/// masterSilence seconds (master_watch.h).
SharedScene shareScene(Transport& t, const std::string& path, const std::function<void()>& preLoad,
                       const std::function<std::string(LoadedScene&, const FileBundle&)>& makeJob,
                       const SceneOptions& options = {}, const std::function<void(LoadedScene&)>& headStart = nullptr,
                       std::shared_ptr<SceneCacheSlot> bounceSlot = nullptr, double masterSilence = 20.0);

}  // namespace rf::farm
