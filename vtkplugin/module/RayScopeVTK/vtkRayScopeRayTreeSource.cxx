#include "vtkRayScopeRayTreeSource.h"

#include <cmath>
#include <exception>
#include <string>
#include <vector>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"

#include "RayScopeArrays.h"
#include "rayscope/render.h"
#include "rayscope/replay.h"
#include "rayscope/scene.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeSceneSettings.h"

vtkStandardNewMacro(vtkRayScopeRayTreeSource);

struct vtkRayScopeRayTreeSource::Internals {
  std::vector<std::pair<int, int>> pixels;
};

vtkRayScopeRayTreeSource::vtkRayScopeRayTreeSource()
    : Sample(-1), MissLength(0.0), Internal(new Internals) {}

vtkRayScopeRayTreeSource::~vtkRayScopeRayTreeSource() {
  delete this->Internal;
}

void vtkRayScopeRayTreeSource::SetPixel(int i, int j) {
  auto& p = this->Internal->pixels;
  if (p.size() == 1 && p[0] == std::make_pair(i, j)) return;
  p.assign(1, {i, j});
  this->Modified();
}

void vtkRayScopeRayTreeSource::AddPixel(int i, int j) {
  this->Internal->pixels.emplace_back(i, j);
  this->Modified();
}

void vtkRayScopeRayTreeSource::RemoveAllPixels() {
  if (this->Internal->pixels.empty()) return;
  this->Internal->pixels.clear();
  this->Modified();
}

int vtkRayScopeRayTreeSource::GetNumberOfPixels() {
  return int(this->Internal->pixels.size());
}

namespace {

/// GetKindColor's table, in rayscope::RayKind order: yellow, blue, green,
/// magenta.
constexpr double kKindColors[rayscope::kRayKindCount][3] = {
    {0.95, 0.7, 0.0}, {0.3, 0.55, 1.0}, {0.1, 0.8, 0.3}, {0.9, 0.25, 0.85}};

}  // namespace

void vtkRayScopeRayTreeSource::GetKindColor(int kind, double rgb[3]) {
  for (int c = 0; c < 3; ++c)
    rgb[c] = kind >= 0 && kind < rayscope::kRayKindCount ? kKindColors[kind][c] : 0.0;
}

namespace {

enum EndKind { kMiss = 0, kHit = 1, kLight = 2, kOccluder = 3, kSkipped = 4 };

/// A skipped reflection or refraction ray is drawn as a stub this fraction of
/// a miss's length: where it would have gone, not where it would have ended.
constexpr float kSkippedStubFraction = 0.15f;

struct Row {
  int pixel;
  const rayscope::RayRecord* ray;
  rayscope::Vec3 end;
  float t;
  int end_kind;
  int end_object;  // object at the end point, -1 for none
};

using rayscope_vtkmodule::make_array;
using rayscope_vtkmodule::make_world_points;
using rayscope_vtkmodule::set_world_point;

}  // namespace

