// libFuzzer harness: a binary glTF (.glb): header, JSON chunk and BIN chunk.
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    rf::FileBundle b;
    b.files["model.glb"] = rffuzz::bytes(data, size);
    rffuzz::loadAndAnimate(std::move(b), "model.glb");
    return 0;
}
