#include "farm/view/display_loss.h"

#include <QAbstractNativeEventFilter>
#include <QApplication>
#include <QByteArray>
#include <QWidget>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>

#include "farm/process/interrupt.h"

namespace rf::view {

namespace {

std::function<void(int)>& sessionEnd() {
    static std::function<void(int)> end;
    return end;
}

std::string displayName() {
    const char* d = std::getenv("DISPLAY");
    return d && *d ? d : "?";
}

/// X11 protocol, DestroyNotify (event code 17): code, unused, sequence (2 bytes), event window
/// (4), window (4). xcb hands events over in the wire layout; the top bit of the code marks an
/// event sent by a client.
constexpr uint8_t kDestroyNotify = 17;

class WindowGone : public QAbstractNativeEventFilter {
public:
    explicit WindowGone(uint32_t window) : window_(window) {}
    bool nativeEventFilter(const QByteArray& type, void* message, qintptr*) override {
        if (gone_ || type != "xcb_generic_event_t" || !message) return false;
        const auto* ev = static_cast<const uint8_t*>(message);
        if ((ev[0] & 0x7f) != kDestroyNotify) return false;
        uint32_t window = 0;
        std::memcpy(&window, ev + 8, sizeof window);
        if (window != window_) return false;
        gone_ = true;
        farm::writeStderrText("rayfarm: error: view: the window was destroyed from outside (on display " + displayName() +
                              "); the session ends\n");
        QCoreApplication::exit(1);
        return true;
    }

private:
    uint32_t window_;
    bool gone_ = false;
};

}  // namespace

void setSessionEnd(std::function<void(int)> end) { sessionEnd() = std::move(end); }

std::unique_ptr<QAbstractNativeEventFilter> endWhenWindowDestroyed(QApplication& app, QWidget& window) {
    if (QGuiApplication::platformName() != "xcb") return nullptr;
    auto filter = std::make_unique<WindowGone>(uint32_t(window.winId()));
    app.installNativeEventFilter(filter.get());
    return filter;
}

bool endIfDisplayLost(const char* msg) {
    if (std::strncmp(msg, "The X11 connection broke", 24) != 0) return false;
    farm::writeStderrText("rayfarm: error: view: lost the connection to the display " + displayName() + " (" + msg +
                          "); the session ends\n");
    // Qt would call exit() next, running static destructors under live render threads.
    if (sessionEnd()) sessionEnd()(1);
    std::_Exit(1);
}

}  // namespace rf::view
