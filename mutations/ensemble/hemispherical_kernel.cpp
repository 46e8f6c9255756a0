// Great-arc ("linear hemispherical") transition kernel of Ensemble MLT (section 3.2,
// eq. 10): the stretch move of linear_kernel.cpp carried onto the sphere.
//
// The map. With the guide w2, the current direction w1 and W = angle(w1, w2), let u be the
// unit tangent at w2 pointing toward w1. The proposal is
//     w(lambda) = cos(lambda W) w2 + sin(lambda W) u,
// the point at angle lambda W from w2 on the great circle through w2 and w1, on w1's side.
// It equals slerp(w1, w2; t = 1 - lambda) = sin(lambda W)/sin W w1 + sin((1-lambda) W)/sin W w2,
// the paper's formula once the dot product it prints inside the sines is read as the angle
// W = acos(w1 . w2) (design notes section 4). lambda < 1 moves toward the guide, lambda > 1
// away from it, exactly as x' = v + lambda (x - v) does in the plane.
//
// The density ratio, derived. Use geodesic polar coordinates (theta, phi) about w2; the
// solid-angle measure is dw = sin(theta) dtheta dphi. The move keeps phi and maps
// theta = W to theta' = lambda W. As in the plane, the delta in phi is common to both
// directions and cancels, leaving the radial parts per unit sin(theta) dtheta:
//   forward:  p(theta' | theta) = g(theta'/theta) / theta   per dtheta'
//             => g(lambda) / (W sin(lambda W))             per unit solid angle
//   reverse:  lambda' = 1/lambda  =>  g(1/lambda) / (lambda W sin W)
//   T(w' -> w) / T(w -> w') = g(1/lambda)/g(lambda) * sin(lambda W) / (lambda sin W).
// For Goodman-Weare's g, g(1/l) = l g(l), so the ratio is
//     sin(lambda W) / sin W = sqrt(1 - (w_new . w2)^2) / sqrt(1 - (w1 . w2)^2).
// The paper's eq. 10 prints the reciprocal, sqrt(1 - (w1.w2)^2) / sqrt(1 - (w_new.w2)^2).
// Check against the plane: for small W, sin(lambda W)/sin W -> lambda, the planar ratio
// (Goodman-Weare's z^(N-1), N = 2), while the printed form tends to 1/lambda. The
// statistical test runs eq. 10 as printed and sees it fail.
//
// Validity. If lambda W >= pi the arc passes the guide's antipode; the point reached there
// has azimuth phi + pi about w2, and the move from it with 1/lambda does not come back, so
// such moves (and the degenerate W ~ 0 or W ~ pi, where the great circle is undefined) are
// reported invalid: reject. The condition is symmetric (a valid forward move has a valid
// reverse, since W = (lambda W) / lambda < pi), so rejecting them keeps detailed balance.
#include <cmath>
#include <limits>

#include "mutations/ensemble/kernels.h"

