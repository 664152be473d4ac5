// libFuzzer harness: the scene bundle a worker receives (FileBundle::deserialize), then the
// scene loaded from it. The bundle's first file is the scene; its type follows its name.
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    rf::FileBundle b;
    try {
        b = rf::FileBundle::deserialize(rffuzz::bytes(data, size));
    } catch (const std::runtime_error&) {
        return 0;
    }
    if (b.files.empty()) return 0;
    const std::string first = b.files.begin()->first;
    rffuzz::loadAndAnimate(std::move(b), first);
    return 0;
}
