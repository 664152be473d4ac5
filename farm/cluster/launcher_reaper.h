#pragma once
/// Ends a hung mpirun. When a host is cut off the network, Open MPI 4.1's mpirun can wait for
/// its daemon there for as long as TCP retransmits (about 15 minutes): the order to kill the job
/// sits unacknowledged in the socket, where the OOB keepalive does not apply. So before rank 0
/// aborts, it leaves a small process behind that kills mpirun (rank 0's parent, if that is
/// mpirun) if mpirun is still there after `seconds`. The daemons on reachable hosts see mpirun go
/// and end their ranks; a cut-off host's worker leaves its silent master by itself.

namespace rf::farm {

/// No-op unless this process's parent is mpirun/orterun. Returns at once.
void armLauncherReaper(double seconds);

}  // namespace rf::farm
