// rayfarm view: a live window on a scene (Qt 6). Loads the scene like `still`, then hands it to
// the window, which renders with the engine's renderTile on all local cores.
#include <QApplication>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <unistd.h>

#include "background_option.h"
#include "cli.h"
#include "errors.h"
#include "file_source.h"
#include "gltf_loader.h"
#include "output_check.h"
#include "scene_loader.h"
#include "view_window.h"

namespace rf::cli {

namespace {
const char* kViewHelp =
    "usage: rayfarm view SCENE|MODEL [options]\n"
    "\n"
    "Opens a window on a scene file (.json) or glTF model (.gltf/.glb) and renders it live on all\n"
    "local cores: 1 spp while the camera moves, refined to the scene's spp at rest. The picture\n"
    "at rest is the one `rayfarm still` renders with the same camera and options.\n"
    "\n"
    "  --size WxH        image size (default: the scene's render.width/height)\n"
    "  --spp N           samples per pixel at rest, a square: 1, 4, 9, 16, ...\n"
    "  --depth N         maximum ray depth; the primary ray counts as 1\n"
    "  --min-weight W    do not trace secondary rays weighing less than W (0: never prune)\n"
    "  --tonemap T       clamp or reinhard\n"
    "  --background B    #RRGGBB or R,G,B (linear); transparent shows coverage over black\n"
    "  --threads N       render threads (default: all cores)\n"
    "  --frame N         start at frame N of the scene's timeline (default 0)\n"
    "  --camera N        start from the model's glTF camera N\n"
    "  -o FILE           where Ctrl+S saves the scene with its camera keys (default: NAME_view.json)\n"
    "  --stats FILE      on close, write frames shown, fps while moving and input latency as JSON\n"
    "\n"
    "Mouse: left drag orbits, middle or shift drag pans, the wheel zooms.\n"
    "Keys: F frames the model, R returns to the timeline's camera, Space plays/pauses, Left/Right\n"
    "step a frame, Home/End jump to the first/last frame, T tints tiles\n"
    "by rank, K adds a camera key at the current time, Delete removes the selected key,\n"
    "Ctrl+S saves, Ctrl+Q closes.\n";

const char* kNoDisplay = "rayfarm: error: view: no display to open a window on (DISPLAY is not set); "
                         "use 'rayfarm render' for a video or 'rayfarm still' for a picture\n";

// Qt reports a display it cannot open through qFatal, after a few warning lines: say it in one
// line in rayfarm's words and leave with the usage status instead.
void qtMessages(QtMsgType type, const QMessageLogContext&, const QString& msg) {
    if (type == QtFatalMsg) {
        std::fprintf(stderr, "rayfarm: error: view: cannot open a window (%s); use 'rayfarm render' or 'rayfarm still'\n",
                     msg.section('\n', 0, 0).toLocal8Bit().constData());
        std::fflush(stderr);
        _exit(2);
    }
    if (type == QtCriticalMsg) std::fprintf(stderr, "rayfarm: view: %s\n", msg.toLocal8Bit().constData());
}

bool haveDisplay() {
    const char* platform = std::getenv("QT_QPA_PLATFORM");
    if (platform && *platform && std::string(platform).rfind("xcb", 0) != 0 && std::string(platform).rfind("wayland", 0) != 0)
        return true;  // offscreen, vnc, ...: Qt needs no display server
    const char* x = std::getenv("DISPLAY");
    const char* w = std::getenv("WAYLAND_DISPLAY");
    return (x && *x) || (w && *w);
}
}  // namespace

int runView(const std::vector<std::string>& args) {
    ArgParser p("view");
    for (const char* o : {"-o", "--size", "--spp", "--depth", "--min-weight", "--tonemap", "--threads", "--stats", "--frame", "--camera", "--background"}) p.option(o);
    p.flag("--help");
    p.flag("-h");
    p.parse(args);
    if (p.has("--help") || p.has("-h")) {
        std::fputs(kViewHelp, stdout);
        return 0;
    }
    if (p.positional().size() != 1) throw UsageError("view: expected one SCENE or MODEL (see rayfarm view --help)");
    if (!haveDisplay()) {
        std::fputs(kNoDisplay, stderr);
        return 2;
    }
    view::ViewOptions o;
    o.scenePath = p.positional()[0];
    o.savePath = p.value("-o").value_or(std::filesystem::path(o.scenePath).stem().string() + "_view.json");
    o.threads = p.intValue("--threads", 0, 0, 4096);
    checkWritableFile(o.savePath);
    BackgroundChoice background;
    if (auto b = p.value("--background")) background = parseBackground(*b);
    if (auto st = p.value("--stats")) {
        checkWritableFile(*st);
        o.statsPath = *st;
    }

    DiskFileSource fs;
    Scene scene = loadScene(o.scenePath, fs);
    for (const std::string& note : scene.notes) std::cerr << "rayfarm: note: " << note << "\n";
    applyBackground(background, scene);
    const anim::Timeline timeline = anim::Timeline::fromScene(scene);
    o.startFrame = p.intValue("--frame", 0, 0, std::max(timeline.frameCount(), view::filmOf(timeline).frames) - 1);
    RenderSettings settings = scene.settings;
    applyQualityOptions(p, settings);
    if (p.has("--camera")) {
        o.gltfCamera = p.intValue("--camera", 0, 0, 1 << 20);
        if (size_t(o.gltfCamera) >= scene.gltfCameras.size())
            throw InputError(scene.sourcePath, "no glTF camera " + std::to_string(o.gltfCamera) + " (the scene has " +
                                                   std::to_string(scene.gltfCameras.size()) + ")");
    }

    qInstallMessageHandler(qtMessages);
    int argc = 1;
    char name[] = "rayfarm";
    char* argv[] = {name, nullptr};
    QApplication app(argc, argv);
    view::ViewWindow window(std::move(scene), timeline, settings, o);
    window.show();
    return app.exec();
}

}  // namespace rf::cli
