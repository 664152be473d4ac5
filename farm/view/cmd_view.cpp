// rayfarm view: a live window on a scene (Qt 6). Loads the scene like `still`, then hands it to
// the window, which renders with the engine's renderTile on all local cores.
#include <QApplication>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <thread>
#include <utility>
#include <unistd.h>

#include "farm/cli/background_option.h"
#include "farm/cli/cli.h"
#include "farm/view/cmd_view.h"
#include "farm/view/display_loss.h"
#include "farm/cli/exposure_meter.h"
#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "engine/load/gltf/gltf_loader.h"
#include "farm/process/interrupt.h"
#include "farm/output/output_check.h"
#include "farm/output/output_paths.h"
#include "engine/load/scene_loader.h"
#include "engine/integrators/render.h"
#include "farm/cluster/master_watch.h"
#include "farm/cluster/scene_broadcast.h"
#include "farm/cluster/transport.h"
#include "farm/view/view_messages.h"
#include "farm/view/preview_window.h"
#include "farm/view/view_window.h"
#include "farm/view/view_worker.h"
#include "farm/cluster/worker.h"

namespace rf::cli {

namespace {
const char* kViewHelp =
    "usage: rayfarm view SCENE|MODEL [options]\n"
    "\n"
    "Opens a window on a scene file (.json) or model (glTF, OBJ, STL, PLY, FBX, .dae, 3MF) and\n"
    "renders it live on all\n"
    "local cores (under mpirun, on every rank: the same farm as render): 1 spp while the camera\n"
    "moves, refined to the scene's spp at rest. The picture at rest is the one `rayfarm still`\n"
    "renders with the same camera and options.\n"
    "\n"
    "  --size WxH        image size (default: the scene's render.width/height)\n"
    "  --spp N           samples per pixel at rest, a square: 1, 4, 9, 16, ...\n"
    "  --depth N         maximum ray depth; the primary ray counts as 1\n"
    "  --min-weight W    do not trace secondary rays weighing less than W (0: never prune)\n"
    "  --indirect N      glTF materials: N traced samples of indirect light (as for still)\n"
    "  --bounce N        glTF materials: cached bounce light on N thousand points (as for still)\n"
    "  --tonemap T       clamp, reinhard or pbr-neutral (as still)\n"
    "  --exposure EV     scale radiance by 2^EV before tone mapping, or auto (metered once)\n"
    "  --background B    #RRGGBB or R,G,B (linear); transparent shows coverage over black\n"
    "  --environment F   light the scene with an equirectangular .hdr or .exr environment\n"
    "  --environment-rotation DEG   turn it about +Y;  --environment-intensity K   scale it\n"
    "  --ground G        shadow: an invisible shadow catcher under the model; none (as still)\n"
    "  --animation A     the model's animation to play, by name or index (as still)\n"
    "  --asset-root DIR, --max-texture-size N   glTF asset folder and texture size (as still)\n"
    "  --point-size PX   how wide glTF points and lines are drawn (as still)\n"
    "  --variant NAME    the model's material variant NAME (as still)\n"
    "  --threads N       render threads (default: all cores)\n"
    "  --frame N         start at frame N of the scene's timeline (default 0)\n"
    "  --camera N        the timeline looks through the model's glTF camera N, following its\n"
    "                    animation (R returns to it); --scene N: the file's scene N\n"
    "  -o FILE           where Ctrl+S saves the scene with its camera keys (default: NAME_view.json)\n"
    "  --stats FILE      on close, write frames shown, fps while moving and input latency as JSON\n"
    "\n"
    "rayfarm view --watch DIR [--total N]\n"
    "  shows the PNG frames a render writes to DIR as they complete, with frames done, fps and\n"
    "  ETA (of N frames); 'render --preview' opens it. Closing it does not stop the render.\n"
    "\n"
    "rayfarm view --stopped TEXT [--picture PNG]\n"
    "  a window saying why a session stopped over its last picture; a view under mpirun opens it\n"
    "  as mpirun ends the job (a rank died), so that the report outlives the job.\n"
    "\n"
    "Mouse: left drag orbits, middle or shift drag pans, the wheel zooms.\n"
    "Keys: F frames the model, R returns to the timeline's camera, Space plays/pauses, Left/Right\n"
    "step a frame, Home/End jump to the first/last frame, T tints tiles\n"
    "by rank, K adds a camera key at the current time, Delete removes the selected key,\n"
    "Ctrl+S saves, Ctrl+R renders the film to NAME.mp4 (again: cancels, frames kept; the next one\n"
    "resumes), Ctrl+Q closes.\n";

const char* kNoDisplay = "view: no display to open a window on (DISPLAY is not set); "
                         "use 'rayfarm render' for a video or 'rayfarm still' for a picture";

// Qt reports a display it cannot open through qFatal, after a few warning lines: say it in one
// line in rayfarm's words and leave with the usage status instead.
void qtMessages(QtMsgType type, const QMessageLogContext&, const QString& msg) {
    // The fatal message is generic ("no Qt platform plugin could be initialized"); the warning
    // before it says why (e.g. "could not connect to display :0"), so it goes in the line too.
    static QString lastWarning;
    if (type == QtWarningMsg && view::endIfDisplayLost(msg.toLocal8Bit().constData())) return;  // (it does not return)
    if (type == QtWarningMsg) lastWarning = msg.section('\n', 0, 0);
    if (type == QtFatalMsg) {
        const QString why = lastWarning.isEmpty() ? msg.section('\n', 0, 0) : lastWarning + ": " + msg.section('\n', 0, 0);
        std::fprintf(stderr, "rayfarm: error: view: cannot open a window (%s); use 'rayfarm render' or 'rayfarm still'\n",
                     why.toLocal8Bit().constData());
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

void checkDisplayAndOutputs(view::ViewOptions& o, const ArgParser& p) {
    if (!haveDisplay()) throw UsageError(kNoDisplay);
    // Ctrl+S must not write the path over the scene it was keyed on (or the stats over either).
    std::vector<std::string> inputs = {o.scenePath};
    if (auto env = p.value("--environment")) inputs.push_back(*env);
    checkOutputPaths({{"-o", o.savePath}, {"--stats", p.value("--stats").value_or("")}}, inputs);
    checkWritableFile(o.savePath);
    if (auto st = p.value("--stats")) {
        checkWritableFile(*st);
        o.statsPath = *st;
    }
}

/// The settings every rank renders with: the scene's, the picture options over them.
RenderSettings pictureSettings(const ArgParser& p, LoadedScene& loaded, const std::shared_ptr<SceneCacheSlot>& bounceSlot) {
    Scene& scene = loaded.scene;
    RenderSettings settings = scene.settings;
    applyQualityOptions(p, settings);
    // One EV for the whole session, the same on every rank (the meter is deterministic).
    // The metering frames fill the window's bounce cache, which its views then use.
    resolveAutoExposure(scene, anim::Timeline::fromScene(loaded), settings, 0, {}, bounceSlot);
    return settings;
}

/// Rank 0 (or the only process): the window. Returns the exit status.
int runWindow(const ArgParser& p, view::ViewOptions& o, view::ViewJob& job, LoadedScene loaded) {
    Scene& scene = loaded.scene;
    for (const std::string& note : scene.notes) std::cerr << "rayfarm: note: " << note << "\n";
    applyBackground(job.background, scene);
    const anim::Timeline timeline = anim::Timeline::fromScene(loaded);
    o.startFrame = p.intValue("--frame", 0, 0, view::filmOf(timeline).frames - 1);
    const RenderSettings settings = pictureSettings(p, loaded, o.bounceSlot);
    qInstallMessageHandler(qtMessages);
    int argc = 1;
    char name[] = "rayfarm";
    char* argv[] = {name, nullptr};
    QApplication app(argc, argv);
    view::ViewWindow window(std::move(loaded), timeline, settings, o);
    window.show();
    const auto destroyed = view::endWhenWindowDestroyed(app, window);
    const int status = app.exec();
    return window.failed() ? 1 : status;
}

/// A window of type W, made from args, in an application of its own (the display checked first)
/// until it closes: the plain windows that need nothing of the farm.
template <class W, class... Args>
int runPlainWindow(Args&&... args) {
    if (!haveDisplay()) throw UsageError(kNoDisplay);
    qInstallMessageHandler(qtMessages);
    int argc = 1;
    char name[] = "rayfarm";
    char* argv[] = {name, nullptr};
    QApplication app(argc, argv);
    W window(std::forward<Args>(args)...);
    window.show();
    const auto destroyed = view::endWhenWindowDestroyed(app, window);
    return app.exec();
}

int runStopped(const std::string& why, const std::string& picture) {
    return runPlainWindow<view::StoppedWindow>(why, picture);
}

int runPreview(const std::string& dir, int total) { return runPlainWindow<view::PreviewWindow>(dir, total); }

/// Under mpirun: rank 0 checks the display and loads the scene, every rank gets it by
/// broadcast; rank 0 opens the window and the others render for it.
int runFarmView(const ArgParser& p, view::ViewOptions& o, view::ViewJob& job) {
    farm::MpiTransport t;
    job.threads = o.threads > 0 ? o.threads : std::max(1, hardwareThreads() / std::max(1, t.ranksOnThisNode()));
    farm::SharedScene shared;
    try {
        shared = farm::shareScene(
            t, o.scenePath, [&] { checkDisplayAndOutputs(o, p); },
            [&](LoadedScene& loaded, const FileBundle&) {
                applyBackground(job.background, loaded.scene);  // as the window will: the meter sees it
                job.settings = pictureSettings(p, loaded, o.bounceSlot);
                return view::encodeViewJob(job);
            },
            sceneOptions(p));
    } catch (const farm::MasterLost&) {
        std::_Exit(1);  // it said why; MPI_Finalize would wait for rank 0 forever
    } catch (const farm::PeerFailed& e) {
        return e.code();
    } catch (const std::exception& e) {
        if (t.rank() == 0) throw;
        farm::reportWorkerError(t, std::string("loading the broadcast scene: ") + e.what());
        return 1;
    }
    if (t.rank() != 0) {
        const view::ViewJob j = view::decodeViewJob(shared.job);
        applyBackground(j.background, shared.scene);
        const int code = view::runViewWorker(t, std::move(shared.loaded()), j.settings, j.threads);
        if (code == farm::kMasterSilentExit) std::_Exit(1);  // MPI_Finalize would wait for rank 0
        return code;
    }
    o.transport = &t;
    o.threads = job.threads;
    view::setSessionEnd([&t](int code) { t.abort(code); });  // the display gone: every rank goes
    farm::installInterruptHandlers();  // mpirun's SIGTERM: the farm names the dead rank first
    const int status = runWindow(p, o, job, std::move(shared.loaded()));
    // A lost rank cannot be stopped politely and MPI_Finalize would wait for it: end them all.
    if (status != 0) t.abort(status);
    return status;
}
}  // namespace

namespace {
int runViewParsed(const std::vector<std::string>& args);
}  // namespace

int runView(const std::vector<std::string>& args) {
    try {
        return runViewParsed(args);
    } catch (const std::exception&) {
        // Under mpirun every rank meets the same bad argument: rank 0 alone says so.
        const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
        if (rank && std::string(rank) != "0") {
            // mpirun ends the whole job when a rank exits non-zero: give rank 0 the moment it
            // needs to print the line first.
            std::this_thread::sleep_for(std::chrono::milliseconds(500));
            return 2;
        }
        throw;
    }
}

namespace {
int runViewParsed(const std::vector<std::string>& args) {
    ArgParser p("view");
    for (const char* o : {"-o", "--size", "--spp", "--depth", "--min-weight", "--indirect", "--bounce", "--tonemap", "--threads", "--stats", "--frame", "--background", "--exposure", "--watch", "--total", "--stopped", "--picture"}) p.option(o);
    declareSceneOptions(p);
    p.flag("--help");
    p.flag("-h");
    p.parse(args);
    if (p.has("--help") || p.has("-h")) {
        std::fputs(kViewHelp, stdout);
        return 0;
    }
    if (auto why = p.value("--stopped")) return runStopped(*why, p.value("--picture").value_or(""));
    if (auto dir = p.value("--watch")) {
        if (!p.positional().empty()) throw UsageError("view: --watch takes a frames directory, not a scene");
        return runPreview(*dir, p.intValue("--total", 0, 0, 1 << 30));
    }
    if (p.positional().size() != 1) throw UsageError("view: expected one SCENE or MODEL (see rayfarm view --help)");
    view::ViewOptions o;
    o.scenePath = p.positional()[0];
    o.savePath = p.value("-o").value_or(std::filesystem::path(o.scenePath).stem().string() + "_view.json");
    o.threads = p.intValue("--threads", 0, 1, 4096);
    view::ViewJob job;
    if (auto b = p.value("--background")) job.background = parseBackground(*b);
    if (const char* n = std::getenv("OMPI_COMM_WORLD_SIZE"); n && std::atoi(n) > 1) return runFarmView(p, o, job);

    checkDisplayAndOutputs(o, p);
    DiskFileSource fs;
    return runWindow(p, o, job, loadScene(o.scenePath, fs, sceneOptions(p)));
}
}  // namespace

}  // namespace rf::cli
