#include "engine/util/sample_count.h"

#include <cmath>

namespace rf {

bool isSquareSpp(int spp) {
    if (spp < 1) return false;
    const int n = static_cast<int>(std::lround(std::sqrt(double(spp))));
    return n * n == spp;
}

std::string sppProblem(int spp) {
    return isSquareSpp(spp) ? std::string() : std::string("expected a square number of samples (1, 4, 9, 16, ...)");
}

}  // namespace rf
