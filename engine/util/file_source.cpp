#include "engine/util/file_source.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <sys/stat.h>

#include "engine/util/errors.h"

namespace rf {

namespace {
void putU64(std::string& out, uint64_t v) {
    char b[8];
    std::memcpy(b, &v, 8);
    out.append(b, 8);
}
uint64_t getU64(const std::string& in, size_t& pos) {
    if (pos + 8 > in.size()) throw std::runtime_error("file bundle: truncated");
    uint64_t v;
    std::memcpy(&v, in.data() + pos, 8);
    pos += 8;
    return v;
}
std::string getBytes(const std::string& in, size_t& pos, uint64_t n) {
    if (n > in.size() - pos) throw std::runtime_error("file bundle: truncated");
    std::string s = in.substr(pos, n);
    pos += n;
    return s;
}
/// What a file that is not a regular one is, for a message.
std::string kindOf(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISLNK(mode)) return "a symbolic link";
    return "a device";
}
}  // namespace

std::string notRegularFile(const std::string& path, bool followLinks) {
    struct stat st {};
    const int rc = followLinks ? ::stat(path.c_str(), &st) : ::lstat(path.c_str(), &st);
    if (rc != 0 || S_ISREG(st.st_mode)) return "";
    return kindOf(st.st_mode);
}

std::string FileBundle::serialize() const {
    std::string out;
    putU64(out, files.size());
    for (const auto& [path, bytes] : files) {
        putU64(out, path.size());
        out += path;
        putU64(out, bytes.size());
        out += bytes;
    }
    return out;
}

FileBundle FileBundle::deserialize(const std::string& in) {
    FileBundle b;
    size_t pos = 0;
    const uint64_t n = getU64(in, pos);
    for (uint64_t i = 0; i < n; ++i) {
        std::string path = getBytes(in, pos, getU64(in, pos));
        b.files[path] = getBytes(in, pos, getU64(in, pos));
    }
    return b;
}

std::optional<std::string> FileSource::realPath(const std::string& path) {
    std::error_code ec;
    const std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec), ec);
    if (ec) return std::nullopt;
    return p.string();
}

size_t FileBundle::totalBytes() const {
    size_t n = 0;
    for (const auto& [p, bytes] : files) n += p.size() + bytes.size();
    return n;
}

std::string DiskFileSource::read(const std::string& path, uint64_t maxBytes) {
    if (auto it = bundle_.files.find(path); it != bundle_.files.end()) return it->second;
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw InputError(path, "not a regular file but " + kindOf(st.st_mode));
    if (static_cast<uint64_t>(st.st_size) > maxBytes)
        throw InputError(path, "file is " + std::to_string(st.st_size) + " bytes, over the limit of " + std::to_string(maxBytes));
    std::ifstream f(path, std::ios::binary);
    if (!f) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
    std::string data(static_cast<size_t>(st.st_size), '\0');
    f.read(data.data(), st.st_size);
    if (f.gcount() != st.st_size) throw InputError(path, "read error");
    bundle_.files[path] = data;
    return data;
}

bool DiskFileSource::exists(const std::string& path) {
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0;
}

std::string BundleFileSource::read(const std::string& path, uint64_t maxBytes) {
    auto it = bundle_.files.find(path);
    if (it == bundle_.files.end()) throw InputError(path, "not in the scene bundle rank 0 sent");
    if (it->second.size() > maxBytes) throw InputError(path, "over the size limit");
    return it->second;
}

bool BundleFileSource::exists(const std::string& path) { return bundle_.files.count(path) > 0; }

}  // namespace rf
