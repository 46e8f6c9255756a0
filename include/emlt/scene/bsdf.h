#pragma once
// BSDF contract. All directions are unit vectors in the local shading frame (z = shading
// normal) and point away from the surface: wo towards where the path came from (the
// camera side for radiance transport), wi towards where it continues.
//
//   eval(wo, wi)   f(wo, wi) without the cosine factor; zero for delta lobes.
//   pdf(wo, wi)    solid-angle density with which sample(wo) yields wi; zero for deltas.
//   sample(wo)     picks wi. For a delta lobe `pdf` holds the discrete probability of
//                  choosing that lobe and `value` the delta's coefficient divided by
//                  |cos wi|, so `weight = value * |cos wi| / pdf` in every case.
//
// TransportMode::Importance is the adjoint BSDF used when tracing from lights: it differs
// from the radiance one only for refraction (no 1/eta^2 radiance compression).
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "emlt/core/frame.h"
#include "emlt/core/math.h"

namespace emlt {

enum class TransportMode : uint8_t { Radiance, Importance };

// Lobe classification. MLT path types ("L D S E") depend on kSpecular being set exactly
// when the sampled interaction is a Dirac delta.
enum LobeFlags : uint32_t {
  kLobeNone = 0,
  kLobeDiffuse = 1u << 0,
  kLobeGlossy = 1u << 1,
  kLobeSpecular = 1u << 2,  // delta distribution
  kLobeReflection = 1u << 3,
  kLobeTransmission = 1u << 4,
};

struct BsdfContext {
  Vec2 uv{0.0f};  // surface texture coordinates (for textured parameters)
  TransportMode mode = TransportMode::Radiance;
  // The mesh's per-vertex colours interpolated at the point (black without them), for
  // textures that read them (Mitsuba's `vertexcolors`).
  Rgb vertex_color{0.0f};
};

struct BsdfSample {
  Vec3 wi{0.0f};
  Rgb value{0.0f};      // f(wo, wi) (or the delta coefficient / |cos wi|)
  Rgb weight{0.0f};     // value * |cos wi| / pdf
  float pdf = 0.0f;     // solid angle density, or lobe probability for deltas
  float pdf_reverse = 0.0f;  // density of sampling wo from wi (same conventions)
  uint32_t lobe = kLobeNone;  // flags of the lobe that was sampled
  float eta = 1.0f;     // relative IOR crossed (1 for reflection)

  bool is_delta() const { return (lobe & kLobeSpecular) != 0; }
};

// The rough components of a BSDF as the manifold perturbation's offset manifolds see them
// (mutations/manifold_perturbation.h): the roughness of each non-Dirac component (Mitsuba's
// getRoughness: a microfacet lobe's alpha; infinity for a diffuse one or any the walk cannot
// treat as a mirror about a microfacet normal) and the interior/exterior index for the
// refracting ones.
struct RoughComponents {
  static constexpr int kMax = 2;
  int count = 0;
  float alpha[kMax] = {0.0f, 0.0f};
  float eta = 1.0f;
};

// A BSDF that is a Lambertian term diffuse / pi plus one normalised Phong lobe,
// specular (n + 2) / (2 pi) cos^n about wo's mirror direction, one-sided: the form the
// Bayesian direct-lighting estimator models in closed form (sampling/bmc_direct_estimator.h).
struct PhongLobes {
  Rgb diffuse{0.0f};
  Rgb specular{0.0f};
  float exponent = 0.0f;
};

class Bsdf {
 public:
  virtual ~Bsdf() = default;

  virtual Rgb eval(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const = 0;
  virtual float pdf(const BsdfContext& ctx, const Vec3& wo, const Vec3& wi) const = 0;
  // u_lobe chooses between lobes, u picks the direction within the lobe.
  virtual std::optional<BsdfSample> sample(const BsdfContext& ctx, const Vec3& wo, float u_lobe,
                                           const Vec2& u) const = 0;
  // Union of the flags of every lobe this BSDF has.
  virtual uint32_t lobes() const = 0;
  virtual std::string name() const = 0;
  // Whether the BSDF changes when the shading frame turns about the normal (anisotropic
  // roughness). Only then must a surface's frame follow dp/du as Mitsuba's does; any other
  // BSDF sees the same expectation in any frame, and keeps the normal's own.
  virtual bool is_anisotropic() const { return false; }
  // By default every non-Dirac component is diffuse-like (it always ends a manifold chain).
  virtual RoughComponents rough_components(const BsdfContext&) const {
    RoughComponents r;
    if ((lobes() & (kLobeDiffuse | kLobeGlossy)) != 0) {
      r.count = 1;
      r.alpha[0] = std::numeric_limits<float>::infinity();
    }
    return r;
  }

  // This BSDF as PhongLobes at a point, or nothing when it is not of that form.
  virtual std::optional<PhongLobes> phong_lobes(const BsdfContext&) const { return std::nullopt; }

  bool has_delta_lobe() const { return (lobes() & kLobeSpecular) != 0; }
  bool is_purely_delta() const {
    return (lobes() & (kLobeDiffuse | kLobeGlossy)) == 0 && has_delta_lobe();
  }
};

using BsdfPtr = std::shared_ptr<const Bsdf>;

}  // namespace emlt
