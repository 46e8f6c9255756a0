#pragma once
// Scenes and checks the manifold perturbation's test files share
// (manifold_perturbation_test.cpp defines them).
#include <memory>

#include "emlt/scene/materials.h"
#include "emlt/scene/scene.h"

// A glass ball above a floor under a small light, seen from above (its caustic and the floor
// seen through it); `ball_material` replaces the smooth glass.
std::unique_ptr<emlt::Scene> caustic_under_a_ball(
    emlt::BsdfPtr ball_material = emlt::make_dielectric(1.5f, 1.0f));

// MLT with bidir=1,manifold=4 against BDPT: the image total within `total` and each
// quadrant within `quadrant`, the manifold perturbation carrying at least `share` of the
// accepted moves.
void expect_manifold_mix_converges(const emlt::Scene& scene, int reference_spp, double mpp,
                                   double share, double quadrant, double total);
