#include "RayScopeParallel.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <span>
#include <stdexcept>
#include <type_traits>

#include "vtkAppendFilter.h"
#include "vtkAppendPolyData.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataObjectTree.h"
#include "vtkDataObjectTreeIterator.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkMultiProcessController.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include "rayscope/share_balance.h"
#include "rayscope/tiles.h"
#include "rayscope_vtkio/data_arrays.h"

namespace rayscope_vtkmodule {

int process_count(vtkMultiProcessController* controller) {
  return controller ? std::max(1, controller->GetNumberOfProcesses()) : 1;
}

int process_index(vtkMultiProcessController* controller) {
  return controller ? controller->GetLocalProcessId() : 0;
}

bool on_any_process(vtkMultiProcessController* controller, bool local) {
  if (process_count(controller) == 1) return local;
  const int mine = local ? 1 : 0;
  int any = 0;
  controller->AllReduce(&mine, &any, 1, vtkCommunicator::MAX_OP);
  return any != 0;
}

bool same_on_every_process(vtkMultiProcessController* controller, const std::vector<int>& values) {
  if (process_count(controller) == 1) return true;
  // The largest of v and of -v on every process: all equal when max == -max(-v).
  std::vector<int> both(values), largest(2 * values.size());
  for (int v : values) both.push_back(-v);
  controller->AllReduce(both.data(), largest.data(), vtkIdType(both.size()),
                        vtkCommunicator::MAX_OP);
  for (size_t i = 0; i < values.size(); ++i)
    if (largest[i] != -largest[values.size() + i]) return false;
  return true;
}

FirstProcessSpeaks::FirstProcessSpeaks(vtkMultiProcessController* controller)
    : Silenced(process_index(controller) != 0), Saved(vtkObject::GetGlobalWarningDisplay()) {
  if (this->Silenced) vtkObject::GlobalWarningDisplayOff();
}

FirstProcessSpeaks::~FirstProcessSpeaks() {
  if (this->Silenced) vtkObject::SetGlobalWarningDisplay(this->Saved);
}

namespace {

bool is_empty_piece(vtkDataObject* piece) {
  if (auto* ds = vtkDataSet::SafeDownCast(piece)) return ds->GetNumberOfPoints() == 0;
  return piece == nullptr;
}

// The leaves of a tree by flat index (empty nodes skipped).
void collect_leaves(vtkDataObjectTree* tree, std::map<unsigned, std::vector<vtkDataObject*>>& out) {
  vtkSmartPointer<vtkDataObjectTreeIterator> it;
  it.TakeReference(tree->NewTreeIterator());
  it->VisitOnlyLeavesOn();
  it->SkipEmptyNodesOn();
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    out[it->GetCurrentFlatIndex()].push_back(it->GetCurrentDataObject());
}

size_t count_leaves(vtkDataObjectTree* tree) {
  std::map<unsigned, std::vector<vtkDataObject*>> leaves;
  collect_leaves(tree, leaves);
  return leaves.size();
}

vtkSmartPointer<vtkDataObject> merge_trees(const std::vector<vtkDataObjectTree*>& trees,
                                           std::string& error) {
  // The structure of the piece with the most leaves (a process whose reader
  // gave nothing may hold an empty tree), every leaf merged across pieces.
  vtkDataObjectTree* shape = *std::max_element(
      trees.begin(), trees.end(),
      [](vtkDataObjectTree* a, vtkDataObjectTree* b) { return count_leaves(a) < count_leaves(b); });
  std::map<unsigned, std::vector<vtkDataObject*>> leaves;
  for (vtkDataObjectTree* t : trees) collect_leaves(t, leaves);
  vtkSmartPointer<vtkDataObjectTree> out;
  out.TakeReference(shape->NewInstance());
  out->CopyStructure(shape);
  vtkSmartPointer<vtkDataObjectTreeIterator> it;
  it.TakeReference(out->NewTreeIterator());
  it->VisitOnlyLeavesOn();
  it->SkipEmptyNodesOff();
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem()) {
    auto found = leaves.find(it->GetCurrentFlatIndex());
    if (found == leaves.end()) continue;
    vtkSmartPointer<vtkDataObject> merged = merge_pieces(found->second, error);
    if (!merged) return nullptr;
    out->SetDataSet(it, merged);
  }
  return out;
}

}  // namespace

