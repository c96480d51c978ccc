// The Whitted integrator (lecture: "Recursive ray tracing"): at each hit, Phong
// local illumination from every light whose shadow ray is unobstructed, plus
// mirror reflection and Fresnel-weighted refraction traced recursively up to a
// maximum depth, skipping secondary rays whose weight within their sample is
// below a cutoff.
//
// The integrator is a template on a Recorder policy. NullRecorder (kActive ==
// false) compiles every recording hook away; a recording policy receives the
// whole ray tree of a pixel (recorder.h).
#pragma once

#include "rayscope/material.h"
#include "rayscope/ray.h"
#include "rayscope/render_settings.h"
#include "rayscope/scene.h"
#include "rayscope/stats.h"

namespace rayscope {

/// Details of a refraction event, for recorders.
struct RefractionEvent {
  float n1, n2;
  float cos_incidence, cos_transmission;
  bool total_internal_reflection;
  float fresnel_reflect, fresnel_transmit;
};

/// Why a ray the lecture's algorithm would cast was not traced.
enum class SkipReason : uint8_t {
  Backfacing,    ///< Shadow ray: the light is behind the surface (N.L <= 0).
  Depth,         ///< Secondary ray: the parent is at the maximum depth.
  Contribution,  ///< Secondary ray: its weight is below the minimum contribution.
};
inline const char* to_string(SkipReason r) {
  switch (r) {
    case SkipReason::Backfacing:
      return "N.L <= 0";
    case SkipReason::Depth:
      return "depth limit";
    case SkipReason::Contribution:
      return "contribution cutoff";
  }
  return "?";
}

/// The recorder interface, with every hook empty. A recorder derives from it,
/// defines kActive = true and the hooks it needs (the others stay no-ops).
struct NullRecorder {
  static constexpr bool kActive = false;
  /// Called before each sample of a pixel.
  void begin_sample(int /*sample*/) {}
  /// A new ray; returns its node id. parent < 0 for the primary ray.
  int begin_ray(RayKind, const Ray&, int /*depth*/, const Color& /*weight*/, int /*parent*/) {
    return -1;
  }
  NullTraversalObserver traversal(int /*node*/) { return {}; }
  void on_hit(int /*node*/, const SurfaceHit&) {}
  void on_shadow(int /*node*/, uint32_t /*light*/, bool /*occluded*/, uint32_t /*occluder*/) {}
  void on_refraction(int /*node*/, const RefractionEvent&) {}
  /// Local illumination at the hit of ray `node`: the ambient term, then the
  /// diffuse and specular terms of each light that reaches it (as added to the
  /// ray's color; the terms of a light are multiplied out separately, so their
  /// sum may differ from the color's in the last bits).
  void on_ambient(int /*node*/, const Color& /*ambient*/) {}
  void on_light_terms(int /*node*/, uint32_t /*light*/, const Color& /*diffuse*/,
                      const Color& /*specular*/) {}
  /// A ray that is not traced (with the ray it would have been; light >= 0 for
  /// shadow rays).
  void skip_ray(RayKind, const Ray&, int /*depth*/, const Color& /*weight*/, int /*parent*/,
                SkipReason, int /*light*/) {}
  void end_ray(int /*node*/, const Color& /*returned*/) {}
};

/// The directions and normals shading uses at a hit reached along ray.dir:
/// d (unit ray direction), v = -d, and both normals turned to face the
/// incoming ray (ns falls back to ng where it faces away from v).
struct ShadingNormals {
  Vec3 d, v, ng, ns;
  bool front;  ///< The ray meets the side the geometric normal points to.
};
inline ShadingNormals shading_normals(const Ray& ray, const SurfaceHit& hit) {
  ShadingNormals s;
  s.d = glm::normalize(ray.dir);
  s.v = -s.d;
  s.front = glm::dot(s.d, hit.ng) < 0.0f;
  s.ng = s.front ? hit.ng : -hit.ng;
  s.ns = s.front ? hit.ns : -hit.ns;
  if (glm::dot(s.ns, s.v) <= 0.0f) s.ns = s.ng;
  return s;
}

/// A light as seen from a hit (normals from shading_normals()).
struct LightView {
  enum class Status : uint8_t {
    Absent,  ///< A point light at the hit itself: no direction, no light.
    Behind,  ///< Behind the surface (N.L <= 0): no shadow ray, no light.
    Facing,  ///< Lights the hit unless a shadow ray finds an occluder.
  };
  Status status;
  Vec3 l{0.0f};       ///< Unit direction toward the light.
  float dist = 0.0f;  ///< Distance to a point light; infinite for directional ones.
};
inline LightView light_view(const Light& light, const SurfaceHit& hit, const Vec3& ng,
                            const Vec3& ns) {
  LightView v{LightView::Status::Facing};
  if (light.type == Light::Type::Point) {
    const Vec3 to = light.position - hit.p;
    v.dist = glm::length(to);
    if (!(v.dist > 0.0f)) return LightView{LightView::Status::Absent};
    v.l = to / v.dist;
  } else {
    v.l = -glm::normalize(light.direction);
    v.dist = kInfinity;
  }
  if (glm::dot(ng, v.l) <= 0.0f || glm::dot(ns, v.l) <= 0.0f) v.status = LightView::Status::Behind;
  return v;
}

/// The shadow ray from a hit toward `light` (direction l from light_view()),
/// leaving the surface on the side of ng.
inline Ray shadow_ray(const SurfaceHit& hit, const Vec3& ng, const Light& light, const Vec3& l) {
  return light.type == Light::Type::Point ? spawn_ray_to(hit.p, hit.p_error, ng, light.position)
                                          : spawn_ray(hit.p, hit.p_error, ng, l);
}

/// Whether a recorder can follow rays traced in packets (render_block.h):
/// it defines kCountsPackets (StatsRecorder), counting their walks from the
/// packets' costs instead of observing each ray's walk.
template <class Recorder>
inline constexpr bool counts_packets = requires {
  requires Recorder::kCountsPackets;
};

/// kShadows == false: the scene has no lights, so no light loop and no shadow rays.
/// kSecondary == false: no reflective or refractive material, so no secondary rays.
template <class Recorder = NullRecorder, bool kShadows = true, bool kSecondary = true>
class WhittedIntegrator {
 public:
  WhittedIntegrator(const Scene& scene, const RenderSettings& settings, RayCounters& counters,
                    Recorder& recorder)
      : scene_(scene),
        settings_(settings),
        counters_(counters),
        rec_(recorder),
        cutoff_(settings.min_contribution /
                float(settings.sample_grid() * settings.sample_grid())) {}

