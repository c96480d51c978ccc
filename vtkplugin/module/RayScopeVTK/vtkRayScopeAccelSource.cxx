#include "vtkRayScopeAccelSource.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <thread>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"

#include "RayScopeArrays.h"
#include "rayscope/accel/accel_view.h"
#include "rayscope/frame.h"
#include "rayscope/replay.h"
#include "rayscope/scene.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeSceneSettings.h"

vtkStandardNewMacro(vtkRayScopeAccelSource);

vtkRayScopeAccelSource::vtkRayScopeAccelSource()
    : LevelRange{0, VTK_INT_MAX},
      OnlyLeaves(0),
      HideEmptyLeaves(0),
      OnlySplitPlanes(0),
      GenerateFaces(0),
      VisitMode(VISIT_NONE),
      Pixel{0, 0},
      VisitRay(-1),
      TraversalSteps(-1),
      NumberOfTraversalEntries(0) {}

vtkRayScopeAccelSource::~vtkRayScopeAccelSource() = default;

namespace {

// Integrator recorder that counts node visits per node id of the walked
// structure (the other hooks are NullRecorder's no-ops).
struct NodeVisitRecorder : rayscope::NullRecorder {
  static constexpr bool kActive = true;
  std::vector<uint32_t>* counts;
  explicit NodeVisitRecorder(std::vector<uint32_t>* c) : counts(c) {}

  struct Observer : rayscope::TraversalHooks {
    static constexpr bool kActive = true;
    std::vector<uint32_t>* c;
    explicit Observer(std::vector<uint32_t>* counts) : c(counts) {}
    void on_node(uint32_t node) { (*c)[node]++; }
  };
  Observer traversal(int) { return Observer{counts}; }
};

// Frame policy: every pixel with a NodeVisitRecorder on its thread's counts.
struct NodeVisitPolicy : rayscope::FramePolicy {
  using Recorder = NodeVisitRecorder;
  tbb::enumerable_thread_specific<std::vector<uint32_t>> local;
  explicit NodeVisitPolicy(size_t nodes)
      : local([nodes] { return std::vector<uint32_t>(nodes); }) {}
  NodeVisitRecorder recorder() { return NodeVisitRecorder{&local.local()}; }
};

// Node visits of every ray of the image: the frame loop of render() (same
// samples, same rays, same walk) with the visit-counting policy, summed over
// threads. Progress is reported from the calling thread only (VTK observers
// expect it there).
std::vector<uint32_t> frame_visits(const rayscope::Scene& scene,
                                   const rayscope::RenderSettings& settings, size_t nnodes,
                                   vtkRayScopeAccelSource* self) {
  NodeVisitPolicy policy(nnodes);
  const std::thread::id caller = std::this_thread::get_id();
  rayscope::render_frame(scene, settings, policy, nullptr, [&](size_t done, size_t total) {
    if (std::this_thread::get_id() == caller)
      self->UpdateProgress(0.9 * double(done) / double(total));
  });
  std::vector<uint32_t> total(nnodes, 0u);
  for (const auto& counts : policy.local)
    for (size_t i = 0; i < nnodes; ++i) total[i] += counts[i];
  return total;
}

using rayscope_vtkmodule::add_field_tuple;
using rayscope_vtkmodule::make_array;
using rayscope_vtkmodule::make_world_points;
using rayscope_vtkmodule::set_world_point;

}  // namespace

