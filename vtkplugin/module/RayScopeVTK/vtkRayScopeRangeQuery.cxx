#include "vtkRayScopeRangeQuery.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <vector>

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkLineSource.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkStringArray.h"
#include "vtkTubeFilter.h"
#include "vtkUnsignedCharArray.h"

#include "RayScopeArrays.h"
#include "rayscope/scene.h"
#include "rayscope/stats.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeSceneSettings.h"

vtkStandardNewMacro(vtkRayScopeRangeQuery);

vtkRayScopeRangeQuery::vtkRayScopeRangeQuery()
    : QueryType(QUERY_BOX),
      Box{-0.5, 0.5, -0.5, 0.5, -0.5, 0.5},
      Center{0.0, 0.0, 0.0},
      Radius(1.0),
      NumberOfNeighbors(1),
      SphereResolution(24) {
  this->SetNumberOfOutputPorts(2);
}

vtkRayScopeRangeQuery::~vtkRayScopeRangeQuery() = default;

namespace {

using rayscope::DVec3;

// Polygons in world coordinates, one object at a time, with the objects'
// cell data.
struct PolyBuilder {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> polys;
  std::vector<int> rank, kind, prim, plane, object;
  std::vector<double> distance;

  PolyBuilder() { points->SetDataTypeToDouble(); }

