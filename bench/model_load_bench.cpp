// Model loading alone, in one process: for each file, the time to read it into the glTF model
// (tinygltf's parse for .gltf/.glb; assimp's import and the conversion for OBJ, STL, PLY, ...)
// and the whole load as `rayfarm still` does it (loadScene: that, the engine's meshes and
// materials, the BVH and the environment). Best of --repeat N (default 3) each.
//   build/bin/model_load_bench MODEL... [--repeat N]
// bench/bench_model_formats.sh makes a 10⁶-triangle mesh in three formats and runs it.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "engine/util/model_path.h"
#include "engine/load/assimp/assimp_import.h"
#include "engine/load/gltf/gltf_parse.h"
#include "engine/load/scene_loader.h"

using namespace rf;

namespace {
double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
}  // namespace

int main(int argc, char** argv) {
    int repeat = 3;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--repeat" && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
        else files.push_back(a);
    }
    if (files.empty()) {
        std::fprintf(stderr, "usage: model_load_bench MODEL... [--repeat N]\n");
        return 2;
    }
    std::printf("%-40s %14s %14s\n", "model", "to glTF s", "whole load s");
    for (const std::string& f : files) {
        double parse = 1e30, whole = 1e30;
        try {
            for (int r = 0; r < repeat; ++r) {
                {
                    DiskFileSource fs;
                    std::vector<std::string> notes;
                    const double t0 = now();
                    const tinygltf::Model m = isAssimpPath(f) ? importAssimpModel(f, fs, {}, notes) : gltf::parseGltf(f, fs, {}, notes);
                    parse = std::min(parse, now() - t0);
                }
                DiskFileSource fs;
                const double t0 = now();
                const LoadedScene s = loadScene(f, fs);
                whole = std::min(whole, now() - t0);
            }
        } catch (const InputError& e) {
            std::fprintf(stderr, "model_load_bench: %s\n", e.what());
            return 2;
        }
        std::printf("%-40s %14.3f %14.3f\n", f.c_str(), parse, whole);
    }
    return 0;
}
