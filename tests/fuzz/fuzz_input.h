#pragma once
// Shared by the libFuzzer harnesses: load one in-memory file as a scene the way rank 0 and the
// workers do (through a FileSource), then evaluate the timeline. Bad input must end in an
// InputError or std::runtime_error; anything else (a crash, a leak, a sanitizer report, a
// hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

namespace rffuzz {

/// Loads `bundle`'s file `path` as a scene, evaluates its first and last frame and builds the
/// acceleration structure. Expected errors are swallowed.
inline void loadAndAnimate(rf::FileBundle bundle, const std::string& path) {
    try {
        rf::BundleFileSource fs(std::move(bundle));
        rf::LoadedScene loaded = rf::loadScene(path, fs);
        rf::Scene& scene = loaded.scene;
        const rf::anim::Timeline tl = rf::anim::Timeline::fromScene(loaded);
        tl.applyFrame(scene, 0);
        tl.applyFrame(scene, tl.frameCount() - 1);
    } catch (const rf::InputError&) {
    } catch (const std::runtime_error&) {  // e.g. a bundle too large for a file cap
    }
}

inline std::string bytes(const uint8_t* data, size_t size) { return std::string(reinterpret_cast<const char*>(data), size); }

}  // namespace rffuzz