  void polygon(const std::vector<DVec3>& corners) {
    std::vector<vtkIdType> ids;
    for (const DVec3& p : corners) ids.push_back(points->InsertNextPoint(p.x, p.y, p.z));
    polys->InsertNextCell(vtkIdType(ids.size()), ids.data());
  }
  // The polygons of a polydata (a tessellated sphere), appended.
  void polydata(vtkPolyData* pd) {
    const vtkIdType base = points->GetNumberOfPoints();
    for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
      points->InsertNextPoint(pd->GetPoint(i));
    vtkCellArray* src = pd->GetPolys();
    vtkIdType n;
    const vtkIdType* pts;
    std::vector<vtkIdType> ids;
    for (src->InitTraversal(); src->GetNextCell(n, pts);) {
      ids.assign(pts, pts + n);
      for (vtkIdType& id : ids) id += base;
      polys->InsertNextCell(n, ids.data());
    }
  }
  // Cell data for every cell added since `first_cell`.
  void tag(vtkIdType first_cell, int r, int k, int p, int pl, int obj, double d) {
    for (vtkIdType c = first_cell; c < polys->GetNumberOfCells(); ++c) {
      rank.push_back(r);
      kind.push_back(k);
      prim.push_back(p);
      plane.push_back(pl);
      object.push_back(obj);
      distance.push_back(d);
    }
  }
  void output(vtkPolyData* out) const {
    out->Initialize();
    out->SetPoints(points);
    out->SetPolys(polys);
    const vtkIdType n = vtkIdType(rank.size());
    auto add = [&](const auto& values, auto array) {
      for (vtkIdType c = 0; c < n; ++c) array->SetValue(c, values[size_t(c)]);
      out->GetCellData()->AddArray(array);
    };
    using rayscope_vtkmodule::make_array;
    add(rank, make_array<vtkIntArray>("Rank", 1, n));
    add(kind, make_array<vtkIntArray>("ObjectKind", 1, n));
    add(prim, make_array<vtkIntArray>("PrimitiveId", 1, n));
    add(plane, make_array<vtkIntArray>("PlaneId", 1, n));
    add(object, make_array<vtkIntArray>("ObjectId", 1, n));
    add(distance, make_array<vtkDoubleArray>("Distance", 1, n));
    out->GetCellData()->SetActiveScalars("Rank");
  }
};

// "ObjectKind" of a found object.
constexpr int kKindTriangle = 0, kKindSphere = 1, kKindPlane = 2, kKindTube = 3;

// A tessellated capsule (a tube segment) in world coordinates: its cylinder,
// closed by spheres at both ends.
vtkSmartPointer<vtkPolyData> capsule_polys(const DVec3& a, const DVec3& b, double radius,
                                           int resolution);

// A tessellated sphere in world coordinates.
vtkSmartPointer<vtkPolyData> sphere_polys(const DVec3& center, double radius, int resolution) {
  vtkNew<vtkSphereSource> s;
  s->SetCenter(center.x, center.y, center.z);
  s->SetRadius(radius);
  s->SetThetaResolution(resolution);
  s->SetPhiResolution(resolution);
  s->Update();
  return s->GetOutput();
}

vtkSmartPointer<vtkPolyData> capsule_polys(const DVec3& a, const DVec3& b, double radius,
                                           int resolution) {
  vtkNew<vtkLineSource> line;
  line->SetPoint1(a.x, a.y, a.z);
  line->SetPoint2(b.x, b.y, b.z);
  vtkNew<vtkTubeFilter> tube;
  tube->SetInputConnection(line->GetOutputPort());
  tube->SetRadius(radius);
  tube->SetNumberOfSides(resolution);
  vtkNew<vtkAppendPolyData> all;
  all->AddInputConnection(tube->GetOutputPort());
  all->AddInputData(sphere_polys(a, radius, resolution));
  all->AddInputData(sphere_polys(b, radius, resolution));
  all->Update();
  return all->GetOutput();
}

// A box's 6 faces.
void box_faces(PolyBuilder& out, const DVec3& lo, const DVec3& hi) {
  auto corner = [&](int c) {
    return DVec3((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
  };
  for (const auto& f : rayscope_vtkmodule::kBoxFaces)
    out.polygon({corner(f[0]), corner(f[1]), corner(f[2]), corner(f[3])});
}

}  // namespace

int vtkRayScopeRangeQuery::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                       vtkInformationVector* outputVector) {
  vtkPolyData* found_out = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* range_out = vtkPolyData::GetData(outputVector, 1);
  found_out->Initialize();
  range_out->Initialize();
  vtkRayScopeImageAlgorithm* source = this->UpdateScene(inputVector[0]);
  if (!source) return 0;
  if (!OutputOnThisProcess(source)) return 1;  // outputs empty: process 0 makes them
  const rayscope::Scene& scene = *source->GetCoreScene();
  const rayscope::Aggregate& accel = scene.accel();

  // The query, in the scene's local coordinates; the core checks the range.
  rayscope::PixelCost cost;
  rayscope::StatsRecorder::Observer obs(&cost);
  std::vector<rayscope::RangeHit> found;
  DVec3 lo(this->Box[0], this->Box[2], this->Box[4]), hi(this->Box[1], this->Box[3], this->Box[5]);
  const DVec3 center(this->Center[0], this->Center[1], this->Center[2]);
  try {
    switch (this->QueryType) {
      case QUERY_BOX: {
        rayscope::Bounds3 box;
        box.lo = scene.to_local(lo);
        box.hi = scene.to_local(hi);
        found = accel.query_box(box, obs);
        break;
      }
      case QUERY_SPHERE:
        found = accel.query_sphere(scene.to_local(center), float(this->Radius), obs);
        break;
      default:
        if (this->NumberOfNeighbors < 1)
          throw std::invalid_argument("NumberOfNeighbors must be at least 1, got " +
                                      std::to_string(this->NumberOfNeighbors));
        found = accel.nearest(scene.to_local(center), uint32_t(this->NumberOfNeighbors), obs);
        break;
    }
  } catch (const std::exception& e) {
    vtkErrorMacro(<< "the range query failed: " << e.what());
    return 0;
  }

  // The range as drawn: the box, or the sphere (for the nearest query,
  // through the farthest object found).
  double radius = this->Radius;
  if (this->QueryType == QUERY_NEAREST)
    radius = found.empty() ? 0.0 : double(found.back().distance);
  if (this->QueryType != QUERY_BOX) {
    lo = center - DVec3(radius);
    hi = center + DVec3(radius);
  }

  PolyBuilder objects;
  for (size_t r = 0; r < found.size(); ++r) {
    const rayscope::RangeHit& h = found[r];
    const vtkIdType first = objects.polys->GetNumberOfCells();
    if (h.plane >= 0) {
      const rayscope::PlaneRecord& pl = accel.plane_records()[size_t(h.plane)];
      const DVec3 p = scene.to_world(pl.point);
      const std::vector<DVec3> poly = rayscope::plane_in_box(p, DVec3(pl.normal), lo, hi);
      if (!poly.empty()) objects.polygon(poly);
      objects.tag(first, int(r), kKindPlane, -1, h.plane,
                  int(scene.plane_object(uint32_t(h.plane))), h.distance);
      continue;
    }
    const uint32_t obj = scene.prim_object(h.prim);
    const uint32_t k = scene.prim_in_object(h.prim);
    int kind = kKindSphere;
    switch (scene.object_type(obj)) {
      case rayscope::ObjectType::Mesh: {
        const rayscope::TriangleMesh& m = scene.meshes[obj];
        const glm::uvec3 t = m.triangles[k];
        objects.polygon({scene.to_world(m.positions[t.x]), scene.to_world(m.positions[t.y]),
                         scene.to_world(m.positions[t.z])});
        kind = kKindTriangle;
        break;
      }
      case rayscope::ObjectType::Tubes: {
        const rayscope::TubeSet& ts = scene.tubes[obj - scene.meshes.size()];
        const glm::uvec2 seg = ts.segments[k];
        objects.polydata(capsule_polys(scene.to_world(ts.positions[seg.x]),
                                       scene.to_world(ts.positions[seg.y]),
                                       double(ts.segment_radius(k)), this->SphereResolution));
        kind = kKindTube;
        break;
      }
      case rayscope::ObjectType::Points: {
        const rayscope::PointSet& ps = scene.points[obj - scene.meshes.size() - scene.tubes.size()];
        objects.polydata(sphere_polys(scene.to_world(ps.positions[k]), double(ps.point_radius(k)),
                                      this->SphereResolution));
        break;
      }
      default: {
        const rayscope::Sphere& sp =
            scene.spheres[obj - scene.meshes.size() - scene.tubes.size() - scene.points.size()];
        objects.polydata(
            sphere_polys(scene.to_world(sp.center), double(sp.radius), this->SphereResolution));
        break;
      }
    }
    objects.tag(first, int(r), kind, int(h.prim), -1, int(obj), h.distance);
  }
  objects.output(found_out);

  vtkFieldData* fd = found_out->GetFieldData();
  vtkNew<vtkStringArray> structure;
  structure->SetName("Structure");
  structure->InsertNextValue(rayscope::to_string(accel.kind()));
  fd->AddArray(structure);
  using rayscope_vtkmodule::add_field_tuple;
  add_field_tuple<vtkIntArray>(fd, "StructureWalked", {accel.walks_structure() ? 1 : 0});
  add_field_tuple<vtkIntArray>(fd, "ObjectsFound", {int(found.size())});
  add_field_tuple<vtkIntArray>(fd, "NodesVisited", {int(cost.nodes)});
  add_field_tuple<vtkIntArray>(fd, "BoxesTested", {int(cost.boxes)});
  add_field_tuple<vtkIntArray>(fd, "NodesCulled", {int(cost.culled)});
  add_field_tuple<vtkIntArray>(fd, "PrimitivesTested", {int(cost.prims)});

  PolyBuilder range;
  if (this->QueryType == QUERY_BOX)
    box_faces(range, lo, hi);
  else if (this->QueryType == QUERY_SPHERE || !found.empty())
    range.polydata(sphere_polys(center, radius, this->SphereResolution));
  range_out->SetPoints(range.points);
  range_out->SetPolys(range.polys);
  return 1;
}

void vtkRayScopeRangeQuery::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "QueryType: " << this->QueryType << "\n";
  os << indent << "Box: " << this->Box[0] << " " << this->Box[1] << " " << this->Box[2] << " "
     << this->Box[3] << " " << this->Box[4] << " " << this->Box[5] << "\n";
  os << indent << "Center: " << this->Center[0] << " " << this->Center[1] << " " << this->Center[2]
     << "\n";
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "NumberOfNeighbors: " << this->NumberOfNeighbors << "\n";
  os << indent << "SphereResolution: " << this->SphereResolution << "\n";
}
