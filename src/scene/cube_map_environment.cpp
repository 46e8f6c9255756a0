#include "emlt/scene/cube_map_environment.h"

#include <algorithm>
#include <cmath>

namespace emlt {

CubeMapEnvironment::CubeMapEnvironment(std::array<Image, kFaces> faces, float scale,
                                       const Mat3& to_world)
    : faces_(std::move(faces)), scale_(scale), to_world_(to_world),
      to_local_(glm::inverse(to_world)) {
  for (Image& face : faces_) {
    for (Rgb& texel : face.pixels) {
      for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(texel[c]) || texel[c] < 0.0f) texel[c] = 0.0f;
      }
    }
  }
  if (!(scale_ >= 0.0f) || !std::isfinite(scale_)) scale_ = 0.0f;
  const int n = face_resolution();

  // Mean radiance over the sphere, from the input texels and their exact solid angles
  // (for light selection). Face (s, t) grids are the tangent-plane grids CubeEnvironment
  // integrates over, up to a flip or transpose, which leaves the solid angles alone.
  double weighted[3] = {0.0, 0.0, 0.0};
  for (const Image& face : faces_) {
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        const double omega = CubeEnvironment::texel_solid_angle(n, x, y);
        for (int c = 0; c < 3; ++c) weighted[c] += omega * double(face.at(x, y)[c]);
      }
    }
  }
  for (int c = 0; c < 3; ++c) average_radiance_[c] = float(scale_ * weighted[c] / (4.0 * kPi));

  // The sampling table reads radiance() in world space, so the dynamic type must be
  // complete: built here, in the constructor's body.
  table_ = std::make_unique<CubeEnvironment>(*this, n);
  double total = 0.0;
  for (int f = 0; f < kFaces; ++f) total += table_->face_mass(f);
  for (int f = 0; f < kFaces; ++f)
    face_probability_[size_t(f)] = total > 0.0 ? table_->face_mass(f) / total : 0.0;
}

int CubeMapEnvironment::select_face(const Vec3& d, Vec2* st) {
  const Vec3 a = glm::abs(d);
  int face;
  float sc, tc, ma;
  if (a.x >= a.y && a.x >= a.z) {
    ma = a.x;
    face = d.x >= 0.0f ? 0 : 1;
    sc = d.x >= 0.0f ? -d.z : d.z;
    tc = -d.y;
  } else if (a.y >= a.z) {
    ma = a.y;
    face = d.y >= 0.0f ? 2 : 3;
    sc = d.x;
    tc = d.y >= 0.0f ? d.z : -d.z;
  } else {
    ma = a.z;
    face = d.z >= 0.0f ? 4 : 5;
    sc = d.z >= 0.0f ? d.x : -d.x;
    tc = -d.y;
  }
  if (st) *st = Vec2(0.5f * (sc / ma + 1.0f), 0.5f * (tc / ma + 1.0f));
  return face;
}

Rgb CubeMapEnvironment::lookup(int face, const Vec2& st) const {
  const Image& image = faces_[size_t(face)];
  const int n = image.width;
  // Texel centres at (i + 1/2) / n; clamped at the face's edges.
  const float x = st.x * float(n) - 0.5f, y = st.y * float(n) - 0.5f;
  const float x_floor = std::floor(x), y_floor = std::floor(y);
  const float fx = x - x_floor, fy = y - y_floor;
  const auto clamp = [n](float i) { return std::clamp(int(i), 0, n - 1); };
  const int x0 = clamp(x_floor), x1 = clamp(x_floor + 1.0f);
  const int y0 = clamp(y_floor), y1 = clamp(y_floor + 1.0f);
  return (1.0f - fy) * ((1.0f - fx) * image.at(x0, y0) + fx * image.at(x1, y0)) +
         fy * ((1.0f - fx) * image.at(x0, y1) + fx * image.at(x1, y1));
}

Rgb CubeMapEnvironment::power() const {
  // As the other environments: pi R^2 * 4 pi * (solid-angle mean radiance).
  return disk_.area() * 4.0f * kPi * average_radiance_;
}

Rgb CubeMapEnvironment::radiance(const Vec3& w) const {
  const Vec3 local = to_local_ * w;
  if (!(glm::length(local) > 0.0f)) return Rgb(0.0f);
  Vec2 st;
  const int face = select_face(local, &st);
  return scale_ * lookup(face, st);
}

Vec3 CubeMapEnvironment::sample_direction(const Vec2& u, float* pdf) const {
  // u.x picks the face and, rescaled within the face's share, the column; u.y the row.
  double cumulative = 0.0;
  int face = -1;
  float u_within = 0.0f;
  for (int f = 0; f < kFaces; ++f) {
    const double p = face_probability_[size_t(f)];
    if (p > 0.0 && double(u.x) < cumulative + p) {
      face = f;
      u_within = float(std::min((double(u.x) - cumulative) / p, double(std::nextafter(1.0f, 0.0f))));
      break;
    }
    cumulative += p;
  }
  if (face < 0) {  // u.x at the top of the last non-empty face's share, or an empty map
    for (int f = kFaces - 1; f >= 0 && face < 0; --f)
      if (face_probability_[size_t(f)] > 0.0) face = f, u_within = std::nextafter(1.0f, 0.0f);
    if (face < 0) {
      if (pdf) *pdf = 0.0f;
      return Vec3(0.0f, 1.0f, 0.0f);
    }
  }
  const Vec3 w = table_->sample_in_face(face, Vec2(u_within, u.y), nullptr);
  // As EnvironmentMap: the density from the returned direction, so that every consumer sees
  // the same bits for the same direction.
  if (pdf) *pdf = pdf_direction(w);
  return w;
}

float CubeMapEnvironment::pdf_direction(const Vec3& w) const {
  if (!(glm::length(w) > 0.0f)) return 0.0f;
  const int face = CubeEnvironment::face_of(w);
  const double p = face_probability_[size_t(face)];
  if (!(p > 0.0)) return 0.0f;
  const float pdf = float(p) * table_->pdf_in_face(face, w);
  return std::isfinite(pdf) ? pdf : 0.0f;
}

}  // namespace emlt
