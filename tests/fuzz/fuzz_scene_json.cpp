// libFuzzer harness: a scene file (.json) with its timeline, as `rayfarm render` reads it.
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    rf::FileBundle b;
    b.files["scene.json"] = rffuzz::bytes(data, size);
    rffuzz::loadAndAnimate(std::move(b), "scene.json");
    return 0;
}
