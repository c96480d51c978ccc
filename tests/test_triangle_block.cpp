// The BVH leaves' four-lane triangle test (triangle_block.h) against
// intersect_triangle(), lane by lane: a lane the block test calls a hit is a
// hit with the same t and barycentrics bit for bit, a lane it calls a miss is
// a miss, and only the rest is left to the scalar test; the SSE version and
// the portable one agree on every lane. Rays: vertices, edge midpoints, rays
// along edges, random rays, grazing rays over slivers, a mesh far from the
// origin, axis-parallel and degenerate rays, degenerate triangles, and tmax
// at, below and beyond the hits. The queries through the aggregate, which
// use the blocks, are checked against brute force in test_aggregate and the
// structure tests (check_queries).
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "accel_test_util.h"
#include "rayscope/accel/triangle_block.h"
#include "rayscope/shapes.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

struct Tri {
  Vec3 p[3];
};

std::vector<Tri> triangles_of(const TriangleMesh& m) {
  std::vector<Tri> out;
  for (const glm::uvec3& t : m.triangles)
    out.push_back(Tri{{m.positions[t.x], m.positions[t.y], m.positions[t.z]}});
  return out;
}

/// Triangles tris[first ..] in the lanes of a block, at most kLanes, and
/// `others` lanes marked as other primitives after them.
TriangleBlock block_of(const std::vector<Tri>& tris, size_t first, int& n, int others = 0) {
  TriangleBlock b;
  n = int(std::min<size_t>(TriangleBlock::kLanes - others, tris.size() - first));
  for (int k = 0; k < n; ++k) {
    b.triangles |= uint8_t(1u << k);
    for (int i = 0; i < 3; ++i)
      for (int axis = 0; axis < 3; ++axis) b.v[i][axis][k] = tris[first + k].p[i][axis];
  }
  for (int k = n; k < n + others; ++k) b.others |= uint8_t(1u << k);
  return b;
}

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof(float)) == 0;
}

struct Counts {
  long lanes = 0, hits = 0, misses = 0, undecided = 0;
};

/// The block test of one block for one ray and tmax against intersect_triangle.
void check_block(const TriangleBlock& b, const Tri* tris, int n, int others, const Ray& ray,
                 float tmax, Counts& c) {
  const TrianglePrecomp pre(ray);
  const TriangleBlockRay r(pre);
  TriangleBlockResult fast, early, portable;
  test_triangle_block(b, r, tmax, fast);
  test_triangle_block<true>(b, r, tmax, early);
  test_triangle_block_scalar(b, r, tmax, portable);
  ASSERT_EQ(fast.hits, portable.hits);
  ASSERT_EQ(fast.undecided, portable.undecided);
  ASSERT_EQ(early.hits, portable.hits);
  ASSERT_EQ(early.undecided, portable.undecided);
  for (unsigned m = early.hits; m != 0; m &= m - 1) {
    const unsigned k = unsigned(__builtin_ctz(m));
    const TriangleHit e = early.hit(k), f = fast.hit(k);
    EXPECT_TRUE(same_bits(e.t, f.t) && same_bits(e.b0, f.b0) && same_bits(e.b1, f.b1) &&
                same_bits(e.b2, f.b2));
  }
  const unsigned other_lanes = ((1u << others) - 1u) << n;
  EXPECT_EQ(fast.undecided & other_lanes, other_lanes);
  EXPECT_EQ(fast.hits & other_lanes, 0u);
  EXPECT_EQ((fast.hits | fast.undecided) >> (n + others), 0u) << "an empty lane was reported";
  for (int k = 0; k < n; ++k) {
    TriangleHit th;
    const bool hit = intersect_triangle(pre, tmax, tris[k].p[0], tris[k].p[1], tris[k].p[2], th);
    ++c.lanes;
    if ((fast.hits >> k) & 1u) {
      ++c.hits;
      ASSERT_TRUE(hit) << "lane " << k << ": the block test hits, intersect_triangle misses";
      const TriangleHit f = fast.hit(k), p = portable.hit(k);
      EXPECT_TRUE(same_bits(f.t, th.t) && same_bits(f.b0, th.b0) && same_bits(f.b1, th.b1) &&
                  same_bits(f.b2, th.b2))
          << "lane " << k << ": t " << f.t << " vs " << th.t;
      EXPECT_TRUE(same_bits(f.t, p.t) && same_bits(f.b0, p.b0) && same_bits(f.b1, p.b1) &&
                  same_bits(f.b2, p.b2));
    } else if ((fast.undecided >> k) & 1u) {
      ++c.undecided;
    } else {
      ++c.misses;
      ASSERT_FALSE(hit) << "lane " << k << ": the block test misses, intersect_triangle hits at t "
                        << th.t << " (tmax " << tmax << ")";
    }
  }
}

