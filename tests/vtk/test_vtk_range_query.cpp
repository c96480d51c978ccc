// vtkRayScopeRangeQuery: the objects it outputs are exactly those a brute-force
// loop over the scene's triangles finds with the core's exact tests (box
// overlap, distance), for every structure the scene source can walk; the
// range output; bad ranges give an error and empty outputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>
#include <vtkStringArray.h>

#include "rayscope/range_query.h"
#include "rayscope/scene.h"
#include "vtkRayScopeImageAlgorithm.h"
#include "vtkRayScopeRangeQuery.h"
#include "vtk_test_util.h"

namespace {

struct Found {
  int rank, prim;
  double distance;
};

// One entry per object (the cells of an object share its rank), by rank.
std::vector<Found> found_of(vtkPolyData* pd) {
  std::map<int, Found> by_rank;
  vtkCellData* cd = pd->GetCellData();
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c) {
    const int r = int(cd->GetArray("Rank")->GetTuple1(c));
    by_rank[r] = {r, int(cd->GetArray("PrimitiveId")->GetTuple1(c)),
                  cd->GetArray("Distance")->GetTuple1(c)};
  }
  std::vector<Found> out;
  for (const auto& [r, f] : by_rank) out.push_back(f);
  return out;
}

int field_int(vtkPolyData* pd, const char* name) {
  return int(pd->GetFieldData()->GetArray(name)->GetTuple1(0));
}

// Two spheres and a floor, all triangle meshes (VTK datasets), as the
// image algorithm's inputs.
struct SceneFixture : ::testing::Test {
  vtkNew<vtkSphereSource> ball, small;
  vtkNew<vtkPlaneSource> floor;
  vtkNew<vtkRayScopeImageAlgorithm> alg;
  vtkNew<vtkRayScopeRangeQuery> query;
  void SetUp() override {
    configure_sphere(ball, 0.0, 0.5, 0.0, 0.5, 32);
    configure_sphere(small, 1.2, 0.3, -0.4, 0.3, 16);
    configure_floor(floor, 0.0, 2.0);
    floor->SetResolution(8, 8);
    alg->AddInputConnection(ball->GetOutputPort());
    alg->AddInputConnection(small->GetOutputPort());
    alg->AddInputConnection(floor->GetOutputPort());
    alg->SetSize(64, 48);
    query->SetSceneSource(alg);
  }
  // Brute force over the committed scene's triangles with the core's exact
  // tests (scene-local coordinates; this scene's origin is the world's).
  template <class Keep>
  std::vector<Found> brute_force(Keep keep) {
    const rayscope::Scene& s = *alg->GetCoreScene();
    std::vector<Found> out;
    int prim = 0;
    for (const rayscope::TriangleMesh& m : s.meshes)
      for (const glm::uvec3& t : m.triangles) {
        double d;
        if (keep(m.positions[t.x], m.positions[t.y], m.positions[t.z], d))
          out.push_back({0, prim, d});
        ++prim;
      }
    return out;
  }
};

TEST_F(SceneFixture, BoxQueryFindsWhatBruteForceFindsWithEveryStructure) {
  const double box[6] = {-0.3, 0.9, 0.2, 0.6, -0.6, 0.1};
  query->SetQueryTypeToBox();
  query->SetBox(const_cast<double*>(box));
  for (int accel :
       {int(vtkRayScopeImageAlgorithm::ACCEL_BVH), int(vtkRayScopeImageAlgorithm::ACCEL_BINARY_BVH),
        int(vtkRayScopeImageAlgorithm::ACCEL_NONE), int(vtkRayScopeImageAlgorithm::ACCEL_KDTREE),
        int(vtkRayScopeImageAlgorithm::ACCEL_GRID), int(vtkRayScopeImageAlgorithm::ACCEL_OCTREE),
        int(vtkRayScopeImageAlgorithm::ACCEL_BSP), int(vtkRayScopeImageAlgorithm::ACCEL_SPHERES)}) {
    SCOPED_TRACE(accel);
    alg->SetAccel(accel);
    ASSERT_EQ(update(query), 1);
    vtkPolyData* out = query->GetOutput(0);
    rayscope::Bounds3 b;
    b.lo = rayscope::Vec3(box[0], box[2], box[4]);
    b.hi = rayscope::Vec3(box[1], box[3], box[5]);
    const std::vector<Found> expected =
        brute_force([&](const auto& a, const auto& c1, const auto& c2, double& d) {
          d = 0.0;
          return rayscope::triangle_overlaps_box(a, c1, c2, b);
        });
    const std::vector<Found> got = found_of(out);
    ASSERT_GT(expected.size(), 20u);  // the box cuts the ball and the floor
    ASSERT_EQ(got.size(), expected.size());
    for (size_t k = 0; k < got.size(); ++k) EXPECT_EQ(got[k].prim, expected[k].prim) << k;
    // One triangle cell per triangle found; field data names the structure
    // and counts what the walk tested (fewer than all, with a structure).
    EXPECT_EQ(out->GetNumberOfCells(), vtkIdType(expected.size()));
    EXPECT_EQ(field_int(out, "ObjectsFound"), int(expected.size()));
    const int tested = field_int(out, "PrimitivesTested");
    const int all = int(alg->GetCoreScene()->accel().records().size());
    if (accel == vtkRayScopeImageAlgorithm::ACCEL_NONE)
      EXPECT_EQ(tested, all);
    else
      EXPECT_LT(tested, all);
    auto* name = vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("Structure"));
    ASSERT_NE(name, nullptr);
    EXPECT_EQ(name->GetValue(0), rayscope::to_string(alg->GetCoreScene()->accel().kind()));
    // The range: the box's 6 faces, at its bounds.
    vtkPolyData* range = query->GetOutput(1);
    EXPECT_EQ(range->GetNumberOfCells(), 6);
    double rb[6];
    range->GetBounds(rb);
    for (int k = 0; k < 6; ++k) EXPECT_DOUBLE_EQ(rb[k], box[k]);
  }
}

