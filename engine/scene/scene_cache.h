#pragma once
/// Something derived from a whole scene and kept between frames, shared by the scene's copies
/// (the bounce light's cache, bounce_cache.h): a lock and the owner's state, which the owner
/// keys by what it was made from (SceneGeometry::version(), the lights), so a copy whose
/// geometry has moved on never reads what another copy made.
#include <memory>
#include <mutex>

namespace rf {

struct SceneCacheSlot {
    std::mutex mutex;
    std::shared_ptr<void> state;  ///< the owner's, of its own type; null until first used
};

}  // namespace rf
