#pragma once
// An environment light resampled onto the six faces of a cube, each face with its own 2D
// piecewise-constant sampling table: the representation Lu's cube-face sampler works on
// (thesis 004, chapter 3, section 3.3.2).
//
// Face f = 2a + (negative ? 1 : 0) looks along axis a (x, y, z) with sign +-1; a direction on
// it is sign e_a + u e_{a+1} + v e_{a+2} (indices mod 3), (u, v) in [-1, 1]^2. The cube is in
// world space (it reads EnvironmentLight::radiance with world directions), so a rotated
// environment needs no rotation here.
//
// Texel weights are luminance x exact texel solid angle (the thesis's section 3.3.3 assumes
// its texels already hold flux; for a radiance map the solid angle must be multiplied in).
// Within a face, directions are drawn piecewise-constant in (u, v) (the thesis's "practical"
// choice, Eq. 3.13, which keeps the CDF inversion exact); the solid-angle density is then
// P(texel) / (texel area in u,v) x (1 + u^2 + v^2)^(3/2), evaluated exactly at the
// direction (dw = (1 + u^2 + v^2)^(-3/2) du dv), so nothing is approximated in the pdf.
//
// Input: any environment light, read through its radiance: a lat-long map, a constant
// colour, a sky model (rasterised to lat-long), or a cube map (cube_map_environment.h),
// whose own face resolution is then the default.
#include <array>
#include <vector>

#include "emlt/core/distribution.h"
#include "emlt/scene/environment.h"

namespace emlt {

class CubeEnvironment {
 public:
  static constexpr int kFaces = 6;

  // `resolution` texels per face edge (> 0); 0 chooses it from the environment: a lat-long
  // map W wide has about W/4 texels per quarter turn at its equator, so W/4 (within [8,
  // 512]); a cube map its own face size; a constant sky gets 8.
  explicit CubeEnvironment(const EnvironmentLight& environment, int resolution = 0);

  int resolution() const { return resolution_; }

  // Exact solid angle of texel (i, j) (column i along u, row j along v) of a face with
  // `resolution` texels per edge: the closed form of the integral of
  // (1 + u^2 + v^2)^(-3/2) du dv over the texel (section 3.3.3's "brute force" integral).
  static double texel_solid_angle(int resolution, int i, int j);
  // The midpoint rule for the same integral (the thesis's Eq. 3.13 approximation).
  static double texel_solid_angle_midpoint(int resolution, int i, int j);

  // The face a direction (any length > 0) falls on, and its face coordinates (u, v).
  static int face_of(const Vec3& w, Vec2* uv = nullptr);
  // The unit direction through face point (u, v).
  static Vec3 direction(int face, const Vec2& uv);
  // The four corners of a face, normalised (Eq. 3.4's c_i).
  const std::array<Vec3, 4>& corners(int face) const { return corners_[size_t(face)]; }

  // I_f: the face's table mass, luminance x solid angle summed over its texels (an estimate
  // of the integral of the luminance over the face).
  double face_mass(int face) const { return face_mass_[size_t(face)]; }

  // A direction on `face` drawn from its table, and its solid-angle density given the face.
  // The face must have mass.
  Vec3 sample_in_face(int face, const Vec2& u, float* pdf) const;
  // Density of sample_in_face at w given the face w falls on (0 if that face is empty).
  float pdf_in_face(int face, const Vec3& w) const;

 private:
  int resolution_ = 8;
  std::array<Distribution2D, kFaces> tables_;
  std::array<double, kFaces> face_mass_{};
  std::array<std::array<Vec3, 4>, kFaces> corners_{};
};

}  // namespace emlt
