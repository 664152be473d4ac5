// libFuzzer harness: an environment image's bytes (.hdr through stb, .exr through OpenEXR), as
// `--environment FILE` hands them to decodeEnvironment on every rank. A bad file must end in
// an InputError; a crash, a leak, a sanitizer report or a hang is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/lights/environment.h"
#include "engine/util/errors.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    try {
        const rf::EquirectImage env = rf::decodeEnvironment(bytes, "env");
        // What the renderer does next with a decoded image: mip levels and a lookup.
        if (env.width > 0 && env.height > 0) {
            env.halved();
            env.sample(rf::Vec2{0.25f, 0.75f});
        }
    } catch (const rf::InputError&) {
    }
    return 0;
}
