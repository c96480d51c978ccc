#include "rayscope_vtkio/mesh_conversion.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataSet.h>
#include <vtkDataSetMapper.h>
#include <vtkDataSetSurfaceFilter.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPointSet.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>
#include <vtkScalarsToColors.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>

#include "rayscope/image.h"
#include "rayscope/scene.h"
#include "rayscope_vtkio/mesh_checks.h"

namespace rayscope_vtkio {
namespace {

bool finite_point(vtkPolyData* pd, vtkIdType id) {
  double p[3];
  pd->GetPoint(id, p);
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// Whether the triangles of `tri` are already ordered consistently: no
// triangle names a point twice, and no directed edge (a to b) belongs to two
// triangles, so that every edge two triangles share is walked in opposite
// directions by them. vtkPolyDataNormals' consistency pass reverses a
// triangle that walks a shared edge in its neighbour's direction, so on such
// a mesh it changes nothing: it is skipped, which made the filter 40% faster
// on the bunny. Anything else (other cells, non-manifold or flipped
// neighbours) keeps the pass.
bool consistently_ordered(vtkPolyData* tri) {
  const vtkIdType points = tri->GetNumberOfPoints();
  vtkCellArray* polys = tri->GetPolys();
  const vtkIdType cells = polys->GetNumberOfCells();
  // The directed edges by their first point (compressed rows): counts first.
  std::vector<vtkIdType> first(size_t(points) + 1, 0);
  vtkIdType n = 0;
  const vtkIdType* p = nullptr;
  for (vtkIdType c = 0; c < cells; ++c) {
    polys->GetCellAtId(c, n, p);
    if (n != 3 || p[0] == p[1] || p[1] == p[2] || p[2] == p[0]) return false;
    for (int k = 0; k < 3; ++k) ++first[size_t(p[k]) + 1];
  }
  for (size_t i = 1; i < first.size(); ++i) first[i] += first[i - 1];
  std::vector<vtkIdType> to(size_t(first.back()));
  std::vector<vtkIdType> fill(first.begin(), first.end() - 1);
  for (vtkIdType c = 0; c < cells; ++c) {
    polys->GetCellAtId(c, n, p);
    for (int k = 0; k < 3; ++k) to[size_t(fill[size_t(p[k])]++)] = p[(k + 1) % 3];
  }
  for (vtkIdType a = 0; a < points; ++a) {
    const auto begin = to.begin() + first[size_t(a)], end = to.begin() + first[size_t(a) + 1];
    std::sort(begin, end);
    if (std::adjacent_find(begin, end) != end) return false;
  }
  return true;
}

vtkSmartPointer<vtkPolyData> compute_normals(vtkPolyData* tri, const SurfaceOptions& o) {
  vtkNew<vtkPolyDataNormals> pn;
  pn->SetInputData(tri);
  pn->SetConsistency(!consistently_ordered(tri));
  pn->SetSplitting(o.splitting);
  pn->SetFeatureAngle(o.feature_angle);
  pn->ComputePointNormalsOn();
  pn->ComputeCellNormalsOff();
  pn->AutoOrientNormalsOff();
  pn->Update();
  return pn->GetOutput();
}

// Point normals of the triangles whose corners are all finite: vtkPolyDataNormals
// averages the triangles around a point, so one non-finite corner would make
// the normals of all its neighbours NaN. The other triangles (the tracer skips
// them, with a warning) are appended afterwards with their cell data.
vtkSmartPointer<vtkPolyData> normals_of_finite_triangles(vtkPolyData* tri,
                                                         const SurfaceOptions& o) {
  std::vector<vtkIdType> bad;
  vtkNew<vtkCellArray> good_polys;
  vtkNew<vtkIdList> ids;
  vtkCellArray* polys = tri->GetPolys();
  vtkIdType cell = 0;
  std::vector<vtkIdType> good;
  for (polys->InitTraversal(); polys->GetNextCell(ids); ++cell) {
    bool finite = true;
    for (vtkIdType k = 0; k < ids->GetNumberOfIds() && finite; ++k)
      finite = finite_point(tri, ids->GetId(k));
    if (finite) {
      good_polys->InsertNextCell(ids);
      good.push_back(cell);
    } else {
      bad.push_back(cell);
    }
  }
  if (bad.empty()) return compute_normals(tri, o);

  vtkNew<vtkPolyData> finite;
  finite->SetPoints(tri->GetPoints());
  finite->GetPointData()->PassData(tri->GetPointData());
  finite->SetPolys(good_polys);
  vtkCellData* cd = finite->GetCellData();
  cd->CopyAllocate(tri->GetCellData(), vtkIdType(good.size()));
  for (size_t k = 0; k < good.size(); ++k) cd->CopyData(tri->GetCellData(), good[k], vtkIdType(k));
  vtkSmartPointer<vtkPolyData> out = compute_normals(finite, o);
  // vtkPolyDataNormals keeps every input point at its index (split copies are
  // appended), so the skipped triangles keep their corners.
  vtkCellArray* out_polys = out->GetPolys();
  vtkCellData* out_cd = out->GetCellData();
  for (vtkIdType c : bad) {
    tri->GetCellPoints(c, ids);
    const vtkIdType id = out_polys->InsertNextCell(ids);
    out_cd->CopyData(tri->GetCellData(), c, id);
  }
  return out;
}

// The point normals of `pd` if they can be used: three components, one per
// point. A reader can leave another array there: an OBJ file with fewer `vn`
// lines than points gave a shorter one (found by fuzz_mesh_loader).
vtkDataArray* usable_normals(vtkPolyData* pd) {
  vtkDataArray* n = pd->GetPointData()->GetNormals();
  return n && n->GetNumberOfComponents() == 3 && n->GetNumberOfTuples() == pd->GetNumberOfPoints()
             ? n
             : nullptr;
}

// `tri` (triangles only, from vtkTriangleFilter) without the points no
// triangle uses, when those are most of them: the normals, the colors and the
// copy below then cost time and memory in proportion to the triangles, not to
// the points (a 117-byte legacy file declaring 1e8 points and one cell cost
// 144 s and 8.3 GB). Below kUnusedPointsFactor points per triangle corner,
// the unused points cost at most that factor times the triangles' work and
// the data is returned as it is (so that the usual mesh, every point used,
// pays nothing). Point data follows its points; cell data is unchanged.
constexpr vtkIdType kUnusedPointsFactor = 2;
vtkSmartPointer<vtkPolyData> without_unused_points(vtkPolyData* tri) {
  vtkCellArray* polys = tri->GetPolys();
  const vtkIdType corners = polys->GetNumberOfConnectivityIds();
  if (tri->GetNumberOfPoints() <= kUnusedPointsFactor * corners) return tri;
  std::vector<vtkIdType> used;
  used.reserve(size_t(corners));
  vtkNew<vtkIdList> ids;
  for (polys->InitTraversal(); polys->GetNextCell(ids);)
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) used.push_back(ids->GetId(k));
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  const vtkIdType n = vtkIdType(used.size());
  auto out = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataType(tri->GetPoints()->GetDataType());
  points->SetNumberOfPoints(n);
  vtkPointData* in_pd = tri->GetPointData();
  vtkPointData* out_pd = out->GetPointData();
  out_pd->CopyAllocate(in_pd, n);
  for (vtkIdType i = 0; i < n; ++i) {
    points->SetPoint(i, tri->GetPoint(used[size_t(i)]));
    out_pd->CopyData(in_pd, used[size_t(i)], i);
  }
  vtkNew<vtkCellArray> remapped;
  remapped->AllocateEstimate(polys->GetNumberOfCells(), 3);
  for (polys->InitTraversal(); polys->GetNextCell(ids);) {
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      ids->SetId(
          k, vtkIdType(std::lower_bound(used.begin(), used.end(), ids->GetId(k)) - used.begin()));
    remapped->InsertNextCell(ids);
  }
  out->SetPoints(points);
  out->SetPolys(remapped);
  out->GetCellData()->ShallowCopy(tri->GetCellData());
  out->GetFieldData()->ShallowCopy(tri->GetFieldData());
  return out;
}

// The surface the mapper would draw: triangles only, with point normals.
vtkSmartPointer<vtkPolyData> triangulate(vtkDataSet* input, const SurfaceOptions& o) {
  vtkSmartPointer<vtkPolyData> surface = vtkPolyData::SafeDownCast(input);
  if (!surface) {
    vtkNew<vtkDataSetSurfaceFilter> sf;
    sf->SetInputData(input);
    sf->SetNonlinearSubdivisionLevel(o.nonlinear_subdivision_level);
    sf->Update();
    surface = sf->GetOutput();
  }
  vtkNew<vtkTriangleFilter> tf;
  tf->SetInputData(surface);
  tf->PassVertsOff();
  tf->PassLinesOff();
  tf->Update();
  vtkSmartPointer<vtkPolyData> tri = without_unused_points(tf->GetOutput());
  if (o.compute_normals && !usable_normals(tri) && tri->GetNumberOfPolys() > 0)
    tri = normals_of_finite_triangles(tri, o);
  return tri;
}

}  // namespace

vtkSmartPointer<vtkUnsignedCharArray> map_colors(vtkMapper* coloring, vtkPolyData* data,
                                                 int& cell_flag) {
  cell_flag = 0;
  if (!coloring) return nullptr;
  vtkNew<vtkDataSetMapper> mapper;
  mapper->ShallowCopy(coloring);
  // A mapper that sets its table's range (UseLookupTableScalarRange off) maps
  // through a copy, so that the caller's table keeps its range. One that uses
  // the table's own range (ParaView's, always) maps through the table itself,
  // as its OpenGL render does: a copy can lose what the table builds from
  // settings DeepCopy() does not carry (ParaView's categorical colors).
  vtkScalarsToColors* lut = coloring->GetLookupTable();
  if (lut && !coloring->GetUseLookupTableScalarRange()) {
    vtkSmartPointer<vtkScalarsToColors> copy = vtk::TakeSmartPointer(lut->NewInstance());
    copy->DeepCopy(lut);
    mapper->SetLookupTable(copy);
  }
  mapper->SetInterpolateScalarsBeforeMapping(0);
  mapper->SetInputData(data);
  return mapper->MapScalars(data, 1.0, cell_flag);
}

ColorSource convert_dataset(vtkDataSet* input, const SurfaceOptions& options, vtkMapper* coloring,
                            vtkPolyData* output) {
  // Before any VTK filter indexes the points with the cells' ids.
  if (std::string e = check_cell_point_ids(input); !e.empty()) throw std::invalid_argument(e);
  vtkSmartPointer<vtkPolyData> tri = triangulate(input, options);

  // Colors by the mapper's own code, on the very surface it would draw.
  // The copy maps with a private copy of the lookup table: the mapper sets the
  // table's range, which must not modify the caller's table on every
  // conversion.
  int cell_flag = 0;
  vtkSmartPointer<vtkUnsignedCharArray> mapped = map_colors(coloring, tri, cell_flag);

  const vtkIdType ntri = tri->GetNumberOfPolys();
  const vtkIdType npts = tri->GetNumberOfPoints();
  // One RGBA color per triangle (cell colors) or per point, or none.
  ColorSource source_of_colors = ColorSource::None;
  vtkSmartPointer<vtkUnsignedCharArray> cell_colors, point_colors;
  if (mapped && mapped->GetNumberOfComponents() == 4) {
    const vtkIdType field_tuple = coloring->GetFieldDataTupleId();
    if (cell_flag == 0 && mapped->GetNumberOfTuples() == npts) {
      point_colors = mapped;
      source_of_colors = ColorSource::Point;
    } else if (cell_flag == 1 && mapped->GetNumberOfTuples() == ntri) {
      cell_colors = mapped;
      source_of_colors = ColorSource::Cell;
    } else if (cell_flag == 2 && field_tuple >= 0 && field_tuple < mapped->GetNumberOfTuples()) {
      point_colors = vtkSmartPointer<vtkUnsignedCharArray>::New();
      point_colors->SetNumberOfComponents(4);
      point_colors->SetNumberOfTuples(npts);
      for (vtkIdType i = 0; i < npts; ++i)
        for (int k = 0; k < 4; ++k)
          point_colors->SetTypedComponent(i, k, mapped->GetTypedComponent(field_tuple, k));
      source_of_colors = ColorSource::Field;
    } else if (cell_flag == 2 && field_tuple < 0 && mapped->GetNumberOfTuples() >= ntri) {
      cell_colors = mapped;  // one field tuple per cell, as VTK draws it
      source_of_colors = ColorSource::Field;
    }
  }

  vtkDataArray* in_normals = usable_normals(tri);

  // With cell colors, each (point, color) pair becomes one output point, so a
  // point shared by cells of different colors is duplicated once per color.
  std::vector<vtkIdType> source;    // output point -> input point
  std::vector<vtkIdType> color_of;  // output point -> color tuple (or -1)
  vtkNew<vtkCellArray> polys;
  polys->AllocateEstimate(ntri, 3);
  vtkNew<vtkIdList> ids;
  vtkCellArray* in_polys = tri->GetPolys();
  if (cell_colors) {
    std::unordered_map<uint64_t, vtkIdType> index;
    index.reserve(size_t(npts));
    vtkIdType cell = 0;
    for (in_polys->InitTraversal(); in_polys->GetNextCell(ids); ++cell) {
      if (ids->GetNumberOfIds() != 3) continue;
      uint32_t rgb = 0;
      for (int k = 0; k < 3; ++k) rgb = (rgb << 8) | cell_colors->GetTypedComponent(cell, k);
      vtkIdType out[3];
      for (int v = 0; v < 3; ++v) {
        vtkIdType p = ids->GetId(v);
        uint64_t key = (uint64_t(p) << 24) | rgb;
        auto [it, inserted] = index.emplace(key, vtkIdType(source.size()));
        if (inserted) {
          source.push_back(p);
          color_of.push_back(cell);
        }
        out[v] = it->second;
      }
      polys->InsertNextCell(3, out);
    }
  } else {
    source.resize(size_t(npts));
    for (vtkIdType i = 0; i < npts; ++i) source[size_t(i)] = i;
    if (point_colors) color_of = source;
    for (in_polys->InitTraversal(); in_polys->GetNextCell(ids);)
      if (ids->GetNumberOfIds() == 3) polys->InsertNextCell(ids);
  }

  const vtkIdType nout = vtkIdType(source.size());
  // Points keep the input's precision: double stays double until the points
  // are made scene-local (mesh_from_converted), so that data far from the
  // origin keeps its detail.
  vtkNew<vtkPoints> points;
  points->SetDataType(
      tri->GetPoints() && tri->GetPoints()->GetDataType() == VTK_DOUBLE ? VTK_DOUBLE : VTK_FLOAT);
  points->SetNumberOfPoints(nout);
  for (vtkIdType i = 0; i < nout; ++i) points->SetPoint(i, tri->GetPoint(source[size_t(i)]));

  output->Initialize();
  output->SetPoints(points);
  output->SetPolys(polys);
  if (in_normals) {
    vtkNew<vtkFloatArray> normals;
    normals->SetName("Normals");
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(nout);
    for (vtkIdType i = 0; i < nout; ++i)
      normals->SetTuple(i, in_normals->GetTuple(source[size_t(i)]));
    output->GetPointData()->SetNormals(normals);
  }
  vtkUnsignedCharArray* colors_in = cell_colors ? cell_colors.Get() : point_colors.Get();
  if (colors_in) {
    const auto& table = rayscope::srgb_byte_table();
    vtkNew<vtkUnsignedCharArray> colors;
    colors->SetName("Colors");
    colors->SetNumberOfComponents(4);
    colors->SetNumberOfTuples(nout);
    vtkNew<vtkFloatArray> linear;
    linear->SetName("LinearColors");
    linear->SetNumberOfComponents(3);
    linear->SetNumberOfTuples(nout);
    for (vtkIdType i = 0; i < nout; ++i) {
      const vtkIdType c = color_of[size_t(i)];
      for (int k = 0; k < 4; ++k) {
        unsigned char b = colors_in->GetTypedComponent(c, k);
        colors->SetTypedComponent(i, k, b);
        if (k < 3) linear->SetTypedComponent(i, k, table[b]);
      }
    }
    output->GetPointData()->SetScalars(colors);
    output->GetPointData()->AddArray(linear);
  }
  return source_of_colors;
}

bool finite_bounds(const std::vector<vtkDataSet*>& data, double bounds[6]) {
  bool any = false;
  for (vtkDataSet* d : data) {
    if (!d || d->GetNumberOfPoints() == 0) continue;
    double b[6];
    d->GetBounds(b);
    if (!std::all_of(b, b + 6, [](double v) { return std::isfinite(v); })) {
      auto* ps = vtkPointSet::SafeDownCast(d);
      if (!ps || !ps->GetPoints()) continue;  // implicit points are finite
      for (int k = 0; k < 3; ++k) ps->GetPoints()->GetData()->GetFiniteRange(b + 2 * k, k);
      if (!(b[0] <= b[1] && b[2] <= b[3] && b[4] <= b[5])) continue;  // no finite point
    }
    for (int k = 0; k < 6; ++k)
      bounds[k] = !any ? b[k] : k % 2 == 0 ? std::min(bounds[k], b[k]) : std::max(bounds[k], b[k]);
    any = true;
  }
  return any;
}

glm::dvec3 local_origin(const std::vector<vtkDataSet*>& data) {
  double b[6];
  if (!finite_bounds(data, b)) return glm::dvec3(0.0);
  const glm::dvec3 lo(b[0], b[2], b[4]), hi(b[1], b[3], b[5]);
  return rayscope::choose_local_origin(0.5 * (lo + hi), glm::length(hi - lo));
}

void mesh_from_converted(vtkPolyData* pd, rayscope::TriangleMesh& m, const glm::dmat4& to_scene) {
  m.positions.clear();
  m.triangles.clear();
  m.normals.clear();
  m.colors.clear();
  if (!pd) return;
  const vtkIdType np = pd->GetNumberOfPoints();
  m.positions.resize(size_t(np));
  const bool identity = to_scene == glm::dmat4(1.0);
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    pd->GetPoint(i, p);
    const glm::dvec3 q = identity ? glm::dvec3(p[0], p[1], p[2])
                                  : glm::dvec3(to_scene * glm::dvec4(p[0], p[1], p[2], 1.0));
    m.positions[size_t(i)] = rayscope::Vec3(q);
  }
  vtkCellArray* polys = pd->GetPolys();
  m.triangles.reserve(size_t(polys->GetNumberOfCells()));
  vtkNew<vtkIdList> ids;
  for (polys->InitTraversal(); polys->GetNextCell(ids);)
    if (ids->GetNumberOfIds() == 3)
      m.triangles.emplace_back(uint32_t(ids->GetId(0)), uint32_t(ids->GetId(1)),
                               uint32_t(ids->GetId(2)));
  // Color and Vec3 are both 3-vectors of floats.
  auto vectors = [&](vtkDataArray* a, std::vector<rayscope::Vec3>& out) {
    if (!a || a->GetNumberOfComponents() != 3 || a->GetNumberOfTuples() != np) return;
    out.resize(size_t(np));
    for (vtkIdType i = 0; i < np; ++i) {
      double v[3];
      a->GetTuple(i, v);
      out[size_t(i)] = rayscope::Vec3(float(v[0]), float(v[1]), float(v[2]));
    }
  };
  vectors(pd->GetPointData()->GetNormals(), m.normals);
  if (!identity) {
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(to_scene)));
    for (rayscope::Vec3& n : m.normals) {
      const glm::dvec3 t = normal_matrix * glm::dvec3(n);
      const double len = glm::length(t);
      n = rayscope::Vec3(len > 0.0 ? t / len : t);
    }
  }
  vectors(pd->GetPointData()->GetArray("LinearColors"), m.colors);
}

}  // namespace rayscope_vtkio
