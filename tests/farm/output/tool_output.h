#pragma once
// For tests that check outputs with FFmpeg's own tools (ffprobe, ffmpeg) rather than the code
// under test: a folder of their own under the test output, and a command's standard output.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace rf::testing {

/// RAYFARM_TEST_OUT/name, created.
inline std::string testOutDir(const char* name) {
    std::string d = RAYFARM_TEST_OUT;  // appended, not operator+: GCC 12 warns falsely under LTO
    d += "/";
    d += name;
    std::filesystem::create_directories(d);
    return d;
}

/// What the shell command writes to its standard output.
inline std::string runCapture(const std::string& cmd) {
    std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
    std::string out;
    char buf[65536];
    size_t n;
    while (p && (n = fread(buf, 1, sizeof buf, p.get())) > 0) out.append(buf, n);
    return out;
}

}  // namespace rf::testing
