// vtkRayScopeAccelSource: leaf boxes contain their triangles (and every triangle
// is in exactly one leaf), levels, SAH terms and visit counts, for every
// structure (the sphere tree's nodes drawn as spheres).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>
#include <vector>

#include <vtkCell.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>
#include <vtkSuperquadricSource.h>

#include "rayscope/scene.h"
#include "vtkRayScopeAccelSource.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeMaterial.h"
#include "vtkRayScopeMeshConverter.h"
#include "vtkRayScopeRayTreeSource.h"
#include "vtk_test_util.h"

namespace {

struct Box {
  double lo[3], hi[3];
  int node, offset, count;
};

// One box per node: its 8 corners are points 8b .. 8b+7 of the output, and
// every cell of the box carries the node's data.
std::vector<Box> boxes_of(vtkPolyData* pd, int cells_per_box) {
  std::vector<Box> out;
  vtkCellData* cd = pd->GetCellData();
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); c += cells_per_box) {
    Box b;
    const vtkIdType first = (c / cells_per_box) * 8;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = pd->GetPoint(first)[k];
      b.hi[k] = pd->GetPoint(first + 7)[k];
    }
    b.node = int(cd->GetArray("NodeId")->GetTuple1(c));
    b.offset = int(cd->GetArray("PrimitiveOffset")->GetTuple1(c));
    b.count = int(cd->GetArray("PrimitiveCount")->GetTuple1(c));
    out.push_back(b);
  }
  return out;
}

struct Scene3 {
  vtkNew<vtkSuperquadricSource> quad;
  vtkNew<vtkSphereSource> sphere;
  vtkNew<vtkPlaneSource> floor;
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  Scene3() {
    quad->SetThetaResolution(48);
    quad->SetPhiResolution(48);
    quad->SetThetaRoundness(0.3);
    quad->SetPhiRoundness(1.5);
    quad->ToroidalOn();
    quad->SetCenter(-0.6, 0.2, 0);
    quad->SetScale(0.6, 0.6, 0.6);
    configure_sphere(sphere, 0.8, 0.1, -0.3, 0.5, 40);
    configure_floor(floor, -0.6, 2.5);
    floor->SetResolution(6, 6);
    alg->AddInputConnection(quad->GetOutputPort());
    alg->AddInputConnection(sphere->GetOutputPort());
    alg->AddInputConnection(floor->GetOutputPort());
    vtkNew<vtkRayScopeMaterial> mirror;
    mirror->SetReflectivity(0.5);
    alg->SetInputMaterial(1, mirror);
    alg->AddPointLight(1, 3, 2, 1, 1, 1, 1);
    alg->SetPosition(0, 1.2, 4);
    alg->SetSize(48, 36);
  }
};

}  // namespace