  /// Radiance arriving along `ray`. `weight` is the ray's weight in the pixel
  /// (a primary ray of N x N samples has 1 / N^2).
  /// `first_hit`, when not null, receives the hit of this ray (for AOVs).
  /// `diff`, when not null, are the ray's differentials: the hit's textures
  /// are then box-filtered over its footprint (settings.texture_filter; given
  /// for primary rays only).
  Color trace(const Ray& ray, RayKind kind, int depth, const Color& weight, int parent,
              SurfaceHit* first_hit = nullptr, const RayDifferential* diff = nullptr) {
    int node = -1;
    if constexpr (Recorder::kActive) node = rec_.begin_ray(kind, ray, depth, weight, parent);
    PrimHit ph;
    bool found;
    if constexpr (Recorder::kActive) {
      auto obs = rec_.traversal(node);
      found = scene_.intersect(ray, ph, obs);
    } else {
      found = scene_.intersect(ray, ph);
    }
    if (!found) return traced(ray, kind, depth, weight, node, nullptr, first_hit, diff);
    const SurfaceHit hit = scene_.surface_hit(ray, ph);
    return traced(ray, kind, depth, weight, node, &hit, first_hit, diff);
  }

  /// trace() of a primary ray whose closest hit a packet found (`hit`, or
  /// null for a miss), with weight `weight`: the same color. A recorder sees
  /// the ray and its shadow rays without their walks (counts_packets). Bit li of
  /// `occluded` answers the shadow ray from the hit toward light li (lights
  /// whose shadow ray is traced: light_view() Facing and casts_shadows),
  /// which a packet traced too (render_block.h). Lights < kMaxPacketLights.
  Color trace_from_packet(const Ray& ray, const SurfaceHit* hit, const Color& weight,
                          SurfaceHit* first_hit, const RayDifferential* diff,
                          uint64_t occluded) requires(!Recorder::kActive ||
                                                      counts_packets<Recorder>) {
    int node = -1;
    if constexpr (Recorder::kActive) node = rec_.begin_ray(RayKind::Primary, ray, 0, weight, -1);
    primary_occluded_ = occluded;
    primary_answered_ = true;
    const Color c = traced(ray, RayKind::Primary, 0, weight, node, hit, first_hit, diff);
    primary_answered_ = false;
    return c;
  }

