// The BSP tree (bsp.h), for its three storage choices (every-cell:
// straddlers on both sides, mailboxed; smallest-cell: the node list, each
// primitive once; split: triangles cut into fragments): builder invariants
// (what each leaf holds, fragment areas and sides), degenerate and bad input,
// figures and the view's polygons. What every structure does (queries ==
// brute force and == the BVH, rays in and across its planes of any
// orientation, the observer, range queries, images) is
// test_accel_conformance's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "accel_test_util.h"
#include "rayscope/accel/accel_view.h"

namespace {

using namespace rayscope;
using rstest::DVec3;
using rstest::Rng;
using rstest::to_d;
using rstest::to_f;

class BspStorage : public ::testing::TestWithParam<PrimStorage> {};
INSTANTIATE_TEST_SUITE_P(All, BspStorage, ::testing::ValuesIn(kPrimStorages), [](const auto& info) {
  std::string s = to_string(info.param);
  s.erase(std::remove(s.begin(), s.end(), '-'), s.end());
  return s;
});

// Random triangles (sizes over two decades) and a few spheres.
std::vector<BspPrim> random_prims(Rng& rng, int n, int spheres) {
  std::vector<BspPrim> p;
  for (int i = 0; i < n; ++i) {
    const DVec3 c(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5));
    const double s = rng.log_uniform(0.05, 3);
    p.push_back(BspPrim::triangle(to_f(c + s * rng.in_unit_ball()),
                                  to_f(c + s * rng.in_unit_ball()),
                                  to_f(c + s * rng.in_unit_ball())));
  }
  for (int i = 0; i < spheres; ++i)
    p.push_back(BspPrim::make_sphere(
        to_f(DVec3(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5))),
        float(rng.log_uniform(0.05, 1))));
  return p;
}

double signed_distance(const BspNode& n, const DVec3& p) {
  return double(n.normal.x) * p.x + double(n.normal.y) * p.y + double(n.normal.z) * p.z - n.offset;
}

// Lowest and highest signed distance of a whole primitive from a node's plane.
void extent(const BspNode& n, const BspPrim& q, double& lo, double& hi) {
  if (q.round) {
    const double c = signed_distance(n, to_d(q.a)),
                 r = double(q.radius) * glm::length(to_d(n.normal));
    lo = c - r;
    hi = c + r;
    return;
  }
  const double s[3] = {signed_distance(n, to_d(q.a)), signed_distance(n, to_d(q.b)),
                       signed_distance(n, to_d(q.c))};
  lo = std::min({s[0], s[1], s[2]});
  hi = std::max({s[0], s[1], s[2]});
}

double polygon_area(const Vec3* v, uint32_t count) {
  DVec3 sum(0.0);
  for (uint32_t i = 1; i + 1 < count; ++i)
    sum += glm::cross(to_d(v[i]) - to_d(v[0]), to_d(v[i + 1]) - to_d(v[0]));
  return 0.5 * glm::length(sum);
}

// The ancestors of every node with the side taken (+1 front, -1 back).
struct Path {
  std::vector<std::pair<uint32_t, int>> steps;
};
std::vector<Path> paths(const BspTree& t) {
  std::vector<Path> p(t.nodes.size());
  for (uint32_t i = 0; i < t.nodes.size(); ++i) {
    if (t.nodes[i].is_leaf()) continue;
    EXPECT_LT(t.nodes[i].front, t.nodes.size());
    EXPECT_GT(t.nodes[i].front, i + 1);
    p[i + 1] = p[i];
    p[i + 1].steps.push_back({i, -1});
    p[t.nodes[i].front] = p[i];
    p[t.nodes[i].front].steps.push_back({i, +1});
  }
  return p;
}

