// libFuzzer harness: one model format read through assimp (engine/load/assimp/), chosen at build
// time by RF_FUZZ_EXT (".obj", ".stl", ".ply", ".fbx", ".dae", ".3mf": fuzz_obj, fuzz_stl, ...),
// loaded as a whole scene as rank 0 and the workers load it. assimp itself is Debian's build,
// not instrumented: libFuzzer sees the coverage of rayfarm's conversion only. assimp reads in a
// child process (engine/load/assimp/assimp_isolated.h), so a crash, a hang or a runaway
// allocation inside it is a refused file here, as for a user; what is fuzzed is that rayfarm
// survives them and the conversion of whatever assimp makes.
#include <cstdlib>

#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // The child's time limit well inside libFuzzer's own -timeout (25 s in tests/fuzz/run.sh).
    ::setenv("RAYFARM_TEST_ASSIMP_SECONDS", "5", 0);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    rf::FileBundle b;
    b.files[std::string("model") + RF_FUZZ_EXT] = rffuzz::bytes(data, size);
    rffuzz::loadAndAnimate(std::move(b), std::string("model") + RF_FUZZ_EXT);
    return 0;
}
