#pragma once
/// The rule for samples per pixel, kept once for the scene loader and every command: the
/// stratified sampler lays an n×n grid in each pixel, so the count must be a square.
#include <string>

namespace rf {

/// Whether spp is a square number of samples (1, 4, 9, 16, ...).
bool isSquareSpp(int spp);

/// "" when spp is a square; otherwise what is wrong, in the words the loader and the CLI print
/// after naming where the number came from ("render.spp: ", "--spp: ").
std::string sppProblem(int spp);

}  // namespace rf