/// Every block of consecutive triangles (neighbours on a mesh, so shared
/// edges and vertices fall in one block) against every ray, with tmax the
/// ray's, each hit's own t (closed bound) and half of it.
Counts check_rays(const std::vector<Tri>& tris, const std::vector<Ray>& rays, int others = 0) {
  Counts c;
  for (const Ray& ray : rays)
    for (size_t first = 0; first < tris.size(); first += TriangleBlock::kLanes - others) {
      int n = 0;
      const TriangleBlock b = block_of(tris, first, n, others);
      check_block(b, &tris[first], n, others, ray, ray.tmax, c);
      if (::testing::Test::HasFatalFailure()) return c;
      for (int k = 0; k < n; ++k) {
        TriangleHit th;
        if (!intersect_triangle(ray, tris[first + k].p[0], tris[first + k].p[1],
                                tris[first + k].p[2], th))
          continue;
        check_block(b, &tris[first], n, others, ray, th.t, c);
        check_block(b, &tris[first], n, others, ray, 0.5f * th.t, c);
        if (::testing::Test::HasFatalFailure()) return c;
      }
    }
  return c;
}

void print(const char* what, const Counts& c) {
  std::printf("%s: %ld lanes, %ld hits, %ld misses, %ld left to the scalar test\n", what, c.lanes,
              c.hits, c.misses, c.undecided);
}

TEST(TriangleBlock, IcosphereVertexEdgeAndRandomRays) {
  Rng rng(11);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 2));
  std::vector<Ray> rays;
  rstest::add_mesh_rays(rng, scene, rays);
  Bounds3 world(Vec3(-2.0f));
  world.extend(Vec3(2.0f));
  rstest::add_random_rays(rng, scene, world, 400, rays);  // axis-parallel ones too
  const size_t adversarial = rays.size();
  // Rays in general position: from a random point of a shell around the
  // sphere through a random point of its box.
  for (int i = 0; i < 400; ++i) {
    const DVec3 o = rng.uniform(2.0, 4.0) * rng.unit_vector();
    const DVec3 target(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    rays.push_back(Ray{to_f(o), to_f(target - o), kInfinity});
  }
  const std::vector<Tri> tris = triangles_of(scene.meshes[0]);
  const Counts edges = check_rays(tris, {rays.begin(), rays.begin() + long(adversarial)});
  print("vertex, edge and random_ray rays", edges);
  const Counts random = check_rays(tris, {rays.begin() + long(adversarial), rays.end()});
  print("rays in general position", random);
  EXPECT_GT(edges.hits, 1000);
  EXPECT_GT(edges.undecided, 0) << "rays through vertices and edges must reach the exact test";
  EXPECT_GT(random.hits, 500);
  // The point of the block test: for rays in general position it decides
  // nearly every lane itself.
  EXPECT_LT(double(random.undecided), 0.001 * double(random.lanes));
}

