// libFuzzer harness: one model format read through assimp (engine/load/assimp/), chosen at build
// time by RF_FUZZ_EXT (".obj", ".stl", ".ply", ".fbx", ".dae", ".3mf": fuzz_obj, fuzz_stl, ...),
// loaded as a whole scene as rank 0 and the workers load it. assimp itself is Debian's build,
// not instrumented: libFuzzer sees the coverage of rayfarm's conversion only, and a memory error
// inside assimp shows only where it crashes.
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    rf::FileBundle b;
    b.files[std::string("model") + RF_FUZZ_EXT] = rffuzz::bytes(data, size);
    rffuzz::loadAndAnimate(std::move(b), std::string("model") + RF_FUZZ_EXT);
    return 0;
}
