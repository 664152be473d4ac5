#include "farm/output/output_paths.h"

#include <filesystem>
#include <system_error>

#include <sys/stat.h>

#include "farm/process/usage_error.h"

namespace rf {

bool samePath(const std::string& a, const std::string& b) {
    struct stat sa {}, sb {};
    const bool ea = ::stat(a.c_str(), &sa) == 0, eb = ::stat(b.c_str(), &sb) == 0;
    if (ea && eb) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    if (ea != eb) return false;  // one exists, the other does not: two names
    std::error_code ec1, ec2;
    const auto ca = std::filesystem::weakly_canonical(std::filesystem::absolute(a), ec1);
    const auto cb = std::filesystem::weakly_canonical(std::filesystem::absolute(b), ec2);
    if (ec1 || ec2) return std::filesystem::absolute(a).lexically_normal() == std::filesystem::absolute(b).lexically_normal();
    return ca == cb;
}

void checkOutputPaths(const std::vector<NamedOutput>& outputs, const std::vector<std::string>& inputs) {
    for (size_t i = 0; i < outputs.size(); ++i) {
        const NamedOutput& o = outputs[i];
        if (o.path.empty()) continue;
        for (const std::string& in : inputs)
            if (samePath(o.path, in))
                throw UsageError(o.path + ": " + o.option + " names a file this run reads (" + in +
                                 "); writing it would destroy the input: choose another name");
        for (size_t j = 0; j < i; ++j)
            if (!outputs[j].path.empty() && samePath(o.path, outputs[j].path))
                throw UsageError(o.path + ": " + o.option + " names the same file as " + outputs[j].option +
                                 " (" + outputs[j].path + "): choose another name");
    }
}

}  // namespace rf