TEST_F(SceneFixture, SphereAndNearestQueriesAreSortedByExactDistance) {
  const double center[3] = {0.6, 0.45, 0.2};
  query->SetQueryTypeToSphere();
  query->SetCenter(const_cast<double*>(center));
  query->SetRadius(0.3);
  alg->SetAccelToKdTree();
  ASSERT_EQ(update(query), 1);  // commits the scene brute_force() reads
  const std::vector<Found> within =
      brute_force([&](const auto& a, const auto& b, const auto& c, double& d) {
        d = rayscope::point_triangle_distance(rayscope::Vec3(0.6f, 0.45f, 0.2f), a, b, c);
        return d <= 0.3;
      });
  ASSERT_GT(within.size(), 5u);
  std::vector<Found> got = found_of(query->GetOutput(0));
  ASSERT_EQ(got.size(), within.size());
  std::set<int> got_ids, want_ids;
  for (size_t k = 0; k < got.size(); ++k) {
    got_ids.insert(got[k].prim);
    want_ids.insert(within[k].prim);
    if (k > 0) {
      EXPECT_LE(got[k - 1].distance, got[k].distance);
    }
  }
  EXPECT_EQ(got_ids, want_ids);

  // The 7 nearest: the 7 smallest distances of all triangles, nearest first,
  // and the range drawn is the sphere through the 7th.
  std::vector<Found> all = brute_force([&](const auto& a, const auto& b, const auto& c, double& d) {
    d = rayscope::point_triangle_distance(rayscope::Vec3(0.6f, 0.45f, 0.2f), a, b, c);
    return true;
  });
  std::stable_sort(all.begin(), all.end(),
                   [](const Found& a, const Found& b) { return a.distance < b.distance; });
  query->SetQueryTypeToNearest();
  query->SetNumberOfNeighbors(7);
  alg->SetAccelToOctree();
  ASSERT_EQ(update(query), 1);
  got = found_of(query->GetOutput(0));
  ASSERT_EQ(got.size(), 7u);
  for (size_t k = 0; k < 7; ++k) EXPECT_DOUBLE_EQ(got[k].distance, all[k].distance) << k;
  double rb[6];
  query->GetOutput(1)->GetBounds(rb);
  // The sphere through the 7th, tessellated at resolution 24: its polygons lie
  // within the sphere and at most 1 - cos(pi / 24) < 1% inside it.
  EXPECT_LE(rb[1] - rb[0], 2.0 * all[6].distance * (1.0 + 1e-6));
  EXPECT_GE(rb[1] - rb[0], 2.0 * all[6].distance * 0.99);
}

TEST_F(SceneFixture, BadRangesGiveAnErrorAndEmptyOutputs) {
  vtkNew<ErrorCatcher> errors;
  query->AddObserver(vtkCommand::ErrorEvent, errors);
  query->SetQueryTypeToBox();
  ASSERT_EQ(update(query), 1);
  ASSERT_GT(query->GetOutput(0)->GetNumberOfCells(), 0);  // the default unit box

  query->SetBox(1, -1, 0, 1, 0, 1);  // xmin > xmax
  EXPECT_EQ(update(query), 0);
  EXPECT_GE(errors->count, 1);
  EXPECT_NE(errors->last.find("range query"), std::string::npos) << errors->last;
  EXPECT_EQ(query->GetOutput(0)->GetNumberOfCells(), 0);
  EXPECT_EQ(query->GetOutput(1)->GetNumberOfCells(), 0);

  query->SetQueryTypeToSphere();
  query->SetRadius(-1.0);
  errors->count = 0;
  EXPECT_EQ(update(query), 0);
  EXPECT_GE(errors->count, 1);
  EXPECT_EQ(query->GetOutput(0)->GetNumberOfCells(), 0);

  query->SetQueryTypeToNearest();
  query->SetNumberOfNeighbors(0);
  errors->count = 0;
  EXPECT_EQ(update(query), 0);
  EXPECT_GE(errors->count, 1);
  EXPECT_NE(errors->last.find("NumberOfNeighbors"), std::string::npos) << errors->last;
}

}  // namespace
