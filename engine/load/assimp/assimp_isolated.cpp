#include "engine/load/assimp/assimp_isolated.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <stdexcept>

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include "engine/util/errors.h"
#include "engine/util/load_control.h"

// Sanitizer runtimes (ASan, UBSan, libFuzzer's) call their death callback on a report; in the
// child that callback belongs to the parent (libFuzzer would write the parent's input as a
// crash of its own). Weak: absent from a plain build.
extern "C" __attribute__((weak)) void __sanitizer_set_death_callback(void (*)(void));

namespace rf {

namespace {

/// The scene's metadata (FBX's axes and unit) rides on a wrapper root node: assimp's binary dump
/// keeps nodes' metadata but not the scene's.
constexpr const char* kMetadataNode = "$rayfarm-scene-metadata$";
constexpr char kMagic[4] = {'R', 'F', 'A', 'I'};

void putU64(std::string& out, uint64_t v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }
void putString(std::string& out, const std::string& s) {
    putU64(out, s.size());
    out += s;
}

/// Reads the child's message; throws std::runtime_error where it is short or malformed.
class Reader {
public:
    explicit Reader(const std::string& bytes) : bytes_(bytes) {}
    uint64_t u64() {
        need(8);
        uint64_t v;
        std::memcpy(&v, bytes_.data() + pos_, 8);
        pos_ += 8;
        return v;
    }
    std::string string() {
        const uint64_t n = u64();
        need(n);
        std::string s = bytes_.substr(pos_, n);
        pos_ += n;
        return s;
    }
    const char* take(uint64_t n) {
        need(n);
        const char* p = bytes_.data() + pos_;
        pos_ += n;
        return p;
    }
    bool atEnd() const { return pos_ == bytes_.size(); }

private:
    void need(uint64_t n) const {
        if (n > bytes_.size() - pos_) throw std::runtime_error("truncated");
    }
    const std::string& bytes_;
    size_t pos_ = 0;
};

bool writeAll(int fd, const char* p, size_t n) {
    while (n > 0) {
        const ssize_t w = ::write(fd, p, std::min<size_t>(n, 1 << 20));
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= size_t(w);
    }
    return true;
}

/// The process's data now (bytes): its private writable mappings, /proc's VmData, which is what
/// RLIMIT_DATA bounds (Linux 4.7 on). Under AddressSanitizer that includes the shadow it reserved
/// at start, so the same limit works there.
uint64_t currentData() {
    std::ifstream status("/proc/self/status");
    std::string key;
    uint64_t kib = 0;
    while (status >> key) {
        if (key == "VmData:") {
            status >> kib;
            return kib << 10;
        }
        status.ignore(1 << 12, '\n');
    }
    return 0;
}

/// The child: reads, dumps the scene and writes the message; never returns.
[[noreturn]] void runChild(int fd, pid_t parent, uint64_t memoryBytes, const std::function<const aiScene*(ChildImportReport&)>& read) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(3);
    if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
    // A crash ends the child plainly (the parent names the signal), not through handlers the
    // parent installed: the farm's interrupt handlers, a fuzzer's crash handlers.
    // Quiet: a crash's message (glibc's "double free detected", a sanitizer's report) would be a
    // second line beside rayfarm's one. glibc writes those to the controlling terminal, which
    // a session of its own does not have; stdout and stderr go nowhere.
    ::setsid();
    if (const int null = ::open("/dev/null", O_RDWR | O_CLOEXEC); null >= 0) {
        ::dup2(null, STDOUT_FILENO);
        ::dup2(null, STDERR_FILENO);
    }
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGSEGV, SIGBUS, SIGABRT, SIGILL, SIGFPE, SIGPIPE}) std::signal(sig, SIG_DFL);
    if (const uint64_t now = currentData(); now > 0) {
        const rlimit limit{now + memoryBytes, RLIM_INFINITY};
        ::setrlimit(RLIMIT_DATA, &limit);
    }
    std::string msg(kMagic, sizeof kMagic);
    std::string failure;
    ChildImportReport report;
    const aiExportDataBlob* blob = nullptr;
    Assimp::Exporter exporter;
    try {
        const aiScene* constScene = read(report);
        if (constScene) {
            auto* scene = const_cast<aiScene*>(constScene);  // the child's own importer's; it ends here
            if (scene->mRootNode) {
                auto* wrapper = new aiNode(kMetadataNode);
                wrapper->mMetaData = scene->mMetaData;
                scene->mMetaData = nullptr;
                wrapper->mNumChildren = 1;
                wrapper->mChildren = new aiNode*[1]{scene->mRootNode};
                scene->mRootNode->mParent = wrapper;
                scene->mRootNode = wrapper;
            }
            blob = exporter.ExportToBlob(scene, "assbin");
            if (!blob) failure = std::string("assimp could not pass the scene on: ") + exporter.GetErrorString();
        }
    } catch (const std::bad_alloc&) {
        failure = "out of memory";
    } catch (const std::exception& e) {
        failure = e.what();
    } catch (...) {
        failure = "an unknown exception";
    }
    msg += char(blob ? 1 : 0);
    for (const std::string* s : {&report.importerError, &report.violation, &report.violationReason, &report.ioError, &failure})
        putString(msg, *s);
    putU64(msg, report.filesRead.size());
    for (const auto& [file, limit] : report.filesRead) {
        putString(msg, file);
        putU64(msg, limit);
    }
    putU64(msg, blob ? blob->size : 0);
    bool ok = writeAll(fd, msg.data(), msg.size());
    if (ok && blob) ok = writeAll(fd, static_cast<const char*>(blob->data), blob->size);
    ::close(fd);
    ::_exit(ok ? 0 : 4);  // no atexit handlers, no stdio flush: the parent's, not the child's
}