vtkSmartPointer<vtkDataObject> merge_pieces(const std::vector<vtkDataObject*>& pieces,
                                            std::string& error) {
  vtkDataObject* first = nullptr;
  std::vector<vtkDataObject*> kept;
  for (vtkDataObject* p : pieces) {
    if (!p) continue;
    if (!first) first = p;
    if (!is_empty_piece(p)) kept.push_back(p);
  }
  if (kept.empty()) {
    vtkSmartPointer<vtkDataObject> empty;
    if (first)
      empty.TakeReference(first->NewInstance());
    else
      empty = vtkSmartPointer<vtkPolyData>::New();
    return empty;
  }
  if (kept.size() == 1) return kept[0];
  auto all = [&](auto is) { return std::all_of(kept.begin(), kept.end(), is); };
  if (all([](vtkDataObject* p) { return vtkPolyData::SafeDownCast(p) != nullptr; })) {
    vtkNew<vtkAppendPolyData> append;
    for (vtkDataObject* p : kept) append->AddInputData(vtkPolyData::SafeDownCast(p));
    append->Update();
    return append->GetOutput();
  }
  if (all([](vtkDataObject* p) { return vtkDataSet::SafeDownCast(p) != nullptr; })) {
    vtkNew<vtkAppendFilter> append;
    append->MergePointsOff();
    for (vtkDataObject* p : kept) append->AddInputData(p);
    append->Update();
    return append->GetOutput();
  }
  if (all([](vtkDataObject* p) { return vtkDataObjectTree::SafeDownCast(p) != nullptr; })) {
    std::vector<vtkDataObjectTree*> trees;
    for (vtkDataObject* p : kept) trees.push_back(vtkDataObjectTree::SafeDownCast(p));
    return merge_trees(trees, error);
  }
  error = "the processes hold pieces of different kinds (";
  for (size_t i = 0; i < kept.size(); ++i)
    error += std::string(i ? ", " : "") + kept[i]->GetClassName();
  error += "): they cannot be put together into one scene";
  return nullptr;
}

bool GatheredInputs::Update(vtkMultiProcessController* controller,
                            const std::vector<vtkDataObject*>& local, std::string& error) {
  std::vector<vtkMTimeType> times;
  for (vtkDataObject* d : local) times.push_back(d ? d->GetMTime() : 0);
  const bool changed = !this->Valid || local != this->Local || times != this->LocalTimes;
  if (!on_any_process(controller, changed)) return true;
  this->Valid = false;
  this->Local = local;
  this->LocalTimes = times;
  this->Merged.clear();
  ++this->Gathers;
  const int mine = int(local.size());
  int inputs = mine;
  controller->AllReduce(&mine, &inputs, 1, vtkCommunicator::MAX_OP);
  bool failed = false;
  for (int i = 0; i < inputs; ++i) {
    // A process without this input sends an empty piece (left out when merged).
    vtkSmartPointer<vtkDataObject> send = i < mine ? local[size_t(i)] : nullptr;
    if (!send) send = vtkSmartPointer<vtkPolyData>::New();
    std::vector<vtkSmartPointer<vtkDataObject>> received;
    failed |= controller->AllGather(send, received) == 0 ||
              int(received.size()) != process_count(controller);
    if (failed) continue;  // every process still takes part in every gather
    std::vector<vtkDataObject*> pieces;
    for (auto& r : received) pieces.push_back(r);
    std::string why;
    vtkSmartPointer<vtkDataObject> merged = merge_pieces(pieces, why);
    if (!merged) {
      if (error.empty()) error = "input " + std::to_string(i) + ": " + why;
      failed = true;
    }
    this->Merged.push_back(merged);
  }
  if (on_any_process(controller, failed)) {
    if (error.empty()) error = "the inputs could not be gathered from every process";
    this->Merged.clear();
    return false;
  }
  this->Valid = true;
  return true;
}

