#pragma once
// `--env-sampler cube-balanced`: Lu's per-receiver cube-face environment sampler (thesis
// 004, chapter 3). The environment is sampled face by face (cube_environment.h), and the
// faces share the samples in proportion to
//
//   mu_f(n) = F_f(n) I_f / sum_g F_g(n) I_g,   F_f(n) = sum over the face's four normalised
//   corners c of max(<n, c>, 0)                                               (Eq. 3.4)
//
// I_f being the face's luminance x solid angle mass. Reading of Eq. 3.4: F_f is not a form
// factor, only a bound on where the cosine is positive: a face is the convex hull of its
// corners, so if no corner is above the receiver's horizon no direction of the face is, and
// mu_f = 0 only for faces that cannot reach the receiver. For a BSDF that transmits, light
// from both sides counts and F_f uses |<n, c>| instead (positive on every face: the four
// corners of a face never all lie on a plane through the centre), so no face is ever
// dropped there.
//
// Sample allocation: `direct`, which draws several light samples per point, gives each face
// the thesis's fractional count (Eqs. 3.5-3.6, fractional_light_counts.h). The path tracer
// and the chains' direct pass draw one light sample per vertex, so there (and under
// --env-face-counts sampled) the counts become their one-sample counterpart: the face is
// drawn with probability mu_f, then a direction from its table. The density is
// mu_f(n) pdf(w | f) (Eq. 3.2's denominator: faces are disjoint, so the mixture over faces
// has one term), which is what light sampling reports to MIS, so the balance heuristic
// against BSDF sampling is exactly Eq. 3.7's. Both are unbiased with the same expected
// counts per face; only the fractional counts stratify the faces.
//
// The receiver's normal is the shading normal turned to the side the light leaves towards
// (wo), since a reflecting BSDF only sees the hemisphere on wo's side.
#include <optional>

#include "emlt/scene/cube_environment.h"
#include "emlt/scene/light.h"
#include "emlt/scene/scene.h"
#include "emlt/settings/settings.h"

namespace emlt {

struct CubeReceiver {
  Vec3 normal{0.0f, 0.0f, 1.0f};  // unit
  bool two_sided = false;         // the BSDF transmits: both hemispheres count
  // Eq. 3.4 (Receiver), or one of the comparisons (settings.h), which ignore the normal.
  CubeFaceBalance balance = CubeFaceBalance::Receiver;
};

// Deliberate mistakes for the tests that must notice them.
enum class CubeSamplerFault {
  None,
  FaceWeightWithoutMass,  // mu_f from F_f alone (the face's I_f left out)
  PdfWithoutFaceChoice,   // the density forgets the face's probability mu_f
};

// Eq. 3.4's mu_f for the six faces (or the receiver's comparison balance); all zero when no
// face with mass faces the receiver.
std::array<double, CubeEnvironment::kFaces> cube_face_weights(
    const CubeEnvironment& cube, const CubeReceiver& receiver,
    CubeSamplerFault fault = CubeSamplerFault::None);

// A direction drawn from sum_f mu_f pdf(w | f): u.x picks the face and, rescaled inside it,
// the table's column; u.y the row. *pdf receives cube_balanced_pdf at the direction (0, and
// no direction, when the receiver sees no face with mass).
std::optional<Vec3> sample_cube_balanced(const CubeEnvironment& cube, const CubeReceiver& receiver,
                                         const Vec2& u, float* pdf,
                                         CubeSamplerFault fault = CubeSamplerFault::None);
float cube_balanced_pdf(const CubeEnvironment& cube, const CubeReceiver& receiver, const Vec3& w,
                        CubeSamplerFault fault = CubeSamplerFault::None);

// How the direct-lighting estimators sample the environment at one shading point: with
// `cube` null, the environment's own (lat-long) table; otherwise the cube-balanced sampler
// for `receiver`.
struct EnvironmentSampling {
  const CubeEnvironment* cube = nullptr;
  CubeReceiver receiver{};
};

// The sampling `kind` asks for at `hit`, light leaving towards wo (world, unit).
EnvironmentSampling environment_sampling(const Scene& scene, EnvSampler kind, const SurfaceHit& hit,
                                         const Vec3& wo,
                                         CubeFaceBalance balance = CubeFaceBalance::Receiver,
                                         int resolution = 0);

// The environment's direct-light sample and its density (light selection excluded) under
// `sampling`.
std::optional<DirectLightSample> sample_environment_direct(const EnvironmentLight& environment,
                                                           const EnvironmentSampling& sampling,
                                                           const Vec3& ref, const Vec2& u);
// The environment's direct-light sample drawn from one face's table (Eq. 3.5's per-face
// samples; `sampling` must be cube-balanced and the face must have mass). Its density is
// reported as the cube-balanced one, mu_f pdf(w | f), so that its MIS weight is the one
// Eq. 3.7 gives a face sample.
std::optional<DirectLightSample> sample_environment_face(const EnvironmentLight& environment,
                                                         const EnvironmentSampling& sampling,
                                                         const Vec3& ref, int face, const Vec2& u);
float environment_direct_pdf(const EnvironmentLight& environment,
                             const EnvironmentSampling& sampling, const Vec3& w);

}  // namespace emlt
