// A vtkRayScopeImageAlgorithm rendered by every process of a
// vtkMultiProcessController (private header). Each process holds a piece of
// every input. The pieces are gathered to every process when any changed,
// each process builds the whole scene and traces its share of the image's
// tiles over it (rayscope::TileShare, handed out by balanced_owners()), and
// process 0 assembles the
// image. All calls here are collective: every process makes them in the same
// order, whatever its data, so a process with nothing to draw still takes part
// and an error on one process ends the render on all of them.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "vtkSmartPointer.h"
#include "vtkType.h"

#include "rayscope/image.h"
#include "rayscope/render_settings.h"
#include "rayscope/scene.h"
#include "rayscope/stats.h"

class vtkDataObject;
class vtkImageData;
class vtkMultiProcessController;

namespace rayscope_vtkmodule {

/// The processes of `controller`: 1 without one.
int process_count(vtkMultiProcessController* controller);
/// This process's index: 0 without a controller.
int process_index(vtkMultiProcessController* controller);

/// True on every process when `local` is true on at least one.
bool on_any_process(vtkMultiProcessController* controller, bool local);

/// True on every process when `values` are the same on all of them.
bool same_on_every_process(vtkMultiProcessController* controller, const std::vector<int>& values);

/// While it lives, VTK's warnings and errors are silent on every process but
/// 0: around checks that every process makes alike on the same data, so that
/// each problem is shown once.
class FirstProcessSpeaks {
 public:
  explicit FirstProcessSpeaks(vtkMultiProcessController* controller);
  ~FirstProcessSpeaks();
  FirstProcessSpeaks(const FirstProcessSpeaks&) = delete;
  FirstProcessSpeaks& operator=(const FirstProcessSpeaks&) = delete;

 private:
  bool Silenced;
  int Saved;
};

/// The pieces of one input from processes 0, 1, ... as one data object, as a
/// serial reader of all pieces makes it: polydata appended in order
/// (vtkAppendPolyData), other datasets as one vtkUnstructuredGrid
/// (vtkAppendFilter, points not merged), composite data leaf by leaf (the
/// pieces of each flat index merged so). Null and empty pieces are left out;
/// all empty gives an empty piece of the first one's type. Pieces of
/// different kinds give null and `error`.
vtkSmartPointer<vtkDataObject> merge_pieces(const std::vector<vtkDataObject*>& pieces,
                                            std::string& error);

/// The inputs of a parallel render: every process's pieces, merged
/// (merge_pieces()) input by input.
class GatheredInputs {
 public:
  /// Gathers `local` (this process's data object of each input; null for an
  /// input it lacks) from every process when any process's inputs changed
  /// since the last call (other objects, or modified), and keeps the merged
  /// inputs otherwise, so that their pointers and times stay the same and the
  /// scene is not converted again. 0 inputs on every process gives 0 merged.
  /// On failure (a marshalling error, pieces of different kinds), returns
  /// false with `error` the same on every process.
  bool Update(vtkMultiProcessController* controller, const std::vector<vtkDataObject*>& local,
              std::string& error);
  const std::vector<vtkSmartPointer<vtkDataObject>>& Get() const { return this->Merged; }
  /// How often Update() gathered.
  size_t GetGathers() const { return this->Gathers; }

 private:
  std::vector<vtkDataObject*> Local;
  std::vector<vtkMTimeType> LocalTimes;
  std::vector<vtkSmartPointer<vtkDataObject>> Merged;
  bool Valid = false;
  size_t Gathers = 0;
};

/// The tiles of the image of `settings` handed out to the processes by
/// estimated cost (rayscope::balance_shares()): each process estimates the
/// tiles of its interleaved share (settings.share without owners) on its
/// `scene` (every process holds the same), the estimates are summed over all
/// processes, and every process makes the same map from them. Collective.
/// Throws what the estimate throws on any process (std::runtime_error for
/// the others), on every process.
std::shared_ptr<const std::vector<int>> balanced_owners(vtkMultiProcessController* controller,
                                                        rayscope::Scene& scene,
                                                        const rayscope::RenderSettings& settings);

/// Process 0 receives every process's share of the image (settings.share is
/// this process's: process_index of process_count, with the owner map all
/// processes render by) and unpacks it into `fb`,
/// and the sum of all processes' counters into `counters`; returns true there
/// and false on the others, whose fb and counters are unchanged. `fb` holds
/// this process's render and has its channels (cost, samples).
bool assemble_image(vtkMultiProcessController* controller, const rayscope::RenderSettings& settings,
                    rayscope::Framebuffer& fb, rayscope::RayCounters& counters);

/// Adds to `image` (the assembled image of `settings`, whose share.count is
/// the process count) the point array "Process": the process that traced
/// each pixel.
void add_process_array(vtkImageData* image, const rayscope::RenderSettings& settings);

}  // namespace rayscope_vtkmodule
