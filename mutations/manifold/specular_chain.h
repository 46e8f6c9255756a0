#pragma once
// A chain of Dirac interactions between two fixed ends, found by Newton's method: the
// manifold walk of Jakob & Marschner (2012, §4), written in the form that fixes one end.
//
// The chain leaves the fixed start point s along a direction ω, keeps at each link the
// Dirac lobe the old chain took there (reflection or refraction, on the same material),
// and after its last link meets the target's tangent plane at E(ω). Solving E(ω) = target
// for ω places every link on the specular manifold: the generalized half-vector
// constraints of the paper's §4.1 hold at every link by construction (each outgoing
// direction is the lobe's own), and the two remaining degrees of freedom are the ones the
// walk solves for. The derivatives of E are carried along the chain as ray differentials
// (Igehy 1999) through each surface's tangent plane and shading-normal derivative, in
// double precision; det dE/dω is the chain's generalized geometry term up to the
// end-point cosines (§4.3): |dA(target)/dω(start)|.
#include <optional>
#include <vector>

#include "emlt/path/vertex.h"
#include "emlt/scene/scene.h"

namespace emlt::manifold {

// One link the chain must keep: its material and whether the lobe refracts. A rough link
// treated as specular (offset_normal.h) reflects or refracts about the microfacet normal
// with local coordinates `offset` in the frame OffsetFrame builds at each point; a Dirac link
// scatters through the material's own lobe.
struct ChainLink {
  const Bsdf* bsdf = nullptr;
  bool transmission = false;
  bool rough = false;
  DVec3 offset{0.0, 0.0, 1.0};  // rough links: m in the local frame
  double ior = 1.0;             // rough refracting links: interior over exterior index
};

struct ChainProblem {
  const Scene* scene = nullptr;
  PathVertex start;                              // the fixed end the chain leaves from
  std::vector<ChainLink> links;                  // in order from the start
  TransportMode mode = TransportMode::Radiance;  // the walk's direction for the lobes
  DVec3 target{0.0};                             // the other fixed end (a surface point)
  DVec3 target_normal{0.0};  // its geometric normal (the plane the end point lies in)
};

struct ChainTrace {
  DVec3 direction{0.0};           // ω, unit, leaving the start
  std::vector<PathVertex> links;  // the surface points reached (Dirac records not filled)
  DVec3 end{0.0};                 // where the last segment meets the target's plane
  double residual = 0.0;          // |end - target|
  // dE/dω: columns the end point's motion in the target plane's (s, t) basis per unit
  // turn of ω about its own frame's s and t axes (radians).
  double jacobian[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
  double offset[2] = {0.0, 0.0};  // (end - target) in the same plane basis

  // |det dE/dω|: target area per unit solid angle at the start.
  double area_per_solid_angle() const {
    return std::abs(jacobian[0][0] * jacobian[1][1] - jacobian[0][1] * jacobian[1][0]);
  }
};

// Traces the chain along `direction`; false when a ray escapes, reaches another material,
// loses the lobe, meets a surface whose normal is not a smooth function of position
// (Scene::shading_normal_derivative) or one whose frame turns with dp/du (anisotropic and
// normal-mapped materials, whose Dirac directions are not reflections about the shading
// normal), or the last segment never reaches the target's plane.
bool trace_chain(const ChainProblem& problem, const DVec3& direction, ChainTrace* trace);

// The iteration limit of the walk (Mitsuba 0.6's MTS_MANIFOLD_MAX_ITERATIONS).
inline constexpr int kMaxNewtonSteps = 20;

// Newton's method on ω from `guess`, each step halved until the end moves closer to the
// target (the paper's step control: a step that fails or moves away is retried shorter),
// until the end lies within `tolerance` of the target. Nothing when it does not converge
// within kMaxNewtonSteps traces; `accept_unconverged` (an injected bug for the tests)
// returns the last trace anyway.
std::optional<ChainTrace> solve_chain(const ChainProblem& problem, const DVec3& guess,
                                      double tolerance, bool accept_unconverged = false);

}  // namespace emlt::manifold