TEST(TriangleBlock, OtherPrimitivesAndEmptyLanes) {
  Rng rng(12);
  Scene scene;
  scene.meshes.push_back(make_icosphere(Vec3(0.0f), 1.0f, 1));
  std::vector<Ray> rays;
  Bounds3 world(Vec3(-2.0f));
  world.extend(Vec3(2.0f));
  rstest::add_random_rays(rng, scene, world, 200, rays);
  const std::vector<Tri> tris = triangles_of(scene.meshes[0]);
  for (int others = 1; others < TriangleBlock::kLanes; ++others) {
    const Counts c = check_rays(tris, rays, others);
    EXPECT_GT(c.hits, 0);
  }
}

TEST(TriangleBlock, GrazingSliversAndFarFromTheOrigin) {
  Rng rng(13);
  const Scene slivers = rstest::sliver_scene(rng);
  std::vector<Ray> rays;
  Bounds3 world(Vec3(-5.0f));
  world.extend(Vec3(5.0f));
  rstest::add_inside_and_grazing_rays(rng, slivers, world, 300, rays);
  rstest::add_random_rays(rng, slivers, world, 300, rays);
  // Rays nearly in each sliver's plane, from outside it.
  const std::vector<Tri> thin = triangles_of(slivers.meshes[1]);
  for (size_t i = 0; i < thin.size(); i += 3) {
    const DVec3 a = to_d(thin[i].p[0]), b = to_d(thin[i].p[1]), c = to_d(thin[i].p[2]);
    const DVec3 n = glm::normalize(glm::cross(b - a, c - a));
    const DVec3 target = (a + b + c) / 3.0;
    const DVec3 along = glm::normalize(b - a);
    const DVec3 o = target - 4.0 * along + 1e-5 * rng.uniform(-1, 1) * n;
    rays.push_back(Ray{to_f(o), to_f(target - o), kInfinity});
  }
  Counts c = check_rays(thin, rays);
  print("slivers", c);
  EXPECT_GT(c.hits, 100);

  // The icosphere moved to ~1e5, rays moved with it.
  Scene far;
  far.meshes.push_back(make_icosphere(Vec3(1.0e5f, -3.0e4f, 2.0e5f), 1.0f, 2));
  std::vector<Ray> far_rays;
  rstest::add_mesh_rays(rng, far, far_rays);
  const std::vector<Tri> moved = triangles_of(far.meshes[0]);
  c = check_rays(moved, far_rays);
  print("far from the origin", c);
  EXPECT_GT(c.hits, 500);
}

TEST(TriangleBlock, AxisParallelAndDegenerateRaysAndTriangles) {
  Rng rng(14);
  std::vector<Tri> tris = triangles_of(make_icosphere(Vec3(0.0f), 1.0f, 1));
  // Zero-area triangles: a repeated vertex, collinear vertices, a point.
  tris.push_back(Tri{{Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)}});
  tris.push_back(Tri{{Vec3(-1, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)}});
  tris.push_back(Tri{{Vec3(0.5f), Vec3(0.5f), Vec3(0.5f)}});
  tris.push_back(Tri{{Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0)}});
  std::vector<Ray> rays;
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {1.0f, -1.0f})
      for (int i = 0; i < 40; ++i) {
        Vec3 d(0.0f);
        d[axis] = sign;
        Vec3 o = to_f(DVec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
        o[axis] = -3.0f * sign;
        if (i % 4 == 0) o[(axis + 1) % 3] = 0.0f;  // in a coordinate plane
        rays.push_back(Ray{o, d, kInfinity});
      }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  rays.push_back(Ray{Vec3(0, 0, -3), Vec3(nan, 0, 1), kInfinity});
  rays.push_back(Ray{Vec3(nan, 0, -3), Vec3(0, 0, 1), kInfinity});
  rays.push_back(Ray{Vec3(0, 0, -3), Vec3(kInfinity, 0, 1), kInfinity});
  rays.push_back(Ray{Vec3(0, 0, -3), Vec3(1e-30f, 1e-30f, 1), kInfinity});
  rays.push_back(Ray{Vec3(0, 0, -3), Vec3(0, 0, 1), 0.0f});
  const Counts c = check_rays(tris, rays);
  print("axis-parallel and degenerate", c);
  EXPECT_GT(c.hits, 100);
}

}  // namespace
