// bench_viewer: the two latencies of `rayscope view` that issue 12 sets.
//
//   click to tree    a synthesized click on a pixel of the image, until the
//                    picked pixel's ray tree is in the window (replay of the
//                    pixel, ray-tree and BVH polydata, the overlay's filters,
//                    the text panel, one render of the window); the bunny
//                    scene at its own settings (640x480, 2x2 samples, depth
//                    6), 41 pixels along the image's middle row, median.
//   first frame      a 640x480, 1 sample per pixel re-render of the default
//                    scene on 2 threads, from the key that asks for it to
//                    the complete frame on screen (the worker's frame loop,
//                    the image arrays, one render of the window); median of 9.
//
// Needs an X display: xvfb-run -a build/bench/bench_viewer [data/scenes/bunny.json]
// Built with the benchmarks; not run by the tests (docs/performance.md has
// figures from this machine).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <vtkCommand.h>
#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>

#include "rayscope/scene_io.h"
#include "rayscope/shapes.h"
#include "rayscope_vtkio/mesh_files.h"
#include "vtkPolyData.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeRayTreeSource.h"
#include "vtkRayScopeViewer.h"

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void configure(vtkRayScopeImageAlgorithm* alg, const rayscope::Scene& scene,
               const rayscope::RenderSettings& rs) {
  alg->SetSize(rs.width, rs.height);
  alg->SetSamples(rs.samples);
  alg->SetMaxDepth(rs.max_depth);
  alg->SetMinContribution(rs.min_contribution);
  alg->SetThreads(2);
  alg->SetCoreScene(scene);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2 || (argc == 2 && argv[1][0] == '-')) {
    std::fprintf(stderr, "usage: xvfb-run -a bench_viewer [SCENE.json]\n");
    return 2;
  }
  const std::string bunny_file =
      argc > 1 ? argv[1] : std::string(RAYSCOPE_SOURCE_DIR) + "/data/scenes/bunny.json";

  // Click to tree, bunny scene.
  rayscope::LoadedScene bunny;
  try {
    bunny = rayscope::load_scene(bunny_file, rayscope_vtkio::load_meshes);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_viewer: %s\n", e.what());
    return 1;
  }
  bunny.scene.commit();
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  configure(alg, bunny.scene, bunny.settings);
  vtkNew<vtkRayScopeViewer> viewer;
  viewer->SetSceneSource(alg);
  if (!viewer->Initialize() || !viewer->WaitForRender()) {
    std::fprintf(stderr, "bench_viewer: %s\n", viewer->GetMessage());
    return 1;
  }
  vtkRenderer* image = viewer->GetImageRenderer();
  vtkRenderWindowInteractor* iren = viewer->GetInteractor();
  const int w = bunny.settings.width, h = bunny.settings.height;
  std::vector<double> clicks, redraws;
  size_t rays = 0;
  for (int k = 0; k < 41; ++k) {
    const int i = w / 8 + k * (3 * w / 4) / 40, j = h / 2;
    image->SetWorldPoint(i, j, 0.0, 1.0);
    image->WorldToDisplay();
    double d[3];
    image->GetDisplayPoint(d);
    iren->SetEventInformation(int(d[0] + 0.5), int(d[1] + 0.5), 0, 0);
    const Clock::time_point t0 = Clock::now();
    iren->InvokeEvent(vtkCommand::LeftButtonPressEvent);
    clicks.push_back(ms_since(t0));
    iren->InvokeEvent(vtkCommand::LeftButtonReleaseEvent);
    if (viewer->GetPickedPixel()[0] != i) {
      std::fprintf(stderr, "bench_viewer: the click missed pixel %d\n", i);
      return 1;
    }
    rays += size_t(viewer->GetRayTreeSource()->GetOutput()->GetNumberOfLines());
    // The same window drawn again with nothing changed: what OpenGL alone costs.
    const Clock::time_point t1 = Clock::now();
    viewer->GetRenderWindow()->Render();
    redraws.push_back(ms_since(t1));
  }
  const int* ws = viewer->GetRenderWindow()->GetSize();
  std::printf(
      "click to tree, %s (%dx%d, %dx%d samples, depth %d): median %.1f ms, min %.1f, "
      "max %.1f over %zu clicks (%.1f rays per tree); the unchanged %dx%d window "
      "redrawn alone: median %.1f ms\n",
      bunny_file.c_str(), w, h, bunny.settings.samples, bunny.settings.samples,
      bunny.settings.max_depth, median(clicks), *std::min_element(clicks.begin(), clicks.end()),
      *std::max_element(clicks.begin(), clicks.end()), clicks.size(),
      double(rays) / double(clicks.size()), ws[0], ws[1], median(redraws));

  // First complete frame of a re-render, default scene, 640x480, 1 spp, 2 threads.
  rayscope::Scene def = rayscope::make_default_scene();
  def.commit();
  rayscope::RenderSettings rs;
  rs.width = 640;
  rs.height = 480;
  rs.samples = 1;
  vtkNew<vtkRayScopeImageAlgorithm> alg2;
  configure(alg2, def, rs);
  vtkNew<vtkRayScopeViewer> viewer2;
  viewer2->SetSceneSource(alg2);
  if (!viewer2->Initialize() || !viewer2->WaitForRender()) {
    std::fprintf(stderr, "bench_viewer: %s\n", viewer2->GetMessage());
    return 1;
  }
  std::vector<double> frames, worker;
  for (int k = 0; k < 9; ++k) {
    const Clock::time_point t0 = Clock::now();
    viewer2->Rerender();
    viewer2->WaitForRender();
    frames.push_back(ms_since(t0));
    worker.push_back(1000.0 * viewer2->GetLastRenderSeconds());
  }
  std::printf(
      "first frame, default scene 640x480, 1 spp, 2 threads: median %.1f ms on screen "
      "(frame loop %.1f ms), min %.1f, max %.1f over %zu re-renders\n",
      median(frames), median(worker), *std::min_element(frames.begin(), frames.end()),
      *std::max_element(frames.begin(), frames.end()), frames.size());
  return 0;
}
