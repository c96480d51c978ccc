// The TBB arena that a render's parallel work runs in (RenderSettings::threads).
#pragma once

#include <tbb/task_arena.h>

namespace rayscope {

/// An arena of `threads` threads; 0 (RenderSettings::threads' default) means
/// as many as the calling thread's arena has (every hardware thread outside
/// any arena).
inline tbb::task_arena thread_arena(int threads) {
  return tbb::task_arena(threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
}

}  // namespace rayscope