// Every triangle lies in the box of the leaf that holds it (exactly: the boxes
// are the float bounds of the very float vertices), and every triangle is in
// exactly one leaf.
TEST(VtkBVH, LeafBoxesContainAllTriangles) {
  Scene3 s;
  vtkNew<vtkRayScopeAccelSource> bvh;
  bvh->SetSceneSource(s.alg);
  bvh->OnlyLeavesOn();
  bvh->Update();
  vtkPolyData* pd = bvh->GetOutput();
  ASSERT_GT(pd->GetNumberOfCells(), 0);
  EXPECT_EQ(pd->GetNumberOfLines(), pd->GetNumberOfCells());
  EXPECT_EQ(pd->GetNumberOfCells() % 12, 0);

  // The triangles, converted independently from the same inputs, numbered
  // input by input.
  std::vector<std::array<double, 9>> tris;
  vtkNew<vtkRayScopeMeshConverter> conv;
  vtkNew<vtkIdList> ids;
  for (vtkAlgorithm* a : std::initializer_list<vtkAlgorithm*>{s.quad, s.sphere, s.floor}) {
    a->Update();
    vtkNew<vtkPolyData> t;
    ASSERT_EQ(conv->Convert(vtkDataSet::SafeDownCast(a->GetOutputDataObject(0)), t), 1);
    for (t->GetPolys()->InitTraversal(); t->GetPolys()->GetNextCell(ids);) {
      std::array<double, 9> tri;
      for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 3; ++k) tri[size_t(3 * v + k)] = t->GetPoint(ids->GetId(v))[k];
      tris.push_back(tri);
    }
  }
  vtkDataArray* leaf_ids = pd->GetFieldData()->GetArray("LeafPrimitiveIds");
  ASSERT_NE(leaf_ids, nullptr);
  ASSERT_EQ(leaf_ids->GetNumberOfTuples(), vtkIdType(tris.size()));

  std::vector<int> seen(tris.size(), 0);
  const std::vector<Box> boxes = boxes_of(pd, 12);
  for (const Box& b : boxes) {
    ASSERT_GE(b.offset, 0);
    ASSERT_GT(b.count, 0);
    for (int slot = b.offset; slot < b.offset + b.count; ++slot) {
      const int prim = int(leaf_ids->GetTuple1(slot));
      ASSERT_GE(prim, 0);
      ASSERT_LT(prim, int(tris.size()));
      seen[size_t(prim)]++;
      for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 3; ++k) {
          const double x = tris[size_t(prim)][size_t(3 * v + k)];
          EXPECT_GE(x, b.lo[k]) << "triangle " << prim << " leaf " << b.node;
          EXPECT_LE(x, b.hi[k]) << "triangle " << prim << " leaf " << b.node;
        }
    }
  }
  for (size_t p = 0; p < seen.size(); ++p) ASSERT_EQ(seen[p], 1) << "triangle " << p;
}

// Levels, subtree counts, SAH terms summing to the hierarchy's SAH cost,
// quads for faces.
TEST(VtkBVH, LevelsCountsAndSAH) {
  Scene3 s;
  vtkNew<vtkRayScopeAccelSource> bvh;
  bvh->SetSceneSource(s.alg);
  bvh->Update();
  vtkPolyData* all = bvh->GetOutput();
  const rayscope::Scene* scene = s.alg->GetCoreScene();
  ASSERT_NE(scene, nullptr);
  const size_t nodes = scene->bvh().nodes.size();
  EXPECT_EQ(all->GetNumberOfCells(), vtkIdType(12 * nodes));
  double sah = 0.0;
  vtkDataArray* sah_a = all->GetCellData()->GetArray("SAHCost");
  for (vtkIdType c = 0; c < all->GetNumberOfCells(); c += 12) sah += sah_a->GetTuple1(c);
  const double expected = scene->bvh().quality().sah_cost;
  EXPECT_NEAR(sah, expected, 1e-9 * expected);
  EXPECT_NEAR(all->GetFieldData()->GetArray("SAHCostTotal")->GetTuple1(0), expected,
              1e-9 * expected);
  EXPECT_EQ(all->GetFieldData()->GetArray("TreeDepth")->GetTuple1(0),
            double(scene->bvh().quality().depth));
  // The root holds every primitive.
  const std::vector<Box> boxes = boxes_of(all, 12);
  EXPECT_EQ(boxes[0].node, 0);
  EXPECT_EQ(size_t(boxes[0].count), scene->accel().records().size());

  bvh->SetLevelRange(2, 3);
  bvh->GenerateFacesOn();
  bvh->Update();
  vtkPolyData* pd = bvh->GetOutput();
  ASSERT_GT(pd->GetNumberOfCells(), 0);
  EXPECT_EQ(pd->GetNumberOfPolys(), pd->GetNumberOfCells());
  EXPECT_EQ(pd->GetNumberOfCells() % 6, 0);
  vtkDataArray* level = pd->GetCellData()->GetArray("Level");
  std::set<int> levels;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c) levels.insert(int(level->GetTuple1(c)));
  EXPECT_EQ(levels, (std::set<int>{2, 3}));

  bvh->SetLevelRange(3, 2);
  vtkNew<ErrorCatcher> errors, pipeline_errors;
  bvh->AddObserver(vtkCommand::ErrorEvent, errors);
  bvh->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline_errors);
  EXPECT_EQ(update(bvh), 0);
  EXPECT_NE(errors->last.find("LevelRange"), std::string::npos);
}

