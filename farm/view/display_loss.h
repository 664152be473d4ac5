#pragma once
/// The display going away under a window: its X window destroyed from outside (`xdotool
/// windowclose`, a crashed compositor, a killed X forwarder all call XDestroyWindow) or the
/// connection to the X server lost. Qt notices neither as a close: with the window destroyed
/// it went on running with nothing on screen, and on a lost connection it called exit(1)
/// without a word. Both now end the session in one line, exit status 1, and under mpirun its
/// ranks go with it.
#include <QAbstractNativeEventFilter>

#include <functional>
#include <memory>

class QApplication;
class QWidget;

namespace rf::view {

/// How the session ends (status 1) once the display is gone: set by a session under mpirun to
/// MPI_Abort, which takes every rank; unset, the process ends itself.
void setSessionEnd(std::function<void(int)> end);

/// Watches the X events of app for the destruction of window's native window: then says so in
/// one line and makes app.exec() return 1. Nothing (null) on a platform other than xcb. Call
/// after window.show(); keep the filter until app.exec() returns.
std::unique_ptr<QAbstractNativeEventFilter> endWhenWindowDestroyed(QApplication& app, QWidget& window);

/// From the Qt message handler: true (and the session ended) when msg is xcb's report of a
/// broken connection to the X server.
bool endIfDisplayLost(const char* msg);

}  // namespace rf::view
