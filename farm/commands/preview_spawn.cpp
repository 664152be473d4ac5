#include "farm/commands/preview_spawn.h"

#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

extern char** environ;

namespace rf::farm {

std::string spawnView(const std::vector<std::string>& args, int passFd) {
    const char* x = std::getenv("DISPLAY");
    const char* w = std::getenv("WAYLAND_DISPLAY");
    if (!(x && *x) && !(w && *w)) return "no display (DISPLAY is not set)";
    char self[4096];
    const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0) return "cannot find this executable";
    self[n] = '\0';
    // The window is not a member of an MPI job: leave the launcher's variables out.
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e)
        if (std::strncmp(*e, "OMPI_", 5) != 0 && std::strncmp(*e, "PMIX_", 5) != 0 && std::strncmp(*e, "OPAL_", 5) != 0)
            env.emplace_back(*e);
    std::vector<char*> envp;
    for (std::string& s : env) envp.push_back(s.data());
    envp.push_back(nullptr);
    std::vector<std::string> words{self, "view"};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& s : words) argv.push_back(s.data());
    argv.push_back(nullptr);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    // Its own session: Ctrl-C on the terminal, or mpirun signalling the job's process groups,
    // does not close the window.
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSID);
    // Nor does it hold our output pipes open (mpirun forwards those until they close).
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    for (int fd : {0, 1, 2}) posix_spawn_file_actions_addopen(&files, fd, "/dev/null", fd == 0 ? O_RDONLY : O_WRONLY, 0);
    if (passFd >= 0) posix_spawn_file_actions_adddup2(&files, passFd, 3);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, self, &files, &attr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&files);
    posix_spawnattr_destroy(&attr);
    return rc == 0 ? "" : std::strerror(rc);
}

void startPreview(const std::string& framesDir, int total) {
    const char* x = std::getenv("DISPLAY");
    const char* w = std::getenv("WAYLAND_DISPLAY");
    if (!(x && *x) && !(w && *w)) {
        std::fprintf(stderr, "rayfarm: note: --preview: no display (DISPLAY is not set); rendering without a window\n");
        return;
    }
    const std::string why = spawnView({"--watch", framesDir, "--total", std::to_string(total)});
    if (!why.empty()) std::fprintf(stderr, "rayfarm: note: --preview: cannot start the window (%s); rendering without a window\n", why.c_str());
}

}  // namespace rf::farm