int vtkRayScopeRayTreeSource::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                          vtkInformationVector* outputVector) {
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  const auto& pixels = this->Internal->pixels;
  if (pixels.empty()) {
    vtkErrorMacro(<< "no pixel to record: call SetPixel(i, j) or AddPixel(i, j)");
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
  const int n2 = settings.sample_grid() * settings.sample_grid();
  if (this->Sample < -1 || this->Sample >= n2) {
    vtkErrorMacro(<< "Sample " << this->Sample << " is outside -1.." << n2 - 1 << " ("
                  << settings.sample_grid() << "x" << settings.sample_grid()
                  << " samples per pixel)");
    return 0;
  }
  for (auto [i, j] : pixels)
    if (i < 0 || j < 0 || i >= settings.width || j >= settings.height) {
      vtkErrorMacro(<< "pixel (" << i << ", " << j << ") is outside the " << settings.width << "x"
                    << settings.height << " image");
      return 0;
    }

  // Rays that end nowhere are drawn to just past the scene's bounds.
  rayscope::Bounds3 bounds = scene.bounds();
  if (bounds.empty()) bounds = rayscope::Bounds3(scene.camera.eye);
  const rayscope::Vec3 center = bounds.center();
  const float radius = 0.5f * glm::length(bounds.extent());
  auto far_t = [&](const rayscope::RayRecord& r) {
    const float len = glm::length(r.dir);
    const float world = this->MissLength > 0.0
                            ? float(this->MissLength)
                            : 1.1f * (glm::length(r.origin - center) + radius) + 1e-3f;
    return len > 0.0f ? world / len : 0.0f;
  };

  std::vector<rayscope::PixelRecord> records;
  records.reserve(pixels.size());
  std::vector<Row> rows;
  for (size_t p = 0; p < pixels.size(); ++p) {
    const int x = pixels[p].first, y = settings.height - 1 - pixels[p].second;
    try {
      records.push_back(rayscope::record_pixel(scene, settings, x, y, this->Sample));
    } catch (const std::exception& e) {
      vtkErrorMacro(<< "recording pixel failed: " << e.what());
      return 0;
    }
    this->UpdateProgress(0.9 * double(p + 1) / double(pixels.size()));
  }
  for (size_t p = 0; p < records.size(); ++p)
    for (const rayscope::RayRecord& r : records[p].rays) {
      Row row{int(p), &r, r.origin, 0.0f, kMiss, -1};
      if (r.kind != rayscope::RayKind::Shadow) {
        if (r.skipped) {
          row.t = kSkippedStubFraction * far_t(r);
          row.end_kind = kSkipped;
        } else if (r.hit) {
          row.end = r.point;
          row.t = r.t;
          row.end_kind = kHit;
          row.end_object = int(r.object);
        } else {
          row.t = far_t(r);
        }
      } else if (r.occluded) {
        // The core records which object occluded the ray, not where: the
        // nearest surface along the shadow ray is found again here.
        rayscope::SurfaceHit h;
        rayscope::Ray ray{r.origin, r.dir, r.tmax};
        if (scene.intersect(ray, h)) {
          row.end = h.p;
          row.t = h.t;
          row.end_kind = kOccluder;
          row.end_object = int(h.object);
        } else {
          row.t = std::isfinite(r.tmax) ? r.tmax : far_t(r);
          row.end_kind = kLight;
        }
      } else {
        row.t = std::isfinite(r.tmax) ? r.tmax : far_t(r);
        row.end_kind = kLight;
      }
      if (row.end_kind != kHit && row.end_kind != kOccluder) row.end = r.origin + row.t * r.dir;
      rows.push_back(row);
    }

  const vtkIdType nrays = vtkIdType(rows.size());
  vtkSmartPointer<vtkPoints> points = make_world_points(scene, 2 * nrays);
  auto normals = make_array<vtkFloatArray>("Normals", 3, 2 * nrays);
  auto gnormals = make_array<vtkFloatArray>("GeometricNormals", 3, 2 * nrays);
  normals->Fill(0.0);
  gnormals->Fill(0.0);
  vtkNew<vtkCellArray> lines, verts;
  std::vector<vtkIdType> hit_rows;
  for (vtkIdType k = 0; k < nrays; ++k) {
    const Row& row = rows[size_t(k)];
    const rayscope::RayRecord& r = *row.ray;
    set_world_point(points, 2 * k, scene, r.origin);
    set_world_point(points, 2 * k + 1, scene, row.end);
    vtkIdType line[2] = {2 * k, 2 * k + 1};
    lines->InsertNextCell(2, line);
    if (row.end_kind == kHit) {
      for (int c = 0; c < 3; ++c) {
        normals->SetTypedComponent(2 * k + 1, c, r.ns[c]);
        gnormals->SetTypedComponent(2 * k + 1, c, r.ng[c]);
      }
      vtkIdType v = 2 * k + 1;
      verts->InsertNextCell(1, &v);
      hit_rows.push_back(k);
    }
  }

  // Cell data: vertex cells first (as vtkPolyData numbers them), then lines.
  const vtkIdType ncells = vtkIdType(hit_rows.size()) + nrays;
  auto ray_id = make_array<vtkIntArray>("RayId", 1, ncells);
  auto parent = make_array<vtkIntArray>("ParentId", 1, ncells);
  auto pixel = make_array<vtkIntArray>("Pixel", 2, ncells);
  auto pixel_index = make_array<vtkIntArray>("PixelIndex", 1, ncells);
  auto sample = make_array<vtkIntArray>("Sample", 1, ncells);
  auto kind = make_array<vtkIntArray>("Kind", 1, ncells);
  auto kind_name = make_array<vtkStringArray>("KindName", 1, ncells);
  auto depth = make_array<vtkIntArray>("Depth", 1, ncells);
  auto hit = make_array<vtkUnsignedCharArray>("Hit", 1, ncells);
  auto occluded = make_array<vtkUnsignedCharArray>("Occluded", 1, ncells);
  auto object = make_array<vtkIntArray>("ObjectId", 1, ncells);
  auto light = make_array<vtkIntArray>("LightId", 1, ncells);
  auto tarr = make_array<vtkFloatArray>("T", 1, ncells);
  auto end_kind = make_array<vtkIntArray>("EndKind", 1, ncells);
  auto end_object = make_array<vtkIntArray>("EndObjectId", 1, ncells);
  auto weight = make_array<vtkFloatArray>("Weight", 3, ncells);
  auto color = make_array<vtkFloatArray>("Color", 3, ncells);
  auto nodes = make_array<vtkIntArray>("NodesVisited", 1, ncells);
  auto boxes = make_array<vtkIntArray>("BoxesTested", 1, ncells);
  auto prims = make_array<vtkIntArray>("PrimitivesTested", 1, ncells);
  auto culled = make_array<vtkIntArray>("NodesCulled", 1, ncells);
  auto is_hit_point = make_array<vtkUnsignedCharArray>("IsHitPoint", 1, ncells);
  auto skipped = make_array<vtkIntArray>("Skipped", 1, ncells);
  auto kind_color = make_array<vtkUnsignedCharArray>("KindColor", 3, ncells);
  auto fill = [&](vtkIdType cell, vtkIdType k, bool vertex) {
    const Row& row = rows[size_t(k)];
    const rayscope::RayRecord& r = *row.ray;
    const bool shadow = r.kind == rayscope::RayKind::Shadow;
    ray_id->SetValue(cell, r.id);
    parent->SetValue(cell, r.parent);
    pixel->SetTypedComponent(cell, 0, pixels[size_t(row.pixel)].first);
    pixel->SetTypedComponent(cell, 1, pixels[size_t(row.pixel)].second);
    pixel_index->SetValue(cell, row.pixel);
    sample->SetValue(cell, r.sample);
    kind->SetValue(cell, int(r.kind));
    kind_name->SetValue(cell, rayscope::to_string(r.kind));
    double rgb[3];
    GetKindColor(int(r.kind), rgb);
    for (int c = 0; c < 3; ++c)
      kind_color->SetTypedComponent(cell, c,
                                    static_cast<unsigned char>(std::lround(255.0 * rgb[c])));
    depth->SetValue(cell, r.depth);
    hit->SetValue(cell, shadow ? r.occluded : r.hit);
    occluded->SetValue(cell, r.occluded);
    const uint32_t obj = shadow ? (r.occluded ? r.occluder : ~0u) : (r.hit ? r.object : ~0u);
    object->SetValue(cell, obj == ~0u ? -1 : int(obj));
    light->SetValue(cell, r.light);
    tarr->SetValue(cell, row.t);
    end_kind->SetValue(cell, row.end_kind);
    end_object->SetValue(cell, row.end_object);
    for (int c = 0; c < 3; ++c) {
      weight->SetTypedComponent(cell, c, r.weight[c]);
      color->SetTypedComponent(cell, c, r.color[c]);
    }
    nodes->SetValue(cell, int(r.traversal.nodes().size()));
    boxes->SetValue(cell, int(r.traversal.boxes_tested()));
    prims->SetValue(cell, int(r.traversal.prims_tested));
    culled->SetValue(cell, int(r.traversal.culled()));
    is_hit_point->SetValue(cell, vertex ? 1 : 0);
    skipped->SetValue(cell, r.skipped ? 1 + int(r.skip_reason) : 0);
  };
  vtkIdType cell = 0;
  for (vtkIdType k : hit_rows) fill(cell++, k, true);
  for (vtkIdType k = 0; k < nrays; ++k) fill(cell++, k, false);

  output->Initialize();
  output->SetPoints(points);
  output->SetVerts(verts);
  output->SetLines(lines);
  output->GetPointData()->SetNormals(normals);
  output->GetPointData()->AddArray(gnormals);
  vtkCellData* cd = output->GetCellData();
  for (vtkAbstractArray* a : std::initializer_list<vtkAbstractArray*>{
           ray_id, parent,   pixel,  pixel_index, sample, kind,         kind_name,  depth,
           hit,    occluded, object, light,       tarr,   end_kind,     end_object, weight,
           color,  nodes,    boxes,  prims,       culled, is_hit_point, skipped,    kind_color})
    cd->AddArray(a);
  cd->SetActiveScalars("Kind");
  auto pixel_color = make_array<vtkFloatArray>("PixelColor", 3, vtkIdType(records.size()));
  for (size_t p = 0; p < records.size(); ++p)
    for (int c = 0; c < 3; ++c)
      pixel_color->SetTypedComponent(vtkIdType(p), c, records[p].color[c]);
  output->GetFieldData()->AddArray(pixel_color);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkRayScopeRayTreeSource::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Pixels:";
  for (auto [i, j] : this->Internal->pixels) os << " (" << i << ", " << j << ")";
  os << "\n";
  os << indent << "Sample: " << this->Sample << "\n";
  os << indent << "MissLength: " << this->MissLength << "\n";
}