// The storage rules, against the planes the tree reports:
// - every-cell: inner nodes hold nothing; a leaf holds exactly the primitives
//   on its side (within the tolerance) of every ancestor plane;
// - smallest-cell: each primitive exactly once, strictly on its side of every
//   ancestor plane, and straddling its node's plane unless the node is a leaf;
// - split: each triangle's pieces (fragments) have areas that sum to its area,
//   and each lies on its side of every ancestor plane; a sphere's pieces are
//   the leaves on its side of every ancestor plane.
void check_invariants(const BspTree& t, const std::vector<BspPrim>& prims) {
  ASSERT_FALSE(t.empty());
  ASSERT_EQ(t.cell_boxes.size(), t.nodes.size());
  ASSERT_EQ(t.plane_polygons.size(), t.nodes.size());
  const std::vector<Path> path = paths(t);
  const double tol = t.tolerance();
  EXPECT_GT(tol, 0.0);
  const BspQuality q = t.quality();
  EXPECT_LE(q.depth, uint32_t(t.config.max_depth));
  // A fragment's vertex is rounded to float: within half an ulp of the
  // largest coordinate of the scene per axis.
  const Bounds3 world = t.bounds();
  const Vec3 m = glm::max(glm::abs(world.lo), glm::abs(world.hi));
  const float mag = std::max({m.x, m.y, m.z});
  const double round = 2.0 * double(std::numeric_limits<float>::epsilon()) * mag;
  std::vector<int> held(prims.size(), 0);
  std::vector<double> area(prims.size(), 0.0);
  std::vector<int> pieces(prims.size(), 0);
  for (uint32_t i = 0; i < t.nodes.size(); ++i) {
    const BspNode& n = t.nodes[i];
    if (!n.is_leaf()) {
      EXPECT_GE(t.plane_polygons[i].count, 3u) << "node " << i << ": its plane crosses its cell";
    }
    if (t.storage() == PrimStorage::EveryCell && !n.is_leaf()) {
      EXPECT_EQ(n.count, 0u);
      continue;
    }
    std::vector<char> here(prims.size(), 0);
    for (uint32_t k = n.first; k < n.first + n.count; ++k) {
      const uint32_t p = t.refs[k];
      ASSERT_LT(p, prims.size());
      here[p] = 1;
      held[p]++;
      if (t.storage() == PrimStorage::Split) {
        const BspFragment& f = t.fragments[k];
        ASSERT_EQ(f.prim, p);
        pieces[p]++;
        if (prims[p].round) {
          EXPECT_EQ(f.count, 0u);
          continue;
        }
        ASSERT_GE(f.count, 3u);
        const Vec3* v = t.fragment_vertices.data() + f.first;
        area[p] += polygon_area(v, f.count);
        for (const auto& [a, side] : path[i].steps)
          for (uint32_t j = 0; j < f.count; ++j)
            ASSERT_GE(side * signed_distance(t.nodes[a], to_d(v[j])), -(tol + round))
                << "fragment " << k << " of prim " << p << " on the wrong side of node " << a;
        if (!n.is_leaf()) {  // a triangle lying in the plane
          double lo, hi;
          extent(n, prims[p], lo, hi);
          EXPECT_GE(lo, -tol);
          EXPECT_LE(hi, tol);
        }
      }
    }
    for (uint32_t p = 0; p < prims.size(); ++p) {
      bool inside = true, strict = true;
      for (const auto& [a, side] : path[i].steps) {
        double lo, hi;
        extent(t.nodes[a], prims[p], lo, hi);
        inside &= side < 0 ? lo <= tol : hi >= -tol;
        strict &= side < 0 ? hi < -tol : lo > tol;
      }
      if (t.storage() == PrimStorage::EveryCell) {
        ASSERT_EQ(bool(here[p]), inside) << "leaf " << i << ", prim " << p;
      } else if (t.storage() == PrimStorage::SmallestCell && here[p]) {
        ASSERT_TRUE(strict) << "node " << i << ", prim " << p;
        if (!n.is_leaf()) {
          double lo, hi;
          extent(n, prims[p], lo, hi);
          EXPECT_TRUE(lo <= tol && hi >= -tol) << "node " << i << " holds a non-straddler";
        }
      } else if (t.storage() == PrimStorage::Split && prims[p].round && n.is_leaf()) {
        ASSERT_EQ(bool(here[p]), inside) << "leaf " << i << ", sphere " << p;
      }
    }
  }
  for (uint32_t p = 0; p < prims.size(); ++p) {
    if (t.storage() == PrimStorage::SmallestCell) {
      ASSERT_EQ(held[p], 1) << "prim " << p;
    }
    ASSERT_GE(held[p], 1) << "prim " << p;
    if (t.storage() != PrimStorage::Split || prims[p].round) continue;
    // Each fragment's area is off by at most its perimeter times the
    // rounding of its vertices; the fragments' perimeters add up to at most
    // the triangle's plus twice each cut (at most the triangle's diameter).
    const BspPrim& tr = prims[p];
    const DVec3 a = to_d(tr.a), b = to_d(tr.b), c = to_d(tr.c);
    const double want = 0.5 * glm::length(glm::cross(b - a, c - a));
    const double per = glm::length(b - a) + glm::length(c - b) + glm::length(a - c);
    EXPECT_NEAR(area[p], want, (1.0 + 2.0 * pieces[p]) * per * round * 4.0 + 1e-12 * want)
        << "prim " << p << ", " << pieces[p] << " pieces";
  }
  if (t.storage() == PrimStorage::Split) {
    EXPECT_EQ(q.fragments, t.refs.size());
    EXPECT_EQ(t.fragments.size(), t.refs.size());
  } else {
    EXPECT_EQ(q.fragments, 0u);
  }
}

