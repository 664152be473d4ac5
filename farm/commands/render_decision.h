#pragma once
/// Rank 0's decisions for a film before anything renders: its outputs claimed, then the job
/// decided from the options and the loaded scene (frames, format, mode, exposure, the frames
/// directory) and its plan line printed.
#include <string>
#include <vector>

#include "engine/util/file_source.h"
#include "engine/load/loaded_scene.h"
#include "engine/scene/scene.h"
#include "farm/cli/cli.h"
#include "farm/cluster/render_job.h"
#include "farm/output/output_lock.h"
#include "farm/output/output_paths.h"

namespace rf::cli {

/// Every file the render writes, by the option that names it (for checkOutputPaths).
std::vector<NamedOutput> renderOutputs(const farm::RenderJob& job);

/// Rank 0 before the scene is read: the outputs can be written, name no input and no other
/// output, and no other run writes them (the locks, held until the run ends); an earlier run's
/// frames are not thrown away unasked.
void claimOutputs(const farm::RenderJob& job, const ArgParser& p, std::vector<OutputLock>& locks);

/// Rank 0's part of makeJob: everything decided from the options and the loaded scene, checked
/// before any rendering.
void decideJob(farm::RenderJob& job, const ArgParser& p, LoadedScene& loaded, const std::shared_ptr<SceneCacheSlot>& bounceSlot,
               const FileBundle& inputs, int ranks, const std::string& threadsNote, bool filmOfSeveral);

}  // namespace rf::cli