// Visit counts: for a pixel, the node visits of its ray tree; for the frame,
// the sum of the image's per-pixel Cost (nodes visited), exactly.
TEST(VtkBVH, VisitCounts) {
  Scene3 s;
  s.alg->Update();
  double cost = 0.0;
  vtkDataArray* c = s.alg->GetOutput()->GetPointData()->GetArray("Cost");
  for (vtkIdType k = 0; k < c->GetNumberOfTuples(); ++k) cost += c->GetTuple1(k);

  vtkNew<vtkRayScopeAccelSource> bvh;
  bvh->SetSceneSource(s.alg);
  bvh->SetVisitModeToFrame();
  bvh->Update();
  auto visits = [&] {
    double v = 0.0;
    vtkDataArray* a = bvh->GetOutput()->GetCellData()->GetArray("VisitCount");
    for (vtkIdType k = 0; k < a->GetNumberOfTuples(); k += 12) v += a->GetTuple1(k);
    return v;
  };
  EXPECT_GT(cost, 0.0);
  EXPECT_EQ(visits(), cost);

  vtkNew<vtkRayScopeRayTreeSource> tree;
  tree->SetSceneSource(s.alg);
  tree->SetPixel(24, 14);
  tree->Update();
  double nodes = 0.0, first = -1.0;
  vtkPolyData* t = tree->GetOutput();
  for (vtkIdType k = t->GetNumberOfVerts(); k < t->GetNumberOfCells(); ++k) {
    const double n = t->GetCellData()->GetArray("NodesVisited")->GetTuple1(k);
    nodes += n;
    if (first < 0.0) first = n;
  }
  bvh->SetVisitModeToPixel();
  bvh->SetPixel(24, 14);
  bvh->Update();
  EXPECT_GT(nodes, 0.0);
  EXPECT_EQ(visits(), nodes);
  bvh->SetVisitRay(0);  // the primary ray only
  bvh->Update();
  EXPECT_EQ(visits(), first);
  // It equals the pixel's Cost in the image too.
  EXPECT_EQ(nodes, c->GetTuple1(14 * 48 + 24));

  // The binary teaching walk (Accel): the same image; the frame's visits are
  // again the image's Cost, now of the binary walk, which enters more nodes.
  vtkNew<vtkImageData> wide_image;
  wide_image->DeepCopy(s.alg->GetOutput());
  s.alg->SetAccelToBinaryBvh();
  s.alg->Update();
  vtkDataArray* wide_rgb = wide_image->GetPointData()->GetScalars();
  vtkDataArray* binary_rgb = s.alg->GetOutput()->GetPointData()->GetScalars();
  ASSERT_EQ(wide_rgb->GetNumberOfTuples(), binary_rgb->GetNumberOfTuples());
  for (vtkIdType k = 0; k < wide_rgb->GetNumberOfTuples(); ++k)
    for (int j = 0; j < wide_rgb->GetNumberOfComponents(); ++j)
      ASSERT_EQ(wide_rgb->GetComponent(k, j), binary_rgb->GetComponent(k, j)) << "pixel " << k;
  double binary_cost = 0.0;
  c = s.alg->GetOutput()->GetPointData()->GetArray("Cost");
  for (vtkIdType k = 0; k < c->GetNumberOfTuples(); ++k) binary_cost += c->GetTuple1(k);
  bvh->SetVisitModeToFrame();
  bvh->Update();
  EXPECT_EQ(visits(), binary_cost);
  EXPECT_GT(binary_cost, cost);

  // The kD-tree (Accel): the same image; the source now draws the kD-tree's
  // cells (the structure the rays walk), and the frame's visits are the
  // image's Cost of the kD-tree walk. Cells tile the root cell: the leaves'
  // volumes add up to the root's.
  s.alg->SetAccelToKdTree();
  s.alg->Update();
  vtkDataArray* kd_rgb = s.alg->GetOutput()->GetPointData()->GetScalars();
  ASSERT_EQ(wide_rgb->GetNumberOfTuples(), kd_rgb->GetNumberOfTuples());
  for (vtkIdType k = 0; k < wide_rgb->GetNumberOfTuples(); ++k)
    for (int j = 0; j < wide_rgb->GetNumberOfComponents(); ++j)
      ASSERT_EQ(wide_rgb->GetComponent(k, j), kd_rgb->GetComponent(k, j)) << "pixel " << k;
  double kd_cost = 0.0;
  c = s.alg->GetOutput()->GetPointData()->GetArray("Cost");
  for (vtkIdType k = 0; k < c->GetNumberOfTuples(); ++k) kd_cost += c->GetTuple1(k);
  ASSERT_EQ(update(bvh), 1);
  EXPECT_EQ(visits(), kd_cost);
  vtkPolyData* out = bvh->GetOutput();
  EXPECT_EQ(out->GetFieldData()->GetAbstractArray("Structure")->GetVariantValue(0).ToString(),
            "kdtree");
  const auto& kd = s.alg->GetCoreScene()->accel().structure_as<rayscope::KdTree>();
  EXPECT_EQ(out->GetNumberOfCells(), vtkIdType(12 * kd.nodes.size()));
  double root_volume = 0.0, leaf_volume = 0.0;
  for (vtkIdType k = 0; k < out->GetNumberOfCells(); k += 12) {
    // A box's 8 corners are points 8b .. 8b+7, from (lo, lo, lo) to (hi, hi, hi).
    const vtkIdType first = 8 * (k / 12);
    double lo[3], hi[3];
    out->GetPoint(first, lo);
    out->GetPoint(first + 7, hi);
    const double v = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    if (out->GetCellData()->GetArray("Level")->GetTuple1(k) == 0) root_volume = v;
    if (out->GetCellData()->GetArray("IsLeaf")->GetTuple1(k) == 1) leaf_volume += v;
  }
  EXPECT_GT(root_volume, 0.0);
  EXPECT_NEAR(leaf_volume, root_volume, 1e-9 * root_volume);

  // The octree, with either storage (Accel, Storage): the same image; the
  // source draws its nodes (loose boxes for smallest-cell), and the frame's
  // visits are the image's Cost of the octree walk.
  for (int storage : {vtkRayScopeImageAlgorithm::STORAGE_EVERY_CELL,
                      vtkRayScopeImageAlgorithm::STORAGE_SMALLEST_CELL}) {
    s.alg->SetAccelToOctree();
    s.alg->SetStorage(storage);
    s.alg->Update();
    ASSERT_EQ(s.alg->GetCoreScene()->accel().kind(), rayscope::AccelKind::Octree);
    ASSERT_EQ(s.alg->GetCoreScene()->accel().structure_as<rayscope::Octree>().loose(),
              storage == vtkRayScopeImageAlgorithm::STORAGE_SMALLEST_CELL);
    vtkDataArray* oc_rgb = s.alg->GetOutput()->GetPointData()->GetScalars();
    ASSERT_EQ(wide_rgb->GetNumberOfTuples(), oc_rgb->GetNumberOfTuples());
    for (vtkIdType k = 0; k < wide_rgb->GetNumberOfTuples(); ++k)
      for (int j = 0; j < wide_rgb->GetNumberOfComponents(); ++j)
        ASSERT_EQ(wide_rgb->GetComponent(k, j), oc_rgb->GetComponent(k, j)) << "pixel " << k;
    double oc_cost = 0.0;
    c = s.alg->GetOutput()->GetPointData()->GetArray("Cost");
    for (vtkIdType k = 0; k < c->GetNumberOfTuples(); ++k) oc_cost += c->GetTuple1(k);
    ASSERT_EQ(update(bvh), 1);
    EXPECT_GT(oc_cost, 0.0);
    EXPECT_EQ(visits(), oc_cost);
    vtkPolyData* o = bvh->GetOutput();
    EXPECT_EQ(o->GetFieldData()->GetAbstractArray("Structure")->GetVariantValue(0).ToString(),
              "octree");
    const rayscope::Octree& oct = s.alg->GetCoreScene()->accel().structure_as<rayscope::Octree>();
    ASSERT_EQ(o->GetNumberOfCells(), vtkIdType(12 * oct.nodes.size()));
    // The root's drawn box is the node box the walk tests.
    const rayscope::Bounds3 root = oct.node_box(oct.cells()[0]);
    double lo[3];
    o->GetPoint(0, lo);
    const double origin_x = s.alg->GetCoreScene()->origin.x;  // world = scene + origin
    EXPECT_NEAR(lo[0] - origin_x, root.lo.x, 1e-5 * (1.0 + std::abs(root.lo.x)));
  }

  // The BSP tree, with each storage: the same image; the source draws its
  // cells' boxes and, after them, one polygon per inner node (its split plane
  // clipped to its cell, on that plane), with the node's data; the frame's
  // visits are the image's Cost of the BSP walk.
  for (int storage : {vtkRayScopeImageAlgorithm::STORAGE_EVERY_CELL,
                      vtkRayScopeImageAlgorithm::STORAGE_SMALLEST_CELL,
                      vtkRayScopeImageAlgorithm::STORAGE_SPLIT}) {
    s.alg->SetAccelToBsp();
    s.alg->SetStorage(storage);
    s.alg->Update();
    const rayscope::Aggregate& acc = s.alg->GetCoreScene()->accel();
    ASSERT_EQ(acc.kind(), rayscope::AccelKind::Bsp);
    vtkDataArray* bsp_rgb = s.alg->GetOutput()->GetPointData()->GetScalars();
    ASSERT_EQ(wide_rgb->GetNumberOfTuples(), bsp_rgb->GetNumberOfTuples());
    for (vtkIdType k = 0; k < wide_rgb->GetNumberOfTuples(); ++k)
      for (int j = 0; j < wide_rgb->GetNumberOfComponents(); ++j)
        ASSERT_EQ(wide_rgb->GetComponent(k, j), bsp_rgb->GetComponent(k, j)) << "pixel " << k;
    double bsp_cost = 0.0;
    c = s.alg->GetOutput()->GetPointData()->GetArray("Cost");
    for (vtkIdType k = 0; k < c->GetNumberOfTuples(); ++k) bsp_cost += c->GetTuple1(k);
    ASSERT_EQ(update(bvh), 1);
    EXPECT_GT(bsp_cost, 0.0);
    vtkPolyData* o = bvh->GetOutput();
    // The boxes' visits (one cell in 12 per box; the polygons come after).
    double box_visits = 0.0;
    vtkDataArray* va = o->GetCellData()->GetArray("VisitCount");
    for (vtkIdType k = 0; k < o->GetNumberOfLines(); k += 12) box_visits += va->GetTuple1(k);
    EXPECT_EQ(box_visits, bsp_cost);
    EXPECT_EQ(o->GetFieldData()->GetAbstractArray("Structure")->GetVariantValue(0).ToString(),
              "bsp");
    const rayscope::BspTree& tree = acc.structure_as<rayscope::BspTree>();
    size_t inner = 0;
    for (const rayscope::BspNode& n : tree.nodes) inner += !n.is_leaf();
    ASSERT_GT(inner, 0u);
    ASSERT_EQ(o->GetNumberOfLines(), vtkIdType(12 * tree.nodes.size()));
    ASSERT_EQ(o->GetNumberOfPolys(), vtkIdType(inner));
    ASSERT_EQ(o->GetNumberOfCells(), vtkIdType(12 * tree.nodes.size() + inner));
    const double origin_x = s.alg->GetCoreScene()->origin.x;
    const double origin_y = s.alg->GetCoreScene()->origin.y;
    const double origin_z = s.alg->GetCoreScene()->origin.z;
    vtkDataArray* node_ids = o->GetCellData()->GetArray("NodeId");
    vtkDataArray* leaf = o->GetCellData()->GetArray("IsLeaf");
    for (vtkIdType k = vtkIdType(12 * tree.nodes.size()); k < o->GetNumberOfCells(); ++k) {
      const rayscope::BspNode& n = tree.nodes.at(size_t(node_ids->GetTuple1(k)));
      EXPECT_EQ(leaf->GetTuple1(k), 0.0);
      vtkCell* cell = o->GetCell(k);
      // vtkPolyData names a polygon of 3 or 4 points a triangle or a quad.
      ASSERT_TRUE(cell->GetCellType() == VTK_POLYGON || cell->GetCellType() == VTK_QUAD ||
                  cell->GetCellType() == VTK_TRIANGLE);
      ASSERT_GE(cell->GetNumberOfPoints(), 3);
      for (vtkIdType j = 0; j < cell->GetNumberOfPoints(); ++j) {
        double p[3];
        o->GetPoint(cell->GetPointId(j), p);
        const rayscope::Vec3 q(float(p[0] - origin_x), float(p[1] - origin_y),
                               float(p[2] - origin_z));
        EXPECT_LT(std::abs(n.distance(q)), 1e-3) << "a polygon point off its plane";
      }
    }
  }

  // The uniform grid likewise: the same image; the source draws the grid's
  // box (level 0) and its cells (level 1), and the frame's visits are the
  // image's Cost of the grid walk.
  s.alg->SetAccelToGrid();
  s.alg->SetStorageToEveryCell();
  EXPECT_EQ(s.alg->GetAccel(), vtkRayScopeImageAlgorithm::ACCEL_GRID);
  s.alg->Update();
  vtkDataArray* grid_rgb = s.alg->GetOutput()->GetPointData()->GetScalars();
  ASSERT_EQ(wide_rgb->GetNumberOfTuples(), grid_rgb->GetNumberOfTuples());
  for (vtkIdType k = 0; k < wide_rgb->GetNumberOfTuples(); ++k)
    for (int j = 0; j < wide_rgb->GetNumberOfComponents(); ++j)
      ASSERT_EQ(wide_rgb->GetComponent(k, j), grid_rgb->GetComponent(k, j)) << "pixel " << k;
  double grid_cost = 0.0;
  c = s.alg->GetOutput()->GetPointData()->GetArray("Cost");
  for (vtkIdType k = 0; k < c->GetNumberOfTuples(); ++k) grid_cost += c->GetTuple1(k);
  ASSERT_EQ(update(bvh), 1);
  EXPECT_GT(grid_cost, 0.0);
  EXPECT_EQ(visits(), grid_cost);
  vtkPolyData* g = bvh->GetOutput();
  EXPECT_EQ(g->GetFieldData()->GetAbstractArray("Structure")->GetVariantValue(0).ToString(),
            "grid");
  EXPECT_EQ(
      g->GetNumberOfCells(),
      vtkIdType(
          12 * (s.alg->GetCoreScene()->accel().structure_as<rayscope::UniformGrid>().cells() + 1)));

  // The sphere tree: the same image; the source draws every node as its
  // sphere (three great circles as lines, a closed latitude-longitude surface
  // with faces), the node's data on each of its cells, and the frame's visits
  // are the image's Cost of the sphere walk.
  s.alg->SetAccelToSpheres();
  EXPECT_EQ(s.alg->GetAccel(), vtkRayScopeImageAlgorithm::ACCEL_SPHERES);
  s.alg->Update();
  ASSERT_EQ(s.alg->GetCoreScene()->accel().kind(), rayscope::AccelKind::Spheres);
  vtkDataArray* sp_rgb = s.alg->GetOutput()->GetPointData()->GetScalars();
  ASSERT_EQ(wide_rgb->GetNumberOfTuples(), sp_rgb->GetNumberOfTuples());
  for (vtkIdType k = 0; k < wide_rgb->GetNumberOfTuples(); ++k)
    for (int j = 0; j < wide_rgb->GetNumberOfComponents(); ++j)
      ASSERT_EQ(wide_rgb->GetComponent(k, j), sp_rgb->GetComponent(k, j)) << "pixel " << k;
  double sp_cost = 0.0;
  c = s.alg->GetOutput()->GetPointData()->GetArray("Cost");
  for (vtkIdType k = 0; k < c->GetNumberOfTuples(); ++k) sp_cost += c->GetTuple1(k);
  const rayscope::SphereTree& st =
      s.alg->GetCoreScene()->accel().structure_as<rayscope::SphereTree>();
  const rayscope::DVec3 origin = s.alg->GetCoreScene()->origin;
  for (bool faces : {false, true}) {
    bvh->SetGenerateFaces(faces);
    ASSERT_EQ(update(bvh), 1);
    vtkPolyData* sp = bvh->GetOutput();
    EXPECT_EQ(sp->GetFieldData()->GetAbstractArray("Structure")->GetVariantValue(0).ToString(),
              "spheres");
    const vtkIdType per_node = faces ? 24 * 12 : 3 * 24;
    ASSERT_EQ(sp->GetNumberOfCells(), per_node * vtkIdType(st.nodes.size()));
    EXPECT_EQ(sp->GetNumberOfPoints(), (faces ? 11 * 24 + 2 : 3 * 24) * vtkIdType(st.nodes.size()));
    double sp_visits = 0.0;
    std::set<int> counted;
    vtkNew<vtkIdList> ids;
    for (vtkIdType k = 0; k < sp->GetNumberOfCells(); ++k) {
      const int node = int(sp->GetCellData()->GetArray("NodeId")->GetTuple1(k));
      ASSERT_GE(node, 0);
      ASSERT_LT(size_t(node), st.nodes.size());
      if (counted.insert(node).second)
        sp_visits += sp->GetCellData()->GetArray("VisitCount")->GetTuple1(k);
      // Every point of the cell lies on the node's sphere.
      sp->GetCellPoints(k, ids);
      ASSERT_GE(ids->GetNumberOfIds(), faces ? 3 : 2);
      const rayscope::SphereNode& n = st.nodes[size_t(node)];
      for (vtkIdType j = 0; j < ids->GetNumberOfIds(); ++j) {
        double p[3];
        sp->GetPoint(ids->GetId(j), p);
        const double d = std::hypot(p[0] - origin.x - n.center.x, p[1] - origin.y - n.center.y,
                                    p[2] - origin.z - n.center.z);
        ASSERT_NEAR(d, n.radius, 1e-5 * (1.0 + n.radius)) << "node " << node;
      }
    }
    EXPECT_EQ(counted.size(), st.nodes.size());
    EXPECT_GT(sp_cost, 0.0);
    EXPECT_EQ(sp_visits, sp_cost);
  }
  bvh->SetGenerateFaces(false);
  s.alg->SetAccel(99);  // clamped to the last kind
  EXPECT_EQ(s.alg->GetAccel(), vtkRayScopeImageAlgorithm::ACCEL_SPHERES);
}

