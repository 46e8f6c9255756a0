#include "emlt/scene/cube_environment.h"

#include <algorithm>
#include <cmath>

#include "emlt/scene/cube_map_environment.h"

namespace emlt {

namespace {

// The solid angle of the face rectangle [0, x] x [0, y] seen from the cube's centre (the
// face at distance 1): atan(x y / sqrt(1 + x^2 + y^2)). A texel's exact solid angle is
// then the inclusion-exclusion of its four corners.
double corner_solid_angle(double x, double y) {
  return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0));
}

// Face coordinate of texel edge k of n (k in [0, n]).
double edge(int resolution, int k) {
  return -1.0 + 2.0 * double(k) / double(resolution);
}

int chosen_resolution(const EnvironmentLight& environment, int requested) {
  if (requested > 0) return requested;
  if (const auto* map = dynamic_cast<const EnvironmentMap*>(&environment))
    return std::clamp(map->map().width / 4, 8, 512);
  // A cube map's own texels (its table then matches them when the map is not rotated).
  if (const auto* cube = dynamic_cast<const CubeMapEnvironment*>(&environment))
    return cube->face_resolution();
  return 8;
}

}  // namespace

double CubeEnvironment::texel_solid_angle(int resolution, int i, int j) {
  const double x0 = edge(resolution, i), x1 = edge(resolution, i + 1);
  const double y0 = edge(resolution, j), y1 = edge(resolution, j + 1);
  return corner_solid_angle(x1, y1) - corner_solid_angle(x0, y1) - corner_solid_angle(x1, y0) +
         corner_solid_angle(x0, y0);
}

double CubeEnvironment::texel_solid_angle_midpoint(int resolution, int i, int j) {
  const double side = 2.0 / double(resolution);
  const double u = -1.0 + side * (double(i) + 0.5), v = -1.0 + side * (double(j) + 0.5);
  return side * side / std::pow(1.0 + u * u + v * v, 1.5);
}

int CubeEnvironment::face_of(const Vec3& w, Vec2* uv) {
  const Vec3 a = glm::abs(w);
  const int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  const float major = w[axis];
  if (uv) {
    const float inv = 1.0f / std::abs(major);
    *uv = Vec2(w[(axis + 1) % 3] * inv, w[(axis + 2) % 3] * inv);
  }
  return 2 * axis + (major < 0.0f ? 1 : 0);
}

Vec3 CubeEnvironment::direction(int face, const Vec2& uv) {
  const int axis = face / 2;
  Vec3 d(0.0f);
  d[axis] = (face % 2) ? -1.0f : 1.0f;
  d[(axis + 1) % 3] = uv.x;
  d[(axis + 2) % 3] = uv.y;
  return glm::normalize(d);
}

CubeEnvironment::CubeEnvironment(const EnvironmentLight& environment, int resolution)
    : resolution_(chosen_resolution(environment, resolution)) {
  const int n = resolution_;
  // A texel's luminance is the mean of 3 x 3 lookups on its centre, edge midpoints and
  // corners: the lookups on its boundary give weight to a texel that a bright feature only
  // touches, so that the table misses as little of the map as it can (a texel the table
  // misses is still found by BSDF sampling, which MIS keeps unbiased).
  constexpr int kTaps = 3;
  for (int face = 0; face < kFaces; ++face) {
    std::vector<float> weights(size_t(n) * size_t(n));
    double mass = 0.0;
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        double sum = 0.0;
        for (int b = 0; b < kTaps; ++b) {
          for (int a = 0; a < kTaps; ++a) {
            const Vec2 uv(float(edge(n, i) + (2.0 / n) * a / (kTaps - 1)),
                          float(edge(n, j) + (2.0 / n) * b / (kTaps - 1)));
            sum += double(luminance(environment.radiance(direction(face, uv))));
          }
        }
        const double lum = sum / double(kTaps * kTaps);
        const double w = (std::isfinite(lum) && lum > 0.0 ? lum : 0.0) * texel_solid_angle(n, i, j);
        weights[size_t(j) * size_t(n) + size_t(i)] = float(w);
        mass += w;
      }
    }
    face_mass_[size_t(face)] = mass;
    tables_[size_t(face)] = Distribution2D(weights, size_t(n), size_t(n));
    const Vec2 c[4] = {{-1.0f, -1.0f}, {1.0f, -1.0f}, {-1.0f, 1.0f}, {1.0f, 1.0f}};
    for (int k = 0; k < 4; ++k) corners_[size_t(face)][size_t(k)] = direction(face, c[k]);
  }
}

Vec3 CubeEnvironment::sample_in_face(int face, const Vec2& u, float* pdf) const {
  float pdf_square = 0.0f;  // density per unit area of [0, 1)^2
  const Vec2 st = tables_[size_t(face)].sample(u, &pdf_square);
  const Vec2 uv = 2.0f * st - 1.0f;
  const float r2 = 1.0f + uv.x * uv.x + uv.y * uv.y;
  // du dv = 4 ds dt and dw = r2^(-3/2) du dv.
  if (pdf) *pdf = pdf_square * 0.25f * r2 * std::sqrt(r2);
  return direction(face, uv);
}

float CubeEnvironment::pdf_in_face(int face, const Vec3& w) const {
  const Distribution2D& table = tables_[size_t(face)];
  if (table.empty_mass()) return 0.0f;
  Vec2 uv;
  face_of(w, &uv);
  const Vec2 st = glm::clamp(0.5f * (uv + 1.0f), Vec2(0.0f), Vec2(std::nextafter(1.0f, 0.0f)));
  const float r2 = 1.0f + uv.x * uv.x + uv.y * uv.y;
  return table.pdf(st) * 0.25f * r2 * std::sqrt(r2);
}

}  // namespace emlt