TEST_P(BspStorage, BuildInvariantsOnRandomTrianglesAndSpheres) {
  Rng rng(61);
  for (int n : {1, 5, 60, 400}) {
    const std::vector<BspPrim> prims = random_prims(rng, n, n / 10);
    BspTree t;
    t.build(prims, {}, GetParam());
    SCOPED_TRACE("n = " + std::to_string(n));
    check_invariants(t, prims);
    const BspQuality q = t.quality();
    if (n >= 60) {
      EXPECT_GT(q.depth, 2u);
      if (GetParam() == PrimStorage::Split) {
        EXPECT_GT(q.split_prims, 0u) << "the test needs cut triangles";
        EXPECT_GT(q.fragments, prims.size());
      }
      if (GetParam() == PrimStorage::EveryCell) {
        EXPECT_GT(q.refs_per_prim, 1.0);
      }
    }
  }
}

TEST_P(BspStorage, DegenerateInput) {
  Rng rng(62);
  // All at one point; zero-area triangles (segments); many coplanar
  // triangles (in z = 1 and in a tilted plane); spheres of radius 0.
  std::vector<std::vector<BspPrim>> cases;
  cases.push_back(std::vector<BspPrim>(50, BspPrim::triangle(Vec3(1), Vec3(1), Vec3(1))));
  {
    std::vector<BspPrim> seg;
    for (int i = 0; i < 80; ++i) {
      const Vec3 a = to_f(DVec3(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2)));
      const Vec3 b = to_f(DVec3(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2)));
      seg.push_back(BspPrim::triangle(a, b, 0.5f * (a + b)));
      seg.push_back(BspPrim::make_sphere(a, 0.0f));
    }
    cases.push_back(seg);
  }
  {
    std::vector<BspPrim> flat;
    const DVec3 n = glm::normalize(DVec3(1, 2, 3)),
                u = glm::normalize(glm::cross(n, DVec3(0, 0, 1))), v = glm::cross(n, u);
    for (int i = 0; i < 100; ++i) {
      const Vec3 c = to_f(DVec3(rng.uniform(-4, 4), rng.uniform(-4, 4), 1.0));
      flat.push_back(BspPrim::triangle(c, c + Vec3(0.3f, 0, 0), c + Vec3(0, 0.3f, 0)));
      const DVec3 p = rng.uniform(-4, 4) * u + rng.uniform(-4, 4) * v;
      flat.push_back(BspPrim::triangle(to_f(p), to_f(p + 0.5 * u), to_f(p + 0.5 * v)));
    }
    cases.push_back(flat);
  }
  for (size_t k = 0; k < cases.size(); ++k) {
    BspTree t;
    t.build(cases[k], {}, GetParam());
    SCOPED_TRACE("case " + std::to_string(k));
    check_invariants(t, cases[k]);
  }
  BspTree t;
  t.build({}, {}, GetParam());
  EXPECT_TRUE(t.empty());
  float tmax = kInfinity;
  NullTraversalObserver obs;
  EXPECT_FALSE(t.traverse<false>(
      Ray{Vec3(0), Vec3(1, 0, 0), kInfinity}, tmax, [](uint32_t, float&) { return true; }, obs));
  // Bad input: one clear error.
  std::vector<BspPrim> bad = random_prims(rng, 10, 0);
  bad[3].b.y = std::numeric_limits<float>::quiet_NaN();
  try {
    t.build(bad, {}, GetParam());
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("primitive 3"), std::string::npos) << e.what();
  }
  bad = random_prims(rng, 10, 2);
  bad.back().radius = -1.0f;
  EXPECT_THROW(t.build(bad, {}, GetParam()), std::invalid_argument);
  BspBuildConfig c;
  c.candidates = 0;
  EXPECT_THROW(t.build(random_prims(rng, 10, 0), c, GetParam()), std::invalid_argument);
  c = {};
  c.split_weight = -1.0f;
  EXPECT_THROW(t.build(random_prims(rng, 10, 0), c, GetParam()), std::invalid_argument);
}

