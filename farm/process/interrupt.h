#pragma once
/// SIGINT and SIGTERM end a run cleanly instead of killing it: the handlers only note the
/// signal; the master and worker loops look at it and wind down. Under mpirun, Ctrl-C reaches
/// mpirun, which sends SIGTERM to every rank and SIGKILL about a second later, so the wind-down
/// finishes the video first.
///
/// SIGHUP (a dropped ssh session, a closed terminal) is handled the same way. A broken stderr
/// (`render ... 2>&1 | head -1`) too: SIGPIPE is ignored, so that a socket of the MPI
/// transport is never mistaken for it, and a write to stderr that fails with EPIPE raises the
/// interrupt as SIGPIPE (stderrGone). SIGXFSZ (a file past `ulimit -f`) is ignored: the write
/// fails with EFBIG instead and is reported as any failed write is.
#include <string>

namespace rf::farm {

/// Installs the handlers (idempotent). Each signal also stops a load in progress
/// (requestLoadCancel, engine/util/load_control.h).
void installInterruptHandlers();
/// Under mpirun: the launcher ending is taken as SIGTERM. A second Ctrl-C makes Open MPI 4.1's
/// mpirun exit at once, before the SIGTERM it would have forwarded, and its ranks would run on
/// unsignalled until their MPI library ends them about a second later, mid-write. Here the
/// kernel signals this process when its parent ends (PR_SET_PDEATHSIG), so the wind-down starts
/// at once. With keepItsStderr (rank 0, whose lines the user must see), mpirun's own stderr is
/// opened now (/proc/PPID/fd/2: the terminal, file or pipe that mpirun writes to): once the
/// parent has gone, the ranks' forwarded stderr leads nowhere, and writeStderrText writes there
/// instead. Call after installInterruptHandlers.
void followLauncher(bool keepItsStderr);
/// Only SIGXFSZ and SIGPIPE ignored (for commands that have no wind-down of their own).
void ignoreWriteSignals();
/// SIGINT, SIGTERM and SIGHUP back to their default action (end the process at once), for a
/// command that handles them only while it loads (`still`); a signal that arrived meanwhile is
/// acted on now, as the default action would have.
void restoreDefaultSignals();
/// The signal received (SIGINT, SIGTERM, SIGHUP, or SIGPIPE for a broken stderr), 0 if none.
int interruptSignal();
/// For tests: pretend a signal arrived (0 clears).
void raiseInterrupt(int sig);
/// "SIGINT", "SIGTERM", "SIGHUP", "SIGPIPE" (or "signal N").
std::string signalName(int sig);
/// The exit status of a run ended by sig, as the shell reports a process killed by it (128 + sig).
inline int signalExitStatus(int sig) { return 128 + sig; }

/// Writes text to stderr in one write() where it can (retried after EINTR or a short write).
/// Returns false when stderr is gone (EPIPE, EIO of a hung-up terminal, closed); EPIPE also
/// raises the interrupt as SIGPIPE, the way the default SIGPIPE would have ended the process.
bool writeStderrText(const std::string& text);

}  // namespace rf::farm