namespace {

// RayCounters is counters only (uint64_t), summed field by field.
static_assert(std::is_trivially_copyable_v<rayscope::RayCounters> &&
              sizeof(rayscope::RayCounters) % sizeof(unsigned long long) == 0);
constexpr size_t kCounterWords = sizeof(rayscope::RayCounters) / sizeof(unsigned long long);

}  // namespace

std::shared_ptr<const std::vector<int>> balanced_owners(vtkMultiProcessController* controller,
                                                        rayscope::Scene& scene,
                                                        const rayscope::RenderSettings& settings) {
  rayscope::RenderSettings mine = settings;
  mine.share = {process_index(controller), process_count(controller), nullptr};
  std::vector<uint64_t> costs;
  std::string failure;
  try {
    costs = rayscope::estimate_tile_costs(scene, mine);
  } catch (const std::exception& e) {
    failure = e.what();
  }
  if (on_any_process(controller, !failure.empty()))
    throw std::runtime_error(failure.empty() ? "another process could not estimate its tiles"
                                             : failure);
  std::vector<vtkIdType> local(costs.begin(), costs.end()), all(costs.size());
  controller->AllReduce(local.data(), all.data(), vtkIdType(all.size()), vtkCommunicator::SUM_OP);
  return std::make_shared<const std::vector<int>>(rayscope::balance_shares(
      std::vector<uint64_t>(all.begin(), all.end()), process_count(controller)));
}

bool assemble_image(vtkMultiProcessController* controller, const rayscope::RenderSettings& settings,
                    rayscope::Framebuffer& fb, rayscope::RayCounters& counters) {
  const int n = process_count(controller), me = process_index(controller);
  const std::vector<float> packed = rayscope::pack_share(fb, settings);
  const vtkIdType length = vtkIdType(packed.size());
  std::vector<vtkIdType> lengths(size_t(n), 0), offsets(size_t(n), 0);
  controller->Gather(&length, lengths.data(), 1, 0);
  std::vector<float> all;
  if (me == 0) {
    for (int r = 1; r < n; ++r)
      offsets[size_t(r)] = offsets[size_t(r - 1)] + lengths[size_t(r - 1)];
    all.resize(size_t(offsets.back() + lengths.back()));
  }
  controller->GatherV(packed.data(), all.data(), length, lengths.data(), offsets.data(), 0);
  unsigned long long mine[kCounterWords], sum[kCounterWords];
  std::memcpy(mine, &counters, sizeof counters);
  controller->Reduce(mine, sum, vtkIdType(kCounterWords), vtkCommunicator::SUM_OP, 0);
  if (me != 0) return false;
  for (int r = 0; r < n; ++r) {
    rayscope::RenderSettings share = settings;
    share.share.index = r;
    rayscope::unpack_share(
        fb, share,
        std::span<const float>(all.data() + offsets[size_t(r)], size_t(lengths[size_t(r)])));
  }
  std::memcpy(&counters, sum, sizeof counters);
  return true;
}

void add_process_array(vtkImageData* image, const rayscope::RenderSettings& settings) {
  const int w = settings.width, h = settings.height;
  auto process = rayscope_vtkio::make_array<vtkIntArray>("Process", 1, vtkIdType(w) * h);
  const rayscope::TileGrid grid(settings);
  // VTK's row j is the core's row h - 1 - j.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      process->SetValue(vtkIdType(h - 1 - y) * w + x, settings.share.owner(grid.tile_of(x, y)));
  image->GetPointData()->AddArray(process);
}

}  // namespace rayscope_vtkmodule
