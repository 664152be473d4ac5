#include "engine/load/gltf/gltf_parse.h"

#include <filesystem>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_compression.h"
#include "engine/load/gltf/gltf_safety.h"
#include "engine/util/load_control.h"

namespace rf::gltf {

namespace {
std::string firstLine(const std::string& s) {
    size_t b = s.find_first_not_of(" \n\r\t");
    if (b == std::string::npos) return "tinygltf could not parse the file";
    const size_t e = s.find('\n', b);
    return s.substr(b, e == std::string::npos ? std::string::npos : e - b);
}
}  // namespace

tinygltf::Model parseGltf(const std::string& path, FileSource& fs, const AssetOptions& assets, std::vector<std::string>& notes) {
    LoadStep parsing("parsing the glTF");
    const std::string bytes = fs.read(path, Limits::kMaxFileBytes);
    const PreflightResult pf = preflight(path, bytes);
    std::string folder = std::filesystem::path(path).parent_path().string();
    ConfinedFs cfs(fs, folder.empty() ? "." : folder, assetRootFor(path, assets.root));
    const std::string patched = pf.patchedJson.empty() ? std::string() : pf.patchedFile(bytes);
    const std::string& input = pf.patchedJson.empty() ? bytes : patched;
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(cfs.callbacks());
    loader.SetImageLoader(&keepEncodedImage, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    bool ok = false;
    try {
        ok = pf.binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(input.data()),
                                                     static_cast<unsigned>(input.size()), cfs.folder())
                       : loader.LoadASCIIFromString(&model, &err, &warn, input.data(), static_cast<unsigned>(input.size()),
                                                    cfs.folder());
    } catch (const std::exception& e) {
        throw InputError(path, std::string("glTF parse error: ") + e.what());
    }
    if (!cfs.violation().empty())
        throw InputError(path, "URI \"" + cfs.violation() + "\": " + cfs.violationReason() + "; refused");
    if (!ok) {
        // tinygltf says "File not found : NAME"; say which kind of file is missing, and where.
        std::string msg = firstLine(err);
        const std::string nf = "File not found : ", re = "File read error : ";
        if (msg.rfind(nf, 0) == 0) msg = "cannot find \"" + msg.substr(nf.size()) + "\" in the model's folder";
        // "File read error : FILE : FILE: not a regular file but a FIFO": the file and what is
        // wrong with it, as FileSource::read said, with the model that names it.
        if (msg.rfind(re, 0) == 0) {
            const std::string rest = msg.substr(re.size());
            const size_t sep = rest.find(" : ");
            if (sep != std::string::npos) {
                const std::string file = rest.substr(0, sep);
                std::string why = rest.substr(sep + 3);
                if (why.rfind(file + ": ", 0) == 0) why = why.substr(file.size() + 2);
                throw InputError(file, why + " (named by " + path + ")");
            }
        }
        throw InputError(path, msg);
    }
    if (!warn.empty()) notes.push_back(firstLine(warn));
    for (const std::string& n : pf.notes) notes.push_back(n);
    pollLoadCancel();
    decodeCompressedGeometry(model, path, &notes);  // Draco and meshopt, before any accessor is read
    return model;
}

}  // namespace rf::gltf
