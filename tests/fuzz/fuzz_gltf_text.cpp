// libFuzzer harness: a .gltf text file whose buffers and images come from data URIs (external
// URIs find nothing in the bundle, as a worker's would).
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    rf::FileBundle b;
    b.files["model.gltf"] = rffuzz::bytes(data, size);
    rffuzz::loadAndAnimate(std::move(b), "model.gltf");
    return 0;
}
