#pragma once
// An environment given as a cube map: six square images of one size, in the order +x, -x,
// +y, -y, +z, -z. A world direction (after the map's rotation) looks up the texel OpenGL's
// cube-map selection rule gives it (the OpenGL specification's table of major axis ->
// face and (s, t)), so a cube map made for an OpenGL sky box, or by the tools that export
// them, reads the same here: direction w shows what texture(samplerCube, w) would.
//
//   major axis  face  sc   tc        s = (sc / |ma| + 1) / 2,  t = (tc / |ma| + 1) / 2
//   +x          0     -z   -y        texel column s n - 1/2, row t n - 1/2 (row 0 at the
//   -x          1     +z   -y        top of the image), bilinear within the face, clamped
//   +y          2     +x   +z        at its edges
//   -y          3     +x   -z
//   +z          4     +x   -y
//   -z          5     -x   -y
//
// Importance sampling: a CubeEnvironment table (texels weighted by luminance x exact solid
// angle) at the faces' own resolution, the face drawn in proportion to its mass; for an
// unrotated map its texels are the input's texels.
#include <array>
#include <memory>

#include "emlt/scene/cube_environment.h"
#include "emlt/scene/environment.h"

namespace emlt {

class CubeMapEnvironment final : public EnvironmentLight {
 public:
  static constexpr int kFaces = 6;

  // `faces`: +x, -x, +y, -y, +z, -z, each square and of one size (checked by the loader).
  CubeMapEnvironment(std::array<Image, kFaces> faces, float scale, const Mat3& to_world);

  Rgb power() const override;
  Rgb radiance(const Vec3& w) const override;
  Vec3 sample_direction(const Vec2& u, float* pdf) const override;
  float pdf_direction(const Vec3& w) const override;

  int face_resolution() const { return faces_[0].width; }

  // The face a map-space direction selects and its (s, t) in [0, 1]^2 (the table above).
  static int select_face(const Vec3& local, Vec2* st);

 private:
  Rgb lookup(int face, const Vec2& st) const;

  std::array<Image, kFaces> faces_;
  float scale_;
  Mat3 to_world_, to_local_;
  std::unique_ptr<CubeEnvironment> table_;  // in world space, built from radiance()
  std::array<double, kFaces> face_probability_{};
  Rgb average_radiance_{0.0f};
};

}  // namespace emlt
