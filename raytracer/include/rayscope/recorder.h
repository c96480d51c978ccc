// Ray-tree recording: every ray traced for a pixel (primary, shadow, reflection,
// refraction) with its hit, normals, ids, optics, weight, returned color and the
// walk it made through the acceleration structure. The recorder is a policy of
// the integrator template; renders use NullRecorder, so none of this costs
// anything unless a pixel is replayed (replay.h). Text and JSON forms of a
// recorded tree: raytree_format.h.
#pragma once

#include <string>
#include <vector>

#include "rayscope/integrator.h"
#include "rayscope/scene.h"

namespace rayscope {

/// One event of a walk through the acceleration structure (traversal.h).
struct TraversalStep {
  enum class Kind : uint8_t {
    Enter,    ///< The node is entered: its child boxes or primitives are tested next.
    BoxHit,   ///< The node's box was tested and overlaps the ray.
    BoxMiss,  ///< The node's box was tested and missed.
    Cull,     ///< The node's box was hit, but it is skipped: a closer hit was found.
  };
  Kind kind;
  uint32_t node;  ///< Binary BVH node id.
  bool operator==(const TraversalStep&) const = default;
};
const char* to_string(TraversalStep::Kind kind);

/// No node (TraversalRecord::hit_leaf when the hit came from outside a leaf).
inline constexpr uint32_t kNoNode = ~0u;

/// How one ray walked the acceleration structure: the walk renders do (the
/// 8-wide BVH by default), named by the binary BVH's node ids.
struct TraversalRecord {
  /// Every node event, in walk order: the root's box test, then for each node
  /// entered its Enter step and the tests of its child boxes; culls where the
  /// walk pops a node it skips. (A 8-wide node is named by the binary node at
  /// its top; its children's boxes are tested together.)
  std::vector<TraversalStep> steps;
  uint32_t prims_tested = 0;
  /// The leaf whose primitive is the ray's hit (closest hit, or a shadow ray's
  /// occluder); kNoNode for a miss, a plane or a walk without a structure.
  uint32_t hit_leaf = kNoNode;
  /// Early termination cut the walk short: nodes were culled by a closer hit, or
  /// an any-hit (shadow) query stopped at its first occluder.
  bool early_terminated = false;

  /// Nodes entered, in order.
  std::vector<uint32_t> nodes() const;
  /// Boxes tested against the ray: the root's, then every child box of each
  /// entered node, hit or missed (so usually more than the nodes entered).
  uint32_t boxes_tested() const;
  uint32_t culled() const;  ///< Nodes skipped because a closer hit was already found.
};

/// The diffuse and specular terms one light adds at a hit.
struct LightTerms {
  int light = -1;
  Color diffuse{0.0f}, specular{0.0f};
};

/// One node of the ray tree.
struct RayRecord {
  int id = 0;
  int parent = -1;
  std::vector<int> children;
  RayKind kind = RayKind::Primary;
  int depth = 0;
  int sample = 0;
  Vec3 origin{0.0f}, dir{0.0f};
  float tmin = 0.0f, tmax = kInfinity;
  Color weight{0.0f};  ///< Weight of this ray in the pixel.
  Color color{0.0f};   ///< Radiance it returned (shadow rays: light arriving, 0 if occluded).

  // Closest hit (not for shadow rays).
  bool hit = false;
  float t = kInfinity;
  Vec3 point{0.0f}, ng{0.0f}, ns{0.0f};
  uint32_t object = ~0u, prim = ~0u, material = ~0u;

  // Shadow rays.
  int light = -1;
  bool occluded = false;
  uint32_t occluder = ~0u;

  // Refraction at this ray's hit (dielectric materials).
  bool has_refraction = false;
  RefractionEvent refraction{};

  /// Local illumination at the hit: the ambient term and, per light reaching
  /// it, the diffuse and specular terms (as the integrator adds them).
  Color ambient{0.0f};
  std::vector<LightTerms> lights;

  /// Not traced (origin, direction, weight and, for shadow rays, light are the
  /// ray's that would have been; color 0, no walk).
  bool skipped = false;
  SkipReason skip_reason = SkipReason::Backfacing;

  TraversalRecord traversal;
};

/// Integrator policy that records the ray tree of the samples it is told to.
class RayTreeRecorder {
 public:
  static constexpr bool kActive = true;

