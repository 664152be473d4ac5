#pragma once
/// The worker loop (ranks 1…N−1): take work items from rank 0, render them on the rank's
/// threads, send pixels back (pixel mode with chunked encoding: to the rank that assembles
/// their frame, which may be this one), and say it is alive every kHeartbeatSeconds meanwhile.
#include <functional>

#include "farm/cluster/chunk_workshop.h"
#include "farm/cluster/render_engine.h"
#include "farm/cluster/transport.h"

namespace rf::farm {

/// What runWorker returns when rank 0 fell silent: the caller must leave at once (_exit), as
/// MPI_Finalize would wait for rank 0 forever.
inline constexpr int kMasterSilentExit = 3;
/// What runWorker returns when rank 0 says stop after it gave up on a worker (kStopAfterLoss):
/// the caller leaves at once with status 0, as MPI_Finalize would wait for the lost rank.
inline constexpr int kStopAfterLossExit = 4;

/// Runs until rank 0 says stop (returns 0, or kStopAfterLossExit), the render fails (the error goes to rank 0 first;
/// returns 1), a signal arrives and rank 0 does not say stop within a few seconds (returns 130),
/// or rank 0 is lost (prints why; returns kMasterSilentExit): this rank sees rank 0's process
/// end (the same machine), or rank 0 says nothing for `masterTimeout` seconds (master_watch.h). Before rank 0's first word (it may still be checking kept
/// frames or building its renderer) the limit is `firstWordTimeout`, 6 × masterTimeout when 0.
/// kTagView sets the engine's interactive epoch (RenderEngine::setView); other tags runWorker
/// does not know go to `other` when given (a viewer's own messages). shop: the rank's
/// ChunkWorkshop over engine when the job encodes chunks on the ranks (kTagChunkAssemble,
/// kTagTile).
int runWorker(Transport& t, RenderEngine& engine, double masterTimeout = 20.0,
              const std::function<void(const Message&)>& other = nullptr, ChunkWorkshop* shop = nullptr,
              double firstWordTimeout = 0.0);

/// Tells rank 0 this worker failed (before it could render anything, e.g. while loading).
void reportWorkerError(Transport& t, const std::string& message);

/// After a failure it told rank 0 of, in a job of several films: waits (up to `seconds`) for
/// rank 0's word to stop that film, so that the word is not taken for the next film's.
void awaitStop(Transport& t, double seconds);

}  // namespace rf::farm