 private:
  // A ray whose closest hit is known (null: it escaped): counted, shaded.
  Color traced(const Ray& ray, RayKind kind, int depth, const Color& weight, int node,
               const SurfaceHit* hit, SurfaceHit* first_hit, const RayDifferential* diff) {
    counters_.rays[int(kind)]++;
    if (!hit) {
      if constexpr (Recorder::kActive) rec_.end_ray(node, scene_.background);
      return scene_.background;
    }
    if constexpr (Recorder::kActive) rec_.on_hit(node, *hit);
    if (first_hit) *first_hit = *hit;
    counters_.hits++;
    if (kind == RayKind::Primary) counters_.primary_hits++;
    Color c = shade(ray, *hit, depth, weight, node, diff);
    if constexpr (Recorder::kActive) rec_.end_ray(node, c);
    return c;
  }

  Color shade(const Ray& ray, const SurfaceHit& hit, int depth, const Color& weight, int node,
              const RayDifferential* diff) {
    const Material& m = scene_.materials[hit.material];
    const ShadingNormals sn = shading_normals(ray, hit);
    const Vec3 &d = sn.d, &v = sn.v, &ng = sn.ng, &ns = sn.ns;
    const bool front = sn.front;
    const Color albedo = hit.has_vertex_color ? hit.vertex_color
                         : diff && m.checker  ? filtered_albedo(m, footprint(*diff, hit.p, hit.ng))
                                              : material_color(m, hit.p, scene_.origin);
    const float opaque = std::max(0.0f, 1.0f - m.reflectivity - m.transparency);

    // Local illumination: ambient + (diffuse + specular) per visible light.
    Color c = opaque * m.ambient * albedo * scene_.ambient_light;
    if constexpr (Recorder::kActive) rec_.on_ambient(node, c);
    if constexpr (kShadows) shade_lights(hit, m, albedo, ng, ns, v, opaque, depth, weight, node, c);
    if constexpr (kSecondary) shade_secondary(hit, m, d, ng, ns, v, front, depth, weight, node, c);
    return c;
  }

  void shade_lights(const SurfaceHit& hit, const Material& m, const Color& albedo, const Vec3& ng,
                    const Vec3& ns, const Vec3& v, float opaque, int depth, const Color& weight,
                    int node, Color& c) {
    for (uint32_t li = 0; li < scene_.lights.size(); ++li) {
      const Light& light = scene_.lights[li];
      const LightView lv = light_view(light, hit, ng, ns);
      if (lv.status == LightView::Status::Absent) continue;
      const Vec3& l = lv.l;
      const float dist = lv.dist;
      if (lv.status == LightView::Status::Behind) {
        counters_.shadow_skipped_backfacing++;
        if constexpr (Recorder::kActive)
          rec_.skip_ray(RayKind::Shadow, shadow_ray(hit, ng, light, l), depth + 1, weight, node,
                        SkipReason::Backfacing, int(li));
        continue;
      }
      if (light.casts_shadows) {
        counters_.rays[int(RayKind::Shadow)]++;
        bool blocked;
        if (depth == 0 && primary_answered_) {
          blocked = (primary_occluded_ >> li) & 1u;
          if constexpr (Recorder::kActive) {
            const int sn = rec_.begin_ray(RayKind::Shadow, shadow_ray(hit, ng, light, l), depth + 1,
                                          weight, node);
            rec_.on_shadow(sn, li, blocked, ~0u);
            rec_.end_ray(sn, blocked ? Color(0.0f) : light.radiance_at(dist));
          }
        } else if constexpr (Recorder::kActive) {
          const Ray shadow = shadow_ray(hit, ng, light, l);
          uint32_t occluder = ~0u;
          int sn = rec_.begin_ray(RayKind::Shadow, shadow, depth + 1, weight, node);
          auto obs = rec_.traversal(sn);
          blocked = scene_.occluded(shadow, obs, &occluder);
          rec_.on_shadow(sn, li, blocked, occluder);
          rec_.end_ray(sn, blocked ? Color(0.0f) : light.radiance_at(dist));
        } else {
          blocked = scene_.occluded(shadow_ray(hit, ng, light, l));
        }
        if (blocked) {
          counters_.shadow_occluded++;
          continue;
        }
      }
      PhongTerms t = phong_terms(m, ns, l, v);
      const Color radiance = light.radiance_at(dist);
      c += radiance *
           (opaque * m.diffuse * t.diffuse * albedo + m.specular * t.specular * m.specular_color);
      if constexpr (Recorder::kActive)
        rec_.on_light_terms(node, li, radiance * (opaque * m.diffuse * t.diffuse * albedo),
                            radiance * (m.specular * t.specular * m.specular_color));
    }
  }