namespace emlt::ensemble {

namespace {

constexpr double kPiDouble = 3.14159265358979323846;
constexpr double kNegativeInfinity = -std::numeric_limits<double>::infinity();
// Angles closer than this to 0 or pi leave the great circle undefined.
constexpr double kMinArcAngle = 1e-6;

bool arc_angle_is_usable(double angle) {
  return angle > kMinArcAngle && angle < kPiDouble - kMinArcAngle;
}

struct ArcFrame {
  DVec3 guide;    // w2
  DVec3 tangent;  // u: unit tangent at w2 toward w1
  double angle;   // W
};

std::optional<ArcFrame> arc_frame(const Vec3& current, const Vec3& guide) {
  const DVec3 w1 = glm::normalize(DVec3(current));
  const DVec3 w2 = glm::normalize(DVec3(guide));
  const double cosine = glm::dot(w1, w2);
  const DVec3 perpendicular = w1 - cosine * w2;  // length sin W
  const double sine = glm::length(perpendicular);
  // atan2 keeps full precision near 0 and pi, where acos of the dot product would not.
  const double angle = std::atan2(sine, cosine);
  if (!arc_angle_is_usable(angle)) return std::nullopt;
  return ArcFrame{w2, perpendicular / sine, angle};
}

// great_arc_log_density_ratio from the sines of the two angles.
double arc_log_density_ratio(double lambda, double sine_proposed, double sine_current,
                             const StretchParams& params) {
  const double planar = linear_log_density_ratio(lambda, params, 2);
  if (planar == kNegativeInfinity) return kNegativeInfinity;
  // For Goodman-Weare's g, planar is log l, and log l - log l is 0 exactly: the two logs are
  // skipped there (docs/experiments.md, "Cost per mutation"), with the very same result.
  const double planar_over_lambda =
      params.distribution == StretchDistribution::InverseSqrt ? 0.0 : planar - std::log(lambda);
  return planar_over_lambda + std::log(sine_proposed) - std::log(sine_current);
}

}  // namespace

std::optional<Vec3> great_arc_point(const Vec3& current, const Vec3& guide, double lambda) {
  const auto frame = arc_frame(current, guide);
  if (!frame) return std::nullopt;
  const double angle = lambda * frame->angle;
  return Vec3(std::cos(angle) * frame->guide + std::sin(angle) * frame->tangent);
}

double great_arc_log_density_ratio(double lambda, double angle_current, double angle_proposed,
                                   const StretchParams& params) {
  if (!arc_angle_is_usable(angle_current) || !arc_angle_is_usable(angle_proposed))
    return kNegativeInfinity;
  // g(1/l)/g(l) * l^(N-2) with N = 2 is linear_log_density_ratio; the sphere replaces the
  // planar radius ratio r'/r = l by sin(theta')/sin(theta), hence * sin(l W) / (l sin W).
  return arc_log_density_ratio(lambda, std::sin(angle_proposed), std::sin(angle_current), params);
}

double great_arc_log_density_ratio_between(const Vec3& from, const Vec3& to, const Vec3& guide,
                                           const StretchParams& params) {
  const auto frame = arc_frame(from, guide);
  if (!frame) return kNegativeInfinity;
  const DVec3 w = glm::normalize(DVec3(to));
  // Angle of `to` from the guide, measured on the side of `from` (atan2 of the component
  // along the tangent toward `from`: negative means the far side of the guide).
  const double angle_proposed = std::atan2(glm::dot(w, frame->tangent), glm::dot(w, frame->guide));
  const double lambda = angle_proposed / frame->angle;
  if (!stretch_in_support(lambda, params)) return kNegativeInfinity;
  return great_arc_log_density_ratio(lambda, frame->angle, angle_proposed, params);
}

GreatArcProposal propose_great_arc(const Vec3& current, const Vec3& guide,
                                   const StretchParams& params, Rng& rng) {
  GreatArcProposal proposal;
  proposal.direction = current;
  proposal.lambda = sample_stretch(params, rng);  // drawn even when invalid: fixed rng use
  const auto frame = arc_frame(current, guide);
  if (!frame) return proposal;
  proposal.angle_current = frame->angle;
  proposal.angle_proposed = proposal.lambda * frame->angle;
  if (!arc_angle_is_usable(proposal.angle_proposed)) return proposal;
  const double angle = proposal.angle_proposed;
  const double sine = std::sin(angle);
  proposal.direction = Vec3(std::cos(angle) * frame->guide + sine * frame->tangent);
  // great_arc_log_density_ratio, with the sine just taken (the angles are usable here).
  proposal.log_density_ratio =
      arc_log_density_ratio(proposal.lambda, sine, std::sin(proposal.angle_current), params);
  proposal.valid = std::isfinite(proposal.log_density_ratio);
  return proposal;
}

}  // namespace emlt::ensemble
