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

rayscope::Framebuffer render_relaying_progress(rayscope::Scene& scene,
                                               const rayscope::RenderSettings& settings,
                                               rayscope::RayCounters* counters,
                                               const std::function<void(double)>& report) {
  rayscope::Framebuffer fb;
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable cv;
  size_t done = 0, total = 1;
  bool finished = false;
  std::thread worker([&] {
    try {
      fb = rayscope::render(scene, settings, counters, [&](size_t d, size_t t) {
        std::lock_guard<std::mutex> lock(mutex);
        done = std::max(done, d);  // calls are serialised but may arrive out of order
        total = t;
        cv.notify_one();
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
  return fb;
}

}  // namespace rayscope_vtkmodule
