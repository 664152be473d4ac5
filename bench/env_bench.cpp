// Environment filtering time by shape (issue 30 #4): an EnvironmentLight made from images of one
// pixel count in several proportions, built straight from texels (no file, so strips that a
// file header is refused for are timed too). Prints wall and CPU seconds per shape.
//   env_bench [--pixels N] [--threads N]      (default: 8192 x 4096 pixels, 2 threads)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "engine/scene/env_lighting.h"

#include "bench/bench_util.h"

using namespace rf;

int main(int argc, char** argv) {
    long long pixels = 8192LL * 4096LL;
    int threads = 2;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--pixels") pixels = std::atoll(argv[i + 1]);
        else if (a == "--threads") threads = std::atoi(argv[i + 1]);
    }
    // Width to height: 2:1 (an equirect), 1:1, 8:1 and 1:8 (the extremes a file may have), and
    // the strips of the issue (8 texels wide or high).
    const long long side2to1 = std::llround(std::sqrt(pixels / 2.0));
    const long long side1to1 = std::llround(std::sqrt(double(pixels)));
    const long long side8to1 = std::llround(std::sqrt(pixels / 8.0));
    const std::vector<std::pair<long long, long long>> shapes = {{2 * side2to1, side2to1}, {side1to1, side1to1},
                                                                 {8 * side8to1, side8to1}, {side8to1, 8 * side8to1},
                                                                 {8, pixels / 8}, {pixels / 8, 8}};
    std::printf("%-16s %12s %8s %8s\n", "shape", "pixels", "wall s", "cpu s");
    for (const auto& [w, h] : shapes) {
        EquirectImage img;
        img.width = int(w);
        img.height = int(h);
        img.texels.resize(size_t(w) * size_t(h));
        for (size_t i = 0; i < img.texels.size(); ++i) img.texels[i] = Color(0.2f + 0.6f * float((i * 2654435761u) % 1000) / 1000.f);
        const double c0 = bench::processCpuSeconds();
        const auto t0 = std::chrono::steady_clock::now();
        const EnvironmentLight env(std::move(img), 0.f, 1.f, threads);
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double cpu = bench::processCpuSeconds() - c0;
        const std::string shape = std::to_string(w) + "x" + std::to_string(h);
        std::printf("%-16s %12lld %8.2f %8.2f   (diffuse up %.3f)\n", shape.c_str(), w * h, wall, cpu, env.diffuse(Vec3(0, 1, 0)).r);
    }
    return 0;
}