  /// Record only this sample (-1: every sample).
  explicit RayTreeRecorder(int only_sample = -1) : only_sample_(only_sample) {}

  std::vector<RayRecord> rays;

  struct Observer : TraversalHooks {
    static constexpr bool kActive = true;
    TraversalRecord* rec;  ///< Null for rays of samples that are not recorded.
    uint32_t entered = kNoNode;
    explicit Observer(TraversalRecord* r) : rec(r) {}
    void step(TraversalStep::Kind kind, uint32_t node) {
      if (rec) rec->steps.push_back({kind, node});
    }
    void on_node(uint32_t node) {
      entered = node;
      step(TraversalStep::Kind::Enter, node);
    }
    void on_box_test(uint32_t node, bool hit) {
      step(hit ? TraversalStep::Kind::BoxHit : TraversalStep::Kind::BoxMiss, node);
    }
    void on_cull(uint32_t node) {
      step(TraversalStep::Kind::Cull, node);
      if (rec) rec->early_terminated = true;
    }
    void on_prim_test(uint32_t) {
      if (rec) rec->prims_tested++;
    }
    void on_prim_hit(uint32_t prim) {
      if (rec) rec->hit_leaf = prim == kPrimOutsideStructure ? kNoNode : entered;
    }
  };

  void begin_sample(int sample) {
    sample_ = sample;
    enabled_ = only_sample_ < 0 || only_sample_ == sample;
  }
  int begin_ray(RayKind kind, const Ray& ray, int depth, const Color& weight, int parent) {
    if (!enabled_) return -1;
    RayRecord r;
    r.id = int(rays.size());
    r.parent = parent;
    r.kind = kind;
    r.depth = depth;
    r.sample = sample_;
    r.origin = ray.origin;
    r.dir = ray.dir;
    r.tmax = ray.tmax;
    r.weight = weight;
    if (parent >= 0) rays[size_t(parent)].children.push_back(r.id);
    rays.push_back(std::move(r));
    return int(rays.size()) - 1;
  }
  Observer traversal(int node) {
    return Observer{node >= 0 ? &rays[size_t(node)].traversal : nullptr};
  }
  void on_hit(int node, const SurfaceHit& h) {
    if (node < 0) return;
    RayRecord& r = rays[size_t(node)];
    r.hit = true;
    r.t = h.t;
    r.point = h.p;
    r.ng = h.ng;
    r.ns = h.ns;
    r.object = h.object;
    r.prim = h.prim;
    r.material = h.material;
  }
  void on_shadow(int node, uint32_t light, bool occluded, uint32_t occluder) {
    if (node < 0) return;
    RayRecord& r = rays[size_t(node)];
    r.light = int(light);
    r.occluded = occluded;
    r.occluder = occluder;
    if (occluded) r.traversal.early_terminated = true;
  }
  void on_refraction(int node, const RefractionEvent& e) {
    if (node < 0) return;
    rays[size_t(node)].has_refraction = true;
    rays[size_t(node)].refraction = e;
  }
  void on_ambient(int node, const Color& ambient) {
    if (node >= 0) rays[size_t(node)].ambient = ambient;
  }
  void on_light_terms(int node, uint32_t light, const Color& diffuse, const Color& specular) {
    if (node >= 0) rays[size_t(node)].lights.push_back({int(light), diffuse, specular});
  }
  void skip_ray(RayKind kind, const Ray& ray, int depth, const Color& weight, int parent,
                SkipReason why, int light) {
    const int node = begin_ray(kind, ray, depth, weight, parent);
    if (node < 0) return;
    rays[size_t(node)].skipped = true;
    rays[size_t(node)].skip_reason = why;
    rays[size_t(node)].light = light;
  }
  void end_ray(int node, const Color& c) {
    if (node >= 0) rays[size_t(node)].color = c;
  }

 private:
  int only_sample_ = -1;
  int sample_ = 0;
  bool enabled_ = true;
};

/// The recorded ray tree of one pixel.
struct PixelRecord {
  int x = 0, y = 0;
  int sample = -1;  ///< The recorded sample, -1 for all.
  int samples = 1;  ///< N: the samples come from an N x N grid (all of it unless adaptive).
  /// Samples the pixel took: N x N, or fewer with adaptive sampling.
  int samples_taken = 1;
  Color color{0.0f};  ///< The pixel's color, exactly as in a full render.
  std::vector<RayRecord> rays;
};

}  // namespace rayscope
