#pragma once
/// Progress on stderr: on a terminal one live line (frames done, fps, ETA, what each rank is
/// rendering), rewritten in place; otherwise a plain line every few seconds, for logs.
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace rf::farm {

class Progress {
public:
    /// total: frames in the output (kept frames count as done from the start). label: put before
    /// each line (a job of several films: "film 2 of 3, NAME"), "" for none.
    Progress(int total, bool live, std::FILE* out = stderr, std::string label = "");
    /// Rate-limited: prints only if enough time has passed. rankFrames[r]: the frame rank r is
    /// rendering (-1: idle), for ranks that render.
    void update(int done, const std::vector<int>& rankFrames);
    /// Ends the live line.
    void finish();
    /// One-line text for the current state (also used by update).
    static std::string line(int done, int total, double seconds, int doneAtStart, const std::vector<int>& rankFrames);

private:
    int total_;
    bool live_;
    std::string label_;
    std::FILE* out_;
    int doneAtStart_ = -1;
    bool printed_ = false;
    std::chrono::steady_clock::time_point start_, last_;
};

/// Whether stderr is a terminal.
bool stderrIsTerminal();

}  // namespace rf::farm