// The datasets through input port 0, without a scene source: the same boxes
// as the scene source with those inputs; a changed input rebuilds them.
TEST(VtkBVH, InputPortWithoutSceneSource) {
  Scene3 s;
  vtkNew<vtkRayScopeAccelSource> from_source, from_port;
  from_source->SetSceneSource(s.alg);
  from_port->AddInputConnection(s.quad->GetOutputPort());
  from_port->AddInputConnection(s.sphere->GetOutputPort());
  from_port->AddInputConnection(s.floor->GetOutputPort());
  ASSERT_EQ(update(from_source), 1);
  ASSERT_EQ(update(from_port), 1);
  vtkPolyData* a = from_source->GetOutput();
  vtkPolyData* b = from_port->GetOutput();
  ASSERT_GT(a->GetNumberOfCells(), 12);
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  for (vtkIdType p = 0; p < a->GetNumberOfPoints(); ++p)
    for (int k = 0; k < 3; ++k) ASSERT_EQ(a->GetPoint(p)[k], b->GetPoint(p)[k]) << p;
  double before[6];
  b->GetBounds(before);
  s.floor->SetResolution(2, 2);
  configure_floor(s.floor, -0.6, 5.0);  // twice as wide: the root box grows
  ASSERT_EQ(update(from_port), 1);
  double after[6];
  from_port->GetOutput()->GetBounds(after);
  EXPECT_LT(after[0], before[0] - 2.0);
  EXPECT_GT(after[1], before[1] + 2.0);
}
