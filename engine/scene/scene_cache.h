#pragma once
/// Something derived from a whole scene and kept between the frames of one job (the bounce
/// light's cache, bounce_cache.h): a lock and the owner's state, which the owner keys by what it
/// was made from (SceneGeometry::version(), the lights), so a scene whose geometry has moved on
/// never reads what another pose made. The job holds it, not the scene (RenderView::bounceSlot,
/// farm::SharedScene, RenderEngine): whatever renders that job's frames, on whichever copy of
/// its scene, shares it.
#include <memory>
#include <mutex>

namespace rf {

struct SceneCacheSlot {
    std::mutex mutex;
    std::shared_ptr<void> state;  ///< the owner's, of its own type; null until first used
};

}  // namespace rf
