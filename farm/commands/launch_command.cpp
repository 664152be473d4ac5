#include "farm/commands/launch_command.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

#include <unistd.h>

namespace rf::farm {

namespace {

std::vector<std::string> cmdlineOf(pid_t pid) {
    std::ifstream f("/proc/" + std::to_string(pid) + "/cmdline", std::ios::binary);
    std::vector<std::string> args;
    std::string a;
    while (std::getline(f, a, '\0')) args.push_back(a);
    return args;
}

std::string baseName(const std::string& p) { return std::filesystem::path(p).filename().string(); }

/// mpirun's arguments before the executable, if this process is mpirun's child.
std::string fromParent() {
    const std::vector<std::string> parent = cmdlineOf(::getppid());
    if (parent.empty()) return "";
    const std::string launcher = baseName(parent[0]);
    if (launcher != "mpirun" && launcher != "mpiexec" && launcher != "orterun" && launcher != "prterun") return "";
    std::error_code ec;
    const std::string self = baseName(std::filesystem::read_symlink("/proc/self/exe", ec).string());
    std::string out;
    for (size_t i = 0; i < parent.size(); ++i) {
        if (i > 0 && !self.empty() && baseName(parent[i]) == self) return out;
        if (!out.empty()) out += ' ';
        out += shellQuote(parent[i]);
    }
    return "";  // the executable was not found among mpirun's arguments: do not guess
}

}  // namespace

std::string shellQuote(const std::string& s) {
    if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-./:=,+@%") == std::string::npos)
        return s;
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

bool launcherKeepsJobAlive() {
    if (!std::getenv("OMPI_COMM_WORLD_SIZE")) return true;
    const char* v = std::getenv("OMPI_MCA_orte_enable_recovery");
    const std::string on = v ? v : "";
    return on == "1" || on == "true" || on == "yes" || on == "on";
}

std::string keepAliveNote(int ranks) {
    if (ranks < 2 || launcherKeepsJobAlive()) return "";
    return "mpirun was started without --enable-recovery: a worker that dies ends the whole job (the frames done are kept "
           "for --resume); with mpirun --enable-recovery its work goes to the other ranks and the film completes";
}

std::string launcherPrefix(int ranks) {
    if (ranks <= 1 && !std::getenv("OMPI_COMM_WORLD_SIZE")) return "";
    // Read once, while mpirun runs: after a second Ctrl-C the parent is gone when this is asked.
    static const std::string parent = fromParent();
    if (!parent.empty()) return parent;
    // Rank 0 started by a remote daemon: rebuild what Open MPI exported from mpirun's options.
    std::string out = "mpirun -np " + std::to_string(ranks);
    const char* over = std::getenv("OMPI_MCA_rmaps_base_oversubscribe");
    if (over && std::string(over) == "1") out += " --oversubscribe";
    for (const char* key : {"btl", "btl_tcp_if_include", "oob_tcp_if_include", "plm_rsh_agent", "pml"})
        if (const char* v = std::getenv(("OMPI_MCA_" + std::string(key)).c_str())) out += std::string(" --mca ") + key + " " + shellQuote(v);
    return out;
}

}  // namespace rf::farm
