#pragma once
/// printf into a std::string: the lines render prints (its plan, its outcome, a job's films).
#include <algorithm>
#include <cstdio>
#include <string>

namespace rf::cli {

/// printf into a std::string of whatever length it takes (scene paths have no limit).
template <class... A>
std::string formatted(const char* fmt, A... a) {
    const int n = std::snprintf(nullptr, 0, fmt, a...);
    std::string s(size_t(std::max(n, 0)) + 1, '\0');
    std::snprintf(s.data(), s.size(), fmt, a...);
    s.resize(size_t(std::max(n, 0)));
    return s;
}

}  // namespace rf::cli
