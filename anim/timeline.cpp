#include "timeline.h"

#include "frame_time.h"

namespace rf::anim {

// First cut: a scene is one still frame. The keyframed timeline replaces this.
Timeline Timeline::fromScene(const Scene&) { return Timeline{}; }

double Timeline::frameTime(int frame) const { return anim::frameTime(t0_, fps_, frame); }

void Timeline::apply(Scene&, double) const {}

}  // namespace rf::anim
