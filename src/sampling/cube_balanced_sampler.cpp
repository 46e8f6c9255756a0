#include "emlt/sampling/cube_balanced_sampler.h"

#include <algorithm>
#include <cmath>

namespace emlt {

std::array<double, CubeEnvironment::kFaces> cube_face_weights(const CubeEnvironment& cube,
                                                              const CubeReceiver& receiver,
                                                              CubeSamplerFault fault) {
  std::array<double, CubeEnvironment::kFaces> mu{};
  double total = 0.0;
  for (int f = 0; f < CubeEnvironment::kFaces; ++f) {
    if (!(cube.face_mass(f) > 0.0)) continue;  // nothing to draw there, whatever F_f says
    double form = 1.0;                         // Mass: no cosine bound
    if (receiver.balance == CubeFaceBalance::Receiver) {
      form = 0.0;
      for (const Vec3& c : cube.corners(f)) {
        const double cosine = double(glm::dot(receiver.normal, c));
        form += receiver.two_sided ? std::abs(cosine) : std::max(cosine, 0.0);
      }
    }
    mu[size_t(f)] = receiver.balance == CubeFaceBalance::Uniform       ? 1.0
                    : fault == CubeSamplerFault::FaceWeightWithoutMass ? form
                                                                       : form * cube.face_mass(f);
    total += mu[size_t(f)];
  }
  if (!(total > 0.0)) return {};
  for (double& m : mu) m /= total;
  return mu;
}

float cube_balanced_pdf(const CubeEnvironment& cube, const CubeReceiver& receiver, const Vec3& w,
                        CubeSamplerFault fault) {
  const int face = CubeEnvironment::face_of(w);
  const double mu = cube_face_weights(cube, receiver, fault)[size_t(face)];
  if (!(mu > 0.0)) return 0.0f;
  const double in_face = double(cube.pdf_in_face(face, w));
  return float(fault == CubeSamplerFault::PdfWithoutFaceChoice ? in_face : mu * in_face);
}

std::optional<Vec3> sample_cube_balanced(const CubeEnvironment& cube, const CubeReceiver& receiver,
                                         const Vec2& u, float* pdf, CubeSamplerFault fault) {
  if (pdf) *pdf = 0.0f;
  const auto mu = cube_face_weights(cube, receiver, fault);
  // The face by inverting the faces' cumulative weights with u.x; what is left of u.x inside
  // the face's interval drives the column (so two numbers suffice, as for every light).
  double below = 0.0;
  int face = -1;
  for (int f = 0; f < CubeEnvironment::kFaces; ++f) {
    if (!(mu[size_t(f)] > 0.0)) continue;
    face = f;  // the last face with weight takes what rounding leaves above the total
    if (double(u.x) < below + mu[size_t(f)]) break;
    below += mu[size_t(f)];
  }
  if (face < 0) return std::nullopt;
  const double rest = (double(u.x) - below) / mu[size_t(face)];
  const Vec2 u_face(float(std::clamp(rest, 0.0, double(std::nextafter(1.0f, 0.0f)))), u.y);
  const Vec3 w = cube.sample_in_face(face, u_face, nullptr);
  // The density evaluated at the direction returned, so that every consumer (MIS weights
  // here, BSDF-sampled hits of the sky later) sees the same number for the same direction.
  const float density = cube_balanced_pdf(cube, receiver, w, fault);
  if (!(density > 0.0f) || !std::isfinite(density)) return std::nullopt;
  if (pdf) *pdf = density;
  return w;
}

EnvironmentSampling environment_sampling(const Scene& scene, EnvSampler kind, const SurfaceHit& hit,
                                         const Vec3& wo, CubeFaceBalance balance, int resolution) {
  EnvironmentSampling sampling;
  if (kind != EnvSampler::CubeBalanced || !scene.environment()) return sampling;
  sampling.cube = scene.cube_environment(resolution);
  const Vec3 n = hit.shading_normal;
  const float side = glm::dot(n, wo);
  sampling.receiver.normal = side < 0.0f ? -n : n;
  sampling.receiver.balance = balance;
  // A transmitting BSDF sees both hemispheres; so does a grazing wo, whose side is unclear.
  sampling.receiver.two_sided = (hit.bsdf->lobes() & kLobeTransmission) != 0 || side == 0.0f;
  return sampling;
}

namespace {

DirectLightSample environment_sample(const EnvironmentLight& environment, const Vec3& ref,
                                     const Vec3& wi, float pdf) {
  DirectLightSample sample;
  sample.position = ref + wi;
  sample.wi = wi;
  sample.distance = kInfinity;
  sample.radiance = environment.radiance(wi);
  sample.pdf = pdf;
  return sample;
}

}  // namespace

std::optional<DirectLightSample> sample_environment_direct(const EnvironmentLight& environment,
                                                           const EnvironmentSampling& sampling,
                                                           const Vec3& ref, const Vec2& u) {
  if (!sampling.cube) return environment.sample_direct(ref, u);
  float pdf = 0.0f;
  const auto wi = sample_cube_balanced(*sampling.cube, sampling.receiver, u, &pdf);
  if (!wi) return std::nullopt;
  return environment_sample(environment, ref, *wi, pdf);
}

std::optional<DirectLightSample> sample_environment_face(const EnvironmentLight& environment,
                                                         const EnvironmentSampling& sampling,
                                                         const Vec3& ref, int face, const Vec2& u) {
  const Vec3 wi = sampling.cube->sample_in_face(face, u, nullptr);
  const float pdf = cube_balanced_pdf(*sampling.cube, sampling.receiver, wi);
  if (!(pdf > 0.0f) || !std::isfinite(pdf)) return std::nullopt;
  return environment_sample(environment, ref, wi, pdf);
}

float environment_direct_pdf(const EnvironmentLight& environment,
                             const EnvironmentSampling& sampling, const Vec3& w) {
  if (!sampling.cube) return environment.pdf_direction(w);
  return cube_balanced_pdf(*sampling.cube, sampling.receiver, w);
}

}  // namespace emlt
