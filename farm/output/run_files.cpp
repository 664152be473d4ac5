#include "farm/output/run_files.h"

#include <filesystem>

#include "farm/output/mp4_remux.h"
#include "farm/output/output_lock.h"
#include "farm/output/png_sink.h"
#include "farm/process/usage_error.h"

namespace rf::farm {

namespace {

/// What a file of the frames folder named `name` is to the run, "" if nothing.
std::string framesFolderFile(std::string name) {
    if (name == "rayfarm-frames.json") return "the frames folder's manifest";
    if (name == "rayfarm-frames.sha256") return "the frames folder's checksum list";
    if (name == "rayfarm.log") return "the frames folder's log";
    const bool part = name.size() > 5 && name.compare(name.size() - 5, 5, ".part") == 0;
    if (part) name.resize(name.size() - 5);
    if (frameOfFileName(name, "png") >= 0 || frameOfFileName(name, "exr") >= 0)
        return part ? "a frame's temporary file in the frames folder" : "a frame kept in the frames folder";
    return "";
}

}  // namespace

std::string runFileAt(const std::string& path, const std::string& video, const std::string& framesDir) {
    if (!video.empty()) {
        if (samePath(path, lockPathFor(video))) return "the lock this run holds on -o (" + video + ")";
        if (samePath(path, remuxTempPath(video))) return "the temporary file the video (" + video + ") is remuxed through";
        if (samePath(path, video + ".part")) return "the temporary file the video (" + video + ") is written through";
    }
    if (!framesDir.empty()) {
        if (samePath(path, lockPathFor(framesDir))) return "the lock this run holds on its frames folder (" + framesDir + ")";
        std::filesystem::path parent = std::filesystem::path(path).parent_path();
        if (parent.empty()) parent = ".";
        if (samePath(parent.string(), framesDir)) {
            const std::string what = framesFolderFile(std::filesystem::path(path).filename().string());
            if (!what.empty()) return what + " (" + framesDir + ")";
        }
    }
    return "";
}

void checkOutputsAgainstRunFiles(const std::vector<NamedOutput>& outputs, const std::string& video, const std::string& framesDir) {
    for (const NamedOutput& o : outputs) {
        if (o.path.empty()) continue;
        const std::string what = runFileAt(o.path, video, framesDir);
        if (!what.empty()) throw UsageError(o.path + ": " + o.option + " names " + what + "; choose another name");
    }
}

}  // namespace rf::farm