int vtkRayScopeAccelSource::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                        vtkInformationVector* outputVector) {
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (this->LevelRange[0] < 0 || this->LevelRange[1] < this->LevelRange[0]) {
    vtkErrorMacro(<< "LevelRange (" << this->LevelRange[0] << ", " << this->LevelRange[1]
                  << ") must satisfy 0 <= min <= max");
    return 0;
  }
  this->UpdateProgress(0.0);
  vtkRayScopeImageAlgorithm* source = this->UpdateScene(inputVector[0]);
  if (!source) return 0;
  if (!OutputOnThisProcess(source)) {
    output->Initialize();
    return 1;
  }
  const rayscope::Scene& scene = *source->GetCoreScene();
  const rayscope::RenderSettings settings = source->GetRenderSettings();
  const rayscope::AccelView view = rayscope::make_accel_view(scene.accel());
  const std::vector<rayscope::AccelViewNode>& nodes = view.nodes;
  const size_t nn = nodes.size();

  // Visit counts, and the states of a played walk.
  std::vector<uint32_t> visits(nn, 0u);
  std::vector<int> state, entry;
  const bool play = this->TraversalSteps >= 0;
  if (play && (this->VisitMode != VISIT_PIXEL || this->VisitRay < 0)) {
    vtkErrorMacro(<< "TraversalSteps " << this->TraversalSteps
                  << " plays one ray's walk: it needs VisitModeToPixel and a VisitRay >= 0");
    return 0;
  }
  if (this->VisitMode == VISIT_PIXEL) {
    const int i = this->Pixel[0], j = this->Pixel[1];
    if (i < 0 || j < 0 || i >= settings.width || j >= settings.height) {
      vtkErrorMacro(<< "Pixel (" << i << ", " << j << ") is outside the " << settings.width << "x"
                    << settings.height << " image");
      return 0;
    }
    rayscope::PixelRecord rec;
    try {
      rec = rayscope::record_pixel(scene, settings, i, settings.height - 1 - j);
    } catch (const std::exception& e) {
      vtkErrorMacro(<< "recording the pixel failed: " << e.what());
      return 0;
    }
    if (this->VisitRay < -1 || this->VisitRay >= int(rec.rays.size())) {
      vtkErrorMacro(<< "VisitRay " << this->VisitRay << " is outside -1.."
                    << int(rec.rays.size()) - 1 << " (the pixel's ray tree has " << rec.rays.size()
                    << " rays)");
      return 0;
    }
    for (const rayscope::RayRecord& r : rec.rays)
      if (this->VisitRay < 0 || r.id == this->VisitRay)
        for (uint32_t n : r.traversal.nodes()) visits[n]++;
    if (play) {
      const rayscope::TraversalRecord& walk = rec.rays[size_t(this->VisitRay)].traversal;
      state.assign(nn, 0);
      entry.assign(nn, -1);
      int entered = 0;
      for (const rayscope::TraversalStep& st : walk.steps) {
        using Kind = rayscope::TraversalStep::Kind;
        if (st.kind == Kind::Enter) {
          if (entered == this->TraversalSteps) break;
          state[st.node] = ENTERED;
          entry[st.node] = entered++;
        } else {
          state[st.node] = st.kind == Kind::BoxHit    ? BOX_HIT
                           : st.kind == Kind::BoxMiss ? BOX_MISSED
                                                      : CULLED;
        }
      }
      if (walk.hit_leaf != rayscope::kNoNode && state[walk.hit_leaf] == ENTERED)
        state[walk.hit_leaf] = HIT_LEAF;
      this->NumberOfTraversalEntries = int(walk.nodes().size());
    }
  } else if (this->VisitMode == VISIT_FRAME && nn > 0) {
    try {
      visits = frame_visits(scene, settings, nn, this);
    } catch (const std::exception& e) {
      vtkErrorMacro(<< "counting the frame's node visits failed: " << e.what());
      return 0;
    }
  }

  // Primitives in each subtree (deepest levels first, each added to its
  // parent) and each node's SAH term, relative to the root's area (the root
  // is the node without a parent: the grid's box has the last id).
  std::vector<uint32_t> subtree(nn, 0u), deepest_first(nn);
  for (uint32_t i = 0; i < uint32_t(nn); ++i) deepest_first[i] = i;
  std::stable_sort(deepest_first.begin(), deepest_first.end(),
                   [&](uint32_t a, uint32_t b) { return nodes[a].level > nodes[b].level; });
  double root_area = 1.0;
  for (uint32_t i : deepest_first) {
    subtree[i] += nodes[i].count;
    if (nodes[i].parent >= 0)
      subtree[size_t(nodes[i].parent)] += subtree[i];
    else
      root_area = std::max(1e-30, double(nodes[i].box.half_area()));
  }
  double sah_total = 0.0;
  std::vector<double> sah(nn, 0.0);
  for (size_t i = 0; i < nn; ++i) {
    const rayscope::AccelViewNode& n = nodes[i];
    sah[i] = double(n.box.half_area()) / root_area *
             ((n.leaf ? 0.0 : view.traversal_cost) + view.intersection_cost * n.count);
    sah_total += sah[i];
  }

  std::vector<uint32_t> shown;
  for (uint32_t i = 0; i < uint32_t(nn); ++i)
    if (nodes[i].level >= this->LevelRange[0] && nodes[i].level <= this->LevelRange[1] &&
        (!this->OnlyLeaves || nodes[i].leaf) && (!play || state[i] != 0) &&
        (play || !this->HideEmptyLeaves || !nodes[i].leaf || nodes[i].count > 0))
      shown.push_back(i);
  // The nodes drawn as volumes: every node shown, or with OnlySplitPlanes
  // (a BSP tree's partition; not for a played walk, whose states are the
  // boxes') only the root's box, whatever the levels, around the planes.
  std::vector<uint32_t> volumes;
  const bool planes_only = this->OnlySplitPlanes && !play;
  for (uint32_t i = 0; i < uint32_t(nn); ++i)
    if (planes_only ? nodes[i].parent < 0 : std::binary_search(shown.begin(), shown.end(), i))
      volumes.push_back(i);

  // A node with a sphere (the sphere tree) is drawn as that sphere: with
  // faces, a latitude-longitude surface of kRings x kSegments cells
  // (triangles at the poles, quads between); as lines, three great circles
  // (kSegments segments each, in the coordinate planes).
  constexpr int kSegments = 24, kRings = 12;
  const bool faces = this->GenerateFaces;
  auto point_count = [&](const rayscope::AccelViewNode& n) -> vtkIdType {
    if (!n.sphere) return 8;
    return faces ? vtkIdType((kRings - 1) * kSegments + 2) : vtkIdType(3 * kSegments);
  };
  auto cell_count = [&](const rayscope::AccelViewNode& n) -> vtkIdType {
    if (!n.sphere) return faces ? 6 : 12;
    return faces ? vtkIdType(kRings * kSegments) : vtkIdType(3 * kSegments);
  };
  vtkIdType npoints = 0, nvolume_cells = 0;
  for (uint32_t i : volumes) {
    npoints += point_count(nodes[i]);
    nvolume_cells += cell_count(nodes[i]);
  }
  // The BSP tree's split planes, clipped to their cells: one polygon per
  // inner node shown, after all boxes.
  std::vector<uint32_t> planes;
  vtkIdType plane_points = 0;
  for (uint32_t i : shown)
    if (nodes[i].polygon_count >= 3) {
      planes.push_back(i);
      plane_points += vtkIdType(nodes[i].polygon_count);
    }
  const vtkIdType ncells = nvolume_cells + vtkIdType(planes.size());
  vtkSmartPointer<vtkPoints> points = make_world_points(scene, npoints + plane_points);
  vtkNew<vtkCellArray> cells, plane_cells;
  cells->AllocateEstimate(nvolume_cells, faces ? 4 : 2);
  plane_cells->AllocateExact(vtkIdType(planes.size()), plane_points);
  auto a_level = make_array<vtkIntArray>("Level", 1, ncells);
  auto a_node = make_array<vtkIntArray>("NodeId", 1, ncells);
  auto a_parent = make_array<vtkIntArray>("ParentId", 1, ncells);
  auto a_leaf = make_array<vtkUnsignedCharArray>("IsLeaf", 1, ncells);
  auto a_count = make_array<vtkIntArray>("PrimitiveCount", 1, ncells);
  auto a_offset = make_array<vtkIntArray>("PrimitiveOffset", 1, ncells);
  auto a_sah = make_array<vtkDoubleArray>("SAHCost", 1, ncells);
  auto a_visits = make_array<vtkIntArray>("VisitCount", 1, ncells);
  vtkSmartPointer<vtkIntArray> a_state, a_entry;
  if (play) {
    a_state = make_array<vtkIntArray>("TraversalState", 1, ncells);
    a_entry = make_array<vtkIntArray>("EntryOrder", 1, ncells);
  }
  auto set_data = [&](vtkIdType c, uint32_t i) {
    const rayscope::AccelViewNode& n = nodes[i];
    a_level->SetValue(c, n.level);
    a_node->SetValue(c, int(i));
    a_parent->SetValue(c, n.parent);
    a_leaf->SetValue(c, n.leaf ? 1 : 0);
    a_count->SetValue(c, int(subtree[i]));
    a_offset->SetValue(c, n.count > 0 ? int(n.first) : -1);
    a_sah->SetValue(c, sah[i]);
    a_visits->SetValue(c, int(visits[i]));
    if (play) {
      a_state->SetValue(c, state[i]);
      a_entry->SetValue(c, entry[i]);
    }
  };
  vtkIdType cell = 0, point = 0;
  for (uint32_t i : volumes) {
    const rayscope::AccelViewNode& n = nodes[i];
    const vtkIdType p0 = point;
    point += point_count(n);
    if (!n.sphere) {
      const rayscope::Vec3 lo = n.box.lo, hi = n.box.hi;
      for (int c = 0; c < 8; ++c)
        set_world_point(
            points, p0 + c, scene,
            rayscope::Vec3((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z));
      for (int k = 0; k < (faces ? 6 : 12); ++k) {
        if (faces) {
          vtkIdType q[4];
          for (int v = 0; v < 4; ++v) q[v] = p0 + rayscope_vtkmodule::kBoxFaces[k][v];
          cells->InsertNextCell(4, q);
        } else {
          vtkIdType e[2] = {p0 + rayscope_vtkmodule::kBoxEdges[k][0],
                            p0 + rayscope_vtkmodule::kBoxEdges[k][1]};
          cells->InsertNextCell(2, e);
        }
      }
    } else {
      const rayscope::Vec3 c = n.sphere->center;
      const double r = double(n.sphere->radius);
      auto put = [&](vtkIdType id, double x, double y, double z) {
        set_world_point(points, id, scene,
                        c + rayscope::Vec3(float(r * x), float(r * y), float(r * z)));
      };
      const double step = 2.0 * rayscope::kPi / kSegments;
      if (faces) {
        // Point 0: the south pole; rings 1 .. kRings - 1 of kSegments points;
        // the last point: the north pole. Outward-facing (counterclockwise
        // seen from outside).
        put(p0, 0, 0, -1);
        for (int ring = 1; ring < kRings; ++ring) {
          const double th = rayscope::kPi * ring / kRings - 0.5 * rayscope::kPi;
          for (int sgm = 0; sgm < kSegments; ++sgm)
            put(p0 + 1 + (ring - 1) * kSegments + sgm, std::cos(th) * std::cos(step * sgm),
                std::cos(th) * std::sin(step * sgm), std::sin(th));
        }
        const vtkIdType north = p0 + 1 + (kRings - 1) * kSegments;
        put(north, 0, 0, 1);
        auto at = [&](int ring, int sgm) {  // ring 1 .. kRings - 1
          return p0 + 1 + (ring - 1) * kSegments + (sgm % kSegments);
        };
        for (int sgm = 0; sgm < kSegments; ++sgm) {
          const vtkIdType t[3] = {p0, at(1, sgm + 1), at(1, sgm)};
          cells->InsertNextCell(3, t);
        }
        for (int ring = 1; ring < kRings - 1; ++ring)
          for (int sgm = 0; sgm < kSegments; ++sgm) {
            const vtkIdType q[4] = {at(ring, sgm), at(ring, sgm + 1), at(ring + 1, sgm + 1),
                                    at(ring + 1, sgm)};
            cells->InsertNextCell(4, q);
          }
        for (int sgm = 0; sgm < kSegments; ++sgm) {
          const vtkIdType t[3] = {north, at(kRings - 1, sgm), at(kRings - 1, sgm + 1)};
          cells->InsertNextCell(3, t);
        }
      } else {
        for (int circle = 0; circle < 3; ++circle)
          for (int sgm = 0; sgm < kSegments; ++sgm) {
            double v[3] = {0, 0, 0};
            v[circle] = std::cos(step * sgm);
            v[(circle + 1) % 3] = std::sin(step * sgm);
            put(p0 + circle * kSegments + sgm, v[0], v[1], v[2]);
            const vtkIdType e[2] = {p0 + circle * kSegments + sgm,
                                    p0 + circle * kSegments + (sgm + 1) % kSegments};
            cells->InsertNextCell(2, e);
          }
      }
    }
    for (const vtkIdType end = cell + cell_count(n); cell < end; ++cell) set_data(cell, i);
  }
  std::vector<vtkIdType> ids;
  for (uint32_t i : planes) {
    const rayscope::AccelViewNode& n = nodes[i];
    ids.clear();
    for (uint32_t k = 0; k < n.polygon_count; ++k, ++point) {
      set_world_point(points, point, scene, view.polygon_vertices[n.polygon_first + k]);
      ids.push_back(point);
    }
    (faces ? cells.Get() : plane_cells.Get())->InsertNextCell(vtkIdType(ids.size()), ids.data());
    set_data(cell++, i);
  }

  output->Initialize();
  output->SetPoints(points);
  if (faces) {
    output->SetPolys(cells);
  } else {
    // Lines come before polygons in a vtkPolyData's cells: the boxes' edges
    // and spheres' circles, then the split polygons, as the cell data above.
    output->SetLines(cells);
    if (!planes.empty()) output->SetPolys(plane_cells);
  }
  vtkCellData* cd = output->GetCellData();
  for (vtkAbstractArray* a : std::initializer_list<vtkAbstractArray*>{
           a_level, a_node, a_parent, a_leaf, a_count, a_offset, a_sah, a_visits})
    cd->AddArray(a);
  if (play) {
    cd->AddArray(a_state);
    cd->AddArray(a_entry);
  }
  cd->SetActiveScalars("Level");

  vtkFieldData* fd = output->GetFieldData();
  auto leaf_ids = make_array<vtkIntArray>("LeafPrimitiveIds", 1, vtkIdType(view.refs.size()));
  for (size_t k = 0; k < view.refs.size(); ++k) leaf_ids->SetValue(vtkIdType(k), int(view.refs[k]));
  fd->AddArray(leaf_ids);
  add_field_tuple<vtkDoubleArray>(fd, "SAHCostTotal", {sah_total});
  add_field_tuple<vtkIntArray>(fd, "BVHUsed", {scene.summary().walks_structure ? 1 : 0});
  add_field_tuple<vtkIntArray>(fd, "TreeDepth", {view.depth});
  vtkNew<vtkStringArray> structure;
  structure->SetName("Structure");
  structure->InsertNextValue(view.structure);
  fd->AddArray(structure);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkRayScopeAccelSource::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LevelRange: " << this->LevelRange[0] << " " << this->LevelRange[1] << "\n";
  os << indent << "OnlyLeaves: " << this->OnlyLeaves << "\n";
  os << indent << "HideEmptyLeaves: " << this->HideEmptyLeaves << "\n";
  os << indent << "OnlySplitPlanes: " << this->OnlySplitPlanes << "\n";
  os << indent << "GenerateFaces: " << this->GenerateFaces << "\n";
  os << indent << "VisitMode: " << this->VisitMode << "\n";
  os << indent << "Pixel: " << this->Pixel[0] << " " << this->Pixel[1] << "\n";
  os << indent << "VisitRay: " << this->VisitRay << "\n";
  os << indent << "TraversalSteps: " << this->TraversalSteps << "\n";
}