  Color filtered_albedo(const Material& m, const Footprint& f) const {
    return material_color_filtered(m, f.center, f.half_width, scene_.origin);
  }

  // Secondary rays: mirror reflection and Fresnel-split refraction.
  void shade_secondary(const SurfaceHit& hit, const Material& m, const Vec3& d, const Vec3& ng,
                       const Vec3& ns, const Vec3& v, bool front, int depth, const Color& weight,
                       int node, Color& c) {
    if (!m.reflective() && !m.refractive()) return;
    float w_reflect = m.reflectivity;
    float w_refract = 0.0f;
    Vec3 t_dir(0.0f);
    RefractionEvent ev{};
    if (m.refractive()) {
      // Entering when the ray meets the outside (front) of the surface.
      ev.n1 = front ? 1.0f : m.ior;
      ev.n2 = front ? m.ior : 1.0f;
      ev.cos_incidence = std::clamp(glm::dot(v, ns), 0.0f, 1.0f);
      ev.total_internal_reflection = !refract(d, ns, ev.n1, ev.n2, t_dir);
      if (!ev.total_internal_reflection && glm::dot(t_dir, ng) >= 0.0f)
        ev.total_internal_reflection = !refract(d, ng, ev.n1, ev.n2, t_dir);
      ev.fresnel_reflect =
          ev.total_internal_reflection ? 1.0f : fresnel_dielectric(ev.cos_incidence, ev.n1, ev.n2);
      ev.fresnel_transmit = 1.0f - ev.fresnel_reflect;
      ev.cos_transmission = ev.total_internal_reflection
                                ? 0.0f
                                : std::clamp(-glm::dot(glm::normalize(t_dir), ng), 0.0f, 1.0f);
      if (ev.total_internal_reflection) counters_.total_internal_reflections++;
      w_reflect += m.transparency * ev.fresnel_reflect;
      w_refract = m.transparency * ev.fresnel_transmit;
      if constexpr (Recorder::kActive) rec_.on_refraction(node, ev);
    }
    auto spawn_child = [&](float w, RayKind kind, const Vec3& dir) {
      if (w <= 0.0f) return;
      Color cw = weight * w;
      auto skip = [&](SkipReason why) {
        if constexpr (Recorder::kActive)
          rec_.skip_ray(kind, spawn_ray(hit.p, hit.p_error, ng, dir), depth + 1, cw, node, why, -1);
      };
      if (depth >= settings_.max_depth) {
        counters_.depth_cutoffs++;
        skip(SkipReason::Depth);
        return;
      }
      if (max_component(cw) < cutoff_) {
        counters_.weight_cutoffs++;
        skip(SkipReason::Contribution);
        return;
      }
      Ray child = spawn_ray(hit.p, hit.p_error, ng, dir);
      c += w * trace(child, kind, depth + 1, cw, node);
    };
    if (w_reflect > 0.0f) {
      Vec3 r = reflect(d, ns);
      if (glm::dot(r, ng) <= 0.0f) r = reflect(d, ng);  // never into the surface
      spawn_child(w_reflect, RayKind::Reflection, r);
    }
    if (w_refract > 0.0f) spawn_child(w_refract, RayKind::Refraction, t_dir);
  }

  const Scene& scene_;
  const RenderSettings& settings_;
  RayCounters& counters_;
  Recorder& rec_;
  /// min_contribution as a weight in the pixel: divided by the sample count.
  const float cutoff_;
  /// trace_from_packet(): the primary ray's shadow rays are answered by
  /// primary_occluded_ (bit per light).
  bool primary_answered_ = false;
  uint64_t primary_occluded_ = 0;
};

}  // namespace rayscope
