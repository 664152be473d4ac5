#pragma once
/// SIGINT and SIGTERM end a run cleanly instead of killing it: the handlers only note the
/// signal; the master and worker loops look at it and wind down. Under mpirun, Ctrl-C reaches
/// mpirun, which sends SIGTERM to every rank and SIGKILL about a second later, so the wind-down
/// finishes the video first.

namespace rf::farm {

/// Installs the handlers (idempotent).
void installInterruptHandlers();
/// The signal received (SIGINT or SIGTERM), 0 if none.
int interruptSignal();
/// For tests: pretend a signal arrived (0 clears).
void raiseInterrupt(int sig);

}  // namespace rf::farm
