#include "RayScopeProgressRelay.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

#include "rayscope/render.h"
#include "rayscope/scene.h"

namespace rayscope_vtkmodule {

void render_relaying_progress(rayscope::Framebuffer& fb, rayscope::Scene& scene,
                              const rayscope::RenderSettings& settings,
                              rayscope::RayCounters* counters,
                              const std::function<void(double)>& report) {
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable cv;
  size_t done = 0, total = 1, notified = 0;
  bool finished = false;
  std::thread worker([&] {
    try {
      rayscope::render_into(fb, scene, settings, counters, [&](size_t d, size_t t) {
        std::lock_guard<std::mutex> lock(mutex);
        done = std::max(done, d);  // calls are serialised but may arrive out of order
        total = t;
        // The calling thread is woken only for a step it reports (1%): a
        // wake-up per tile (900 at 1280x720) took the render's cores from it.
        if ((done - notified) * 100 >= total) {
          notified = done;
          cv.notify_one();
        }
      });
    } catch (...) {
      failure = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(mutex);
    finished = true;
    cv.notify_one();
  });
  {
    double reported = 0.0;
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      cv.wait_for(lock, std::chrono::milliseconds(100));
      if (finished) break;
      const double p = double(done) / double(std::max<size_t>(total, 1));
      if (p >= reported + 0.01) {
        reported = p;
        lock.unlock();
        report(p);
        lock.lock();
      }
    }
  }
  worker.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace rayscope_vtkmodule
