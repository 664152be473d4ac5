#pragma once
/// The launcher part of a printed resume command. Under mpirun the command must keep mpirun's
/// own options (--oversubscribe, --hostfile, --mca ...), or it fails as printed.
#include <string>

namespace rf::farm {

/// Shell-quotes s if it holds anything beyond plain path characters.
std::string shellQuote(const std::string& s);

/// What to put before the rayfarm executable: "" for one plain process; under mpirun, mpirun's
/// own arguments as it was started (read from /proc when rank 0 is mpirun's child), else
/// "mpirun -np N" with the options Open MPI exported to this rank's environment. mpirun's
/// arguments are read at the first call (cmd_render asks early, while mpirun surely runs).
std::string launcherPrefix(int ranks);

/// Under Open MPI's mpirun with workers: "" when mpirun keeps the job alive when a rank dies
/// (--enable-recovery, i.e. OMPI_MCA_orte_enable_recovery set), else a note that a dying worker
/// ends the whole job and how to keep it going. "" for one rank or other launchers.
std::string keepAliveNote(int ranks);

/// Whether the launcher lets the job go on when a rank dies: Open MPI's mpirun only with
/// --enable-recovery (OMPI_MCA_orte_enable_recovery); true for other launchers (srun
/// --no-kill is the user's to give), false for one process.
bool launcherKeepsJobAlive();

}  // namespace rf::farm