std::string signalName(int sig) {
    const char* d = ::strsignal(sig);
    return "signal " + std::to_string(sig) + (d ? std::string(", ") + d : std::string());
}

/// Kills and reaps the child (it may be gone already).
void endChild(pid_t pid) {
    ::kill(pid, SIGKILL);
    while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
    }
}

/// Takes the wrapper root off again, putting its metadata back on the scene.
void unwrapMetadata(aiScene& scene) {
    aiNode* wrapper = scene.mRootNode;
    if (!wrapper || wrapper->mName != aiString(std::string(kMetadataNode)) || wrapper->mNumChildren != 1) return;
    aiNode* root = wrapper->mChildren[0];
    wrapper->mChildren[0] = nullptr;
    wrapper->mNumChildren = 0;
    root->mParent = nullptr;
    delete scene.mMetaData;
    scene.mMetaData = wrapper->mMetaData;
    wrapper->mMetaData = nullptr;
    delete wrapper;
    scene.mRootNode = root;
}

}  // namespace

const aiScene* importInChild(Assimp::Importer& into, const std::string& path, uint64_t inputBytes,
                             const std::function<const aiScene*(ChildImportReport&)>& read, ChildImportReport& report,
                             ChildImportLimits limits) {
    double seconds = limits.seconds > 0 ? limits.seconds : ChildImportLimits::kTimeBase + ChildImportLimits::kTimePerByte * double(inputBytes);
    // Tests and the fuzz harnesses shorten it (a fuzzer's own timeout is 25 s).
    if (const char* t = std::getenv("RAYFARM_TEST_ASSIMP_SECONDS"); t && limits.seconds <= 0 && std::atof(t) > 0) seconds = std::atof(t);
    const uint64_t memory = limits.memoryBytes > 0 ? limits.memoryBytes
                                                   : ChildImportLimits::kMemoryBase + ChildImportLimits::kMemoryPerByte * inputBytes;
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) throw InputError(path, std::string("cannot start the importer's process: ") + std::strerror(errno));
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int e = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        throw InputError(path, std::string("cannot start the importer's process: ") + std::strerror(e));
    }
    if (pid == 0) {
        ::close(fds[0]);
        runChild(fds[1], parent, memory, read);
    }
    ::close(fds[1]);

    // The message, read as it comes (a pipe holds 64 KiB), while watching the clock and cancels.
    std::string msg;
    const uint64_t maxMessage = memory + (64ull << 20);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    std::string stopped;  // why the parent stopped reading before the end
    std::vector<char> chunk(1 << 20);
    for (;;) {
        if (loadCancelSignal() != 0) {
            ::close(fds[0]);
            endChild(pid);
            pollLoadCancel();
        }
        if (std::chrono::steady_clock::now() > deadline) {
            char buf[64];
            std::snprintf(buf, sizeof buf, "%.0f", seconds);
            stopped = std::string("assimp took longer than ") + buf + " s on it, the limit for a file of its size";
            break;
        }
        pollfd p{fds[0], POLLIN, 0};
        const int r = ::poll(&p, 1, 50);
        if (r < 0 && errno != EINTR) {
            stopped = std::string("lost the importer's process: ") + std::strerror(errno);
            break;
        }
        if (r <= 0) continue;
        const ssize_t n = ::read(fds[0], chunk.data(), chunk.size());
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (n <= 0) break;  // the end (or the child's death)
        if (msg.size() + size_t(n) > maxMessage) {
            stopped = "assimp made more of it than a file of its size may take";
            break;
        }
        msg.append(chunk.data(), size_t(n));
    }
    ::close(fds[0]);
    int status = 0;
    if (!stopped.empty()) {
        endChild(pid);
        throw InputError(path, stopped + "; refused");
    }
    // The pipe closed: the child has ended or is about to.
    for (;;) {
        const pid_t w = ::waitpid(pid, &status, 0);
        if (w == pid) break;
        if (errno != EINTR) {
            status = 0;
            break;
        }
    }
    if (loadCancelSignal() != 0) pollLoadCancel();  // a Ctrl-C that reached the child as well
    if (WIFSIGNALED(status))
        throw InputError(path, "assimp crashed reading it (" + signalName(WTERMSIG(status)) + "); the file is refused");
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw InputError(path, "assimp's process ended before it finished (exit status " + std::to_string(WEXITSTATUS(status)) + ")");

    try {
        Reader in(msg);
        if (std::memcmp(in.take(sizeof kMagic), kMagic, sizeof kMagic) != 0) throw std::runtime_error("no header");
        const bool hasScene = *in.take(1) == 1;
        std::string failure;
        for (std::string* s : {&report.importerError, &report.violation, &report.violationReason, &report.ioError, &failure})
            *s = in.string();
        const uint64_t files = in.u64();
        for (uint64_t i = 0; i < files; ++i) {
            std::string file = in.string();
            report.filesRead.emplace_back(std::move(file), in.u64());
        }
        const uint64_t blobSize = in.u64();
        const char* blob = in.take(blobSize);
        if (!in.atEnd()) throw std::runtime_error("trailing bytes");
        if (!failure.empty()) throw InputError(path, "assimp failed on it: " + failure);
        if (!hasScene) return nullptr;
        const aiScene* scene = into.ReadFileFromMemory(blob, size_t(blobSize), 0, "assbin");
        if (!scene) throw InputError(path, std::string("could not read back the scene assimp made: ") + into.GetErrorString());
        unwrapMetadata(*const_cast<aiScene*>(scene));
        return scene;
    } catch (const std::runtime_error& e) {
        if (dynamic_cast<const InputError*>(&e)) throw;
        throw InputError(path, std::string("the importer's process sent a malformed answer (") + e.what() + ")");
    }
}

}  // namespace rf