void commit_bsp(Scene& scene, PrimStorage storage) {
  AccelConfig ac;
  ac.kind = AccelKind::Bsp;
  ac.storage = storage;
  scene.commit(ac);
  ASSERT_EQ(scene.accel().kind(), AccelKind::Bsp);
  ASSERT_EQ(scene.accel().storage(), storage);
  ASSERT_FALSE(scene.accel().structure_as<BspTree>().empty());
}

TEST(Bsp, StorageCheckFiguresAndView) {
  for (PrimStorage s : kPrimStorages) EXPECT_EQ(accel_storage_error(AccelKind::Bsp, s), "");
  EXPECT_NE(accel_storage_error(AccelKind::Octree, PrimStorage::Split), "");
  Rng rng(68);
  Scene scene = rstest::soup_scene(rng);
  for (PrimStorage st : kPrimStorages) {
    commit_bsp(scene, st);
    const Aggregate& a = scene.accel();
    const BspQuality q = a.structure_as<BspTree>().quality();
    const AccelFigures f = a.figures();
    EXPECT_EQ(f.nodes, q.nodes);
    EXPECT_EQ(f.leaves, q.leaves);
    EXPECT_EQ(f.depth, q.depth);
    EXPECT_DOUBLE_EQ(f.refs_per_prim, double(q.references) / double(a.records().size()));
    EXPECT_EQ(f.fragments, q.fragments);
    if (st == PrimStorage::SmallestCell) {
      EXPECT_DOUBLE_EQ(f.refs_per_prim, 1.0);
    }
    EXPECT_EQ(f.memory_bytes, a.structure_as<BspTree>().memory_bytes() +
                                  a.records().size() * (sizeof(PrimRecord) + sizeof(uint32_t)) +
                                  a.plane_records().size() * sizeof(PlaneRecord));
    // The binary BVH is built when first asked for; from then on the
    // aggregate holds it and counts it.
    const size_t binary = a.bvh().quality().memory_bytes;
    EXPECT_EQ(a.memory_bytes(), binary + a.structure_as<BspTree>().memory_bytes() +
                                    a.records().size() * (sizeof(PrimRecord) + sizeof(uint32_t)) +
                                    a.plane_records().size() * sizeof(PlaneRecord));
    // The teaching view: cell boxes, parents, the split polygons of inner
    // nodes (on their plane, inside their cell box).
    const AccelView v = make_accel_view(a);
    EXPECT_STREQ(v.structure, "bsp");
    ASSERT_EQ(v.nodes.size(), a.structure_as<BspTree>().nodes.size());
    EXPECT_EQ(v.refs.size(), a.structure_as<BspTree>().refs.size());
    EXPECT_EQ(uint32_t(v.depth), q.depth + 1);
    for (size_t i = 0; i < v.nodes.size(); ++i) {
      const AccelViewNode& n = v.nodes[i];
      const BspNode& b = a.structure_as<BspTree>().nodes[i];
      EXPECT_EQ(n.leaf, b.is_leaf());
      if (b.is_leaf()) {
        EXPECT_EQ(n.polygon_count, 0u);
        continue;
      }
      EXPECT_EQ(v.nodes[i + 1].parent, int32_t(i));
      EXPECT_EQ(v.nodes[b.front].parent, int32_t(i));
      ASSERT_GE(n.polygon_count, 3u);
      for (uint32_t j = 0; j < n.polygon_count; ++j) {
        const Vec3 p = v.polygon_vertices.at(n.polygon_first + j);
        EXPECT_LT(std::abs(signed_distance(b, to_d(p))), 1e-4);
        EXPECT_TRUE(n.box.contains(Bounds3(p)));
      }
    }
  }
}

}  // namespace
