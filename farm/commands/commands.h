#pragma once
/// The entry points of render, still and info (farm/commands/): the commands that render over
/// the cluster, or read a model, on top of the command line's parsing (farm/cli/).
#include <string>
#include <vector>

namespace rf::cli {

int runStill(const std::vector<std::string>& args);
int runRender(const std::vector<std::string>& args);
/// rayfarm info MODEL [--json]: what the file holds and its default turntable.
int runInfo(const std::vector<std::string>& args);

}  // namespace rf::cli
