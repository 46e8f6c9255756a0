// The named conductor presets against the values Mitsuba 0.6's RGB build itself computes:
// eta/k as its Spectrum::fromContinuousSpectrum gives them for data/ior/<name>.*.spd, and
// the reflectance a smooth conductor of each shows in a Mitsuba render (constant
// environment of radiance 1 seen in the plane at normal incidence, maxDepth 2, so each
// pixel is the Fresnel reflectance with eta and k divided by extEta = air, 1.000277).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "emlt/scene/conductor_presets.h"
#include "emlt/scene/materials.h"

using namespace emlt;

namespace {

struct MitsubaConductor {
  const char* name;
  std::array<double, 3> eta, k;
  std::array<double, 3> r0;  // rendered normal-incidence reflectance, extEta = air
};

// eta, k: printed by a program linked against Mitsuba 0.6's libmitsuba-core (RGB build)
// calling fromContinuousSpectrum(InterpolatedSpectrum(".../data/ior/<name>.eta.spd")).
// r0: pixel values of `mitsuba` renders of the scene described above.
const MitsubaConductor kMitsuba[] = {
    {"Cu", {0.200431377, 0.924036682, 1.10221112}, {3.91293001, 2.45285606, 2.14218402},
     {0.9521304, 0.6196126, 0.5105043}},
    {"Au", {0.1431254, 0.374955684, 1.44247591}, {3.98314905, 2.38572431, 1.6032083},
     {0.9666531, 0.8021564, 0.3239679}},
    {"Ag", {0.155264333, 0.116723448, 0.138380706}, {4.82832527, 3.12225437, 2.14695048},
     {0.9747961, 0.9575281, 0.9062510}},
    {"Al", {1.65745771, 0.880369365, 0.521227419}, {9.22386265, 6.26952982, 4.83700228},
     {0.9280289, 0.9177838, 0.9188891}},
    {"Cr", {4.3696661, 2.91670966, 1.65470028}, {5.2064085, 4.23137379, 3.75494695},
     {0.6874762, 0.6489919, 0.6869460}},
    {"Cu_palik", {0.212680534, 0.919989347, 1.1024071}, {3.92154431, 2.45715594, 2.13665295},
     {0.9494973, 0.6214949, 0.5091729}},
    {"Hg", {2.3989265, 1.44002795, 0.909548521}, {6.32759476, 4.37195444, 3.42178988},
     {0.8139601, 0.7701667, 0.7630122}},
    {"TiN", {1.64846277, 1.1504513, 1.37977338}, {3.3684516, 1.94349003, 1.1020118},
     {0.6408030, 0.4521960, 0.1974754}},
};

constexpr float kAir = 1.000277f;

double normal_reflectance(double eta, double k) {
  return ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
}

TEST(ConductorPresets, MatchMitsubaRgbBuild) {
  for (const MitsubaConductor& m : kMitsuba) {
    Rgb eta(-1.0f), k(-1.0f);
    ASSERT_TRUE(conductor_preset(m.name, &eta, &k)) << m.name;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(eta[c], m.eta[size_t(c)], 1e-4) << m.name << " eta channel " << c;
      EXPECT_NEAR(k[c], m.k[size_t(c)], 1e-4) << m.name << " k channel " << c;
    }
  }
}

TEST(ConductorPresets, SmoothConductorReflectsAsMitsubaRenders) {
  const Vec3 normal(0.0f, 0.0f, 1.0f);
  for (const MitsubaConductor& m : kMitsuba) {
    Rgb eta, k;
    ASSERT_TRUE(conductor_preset(m.name, &eta, &k)) << m.name;
    const BsdfPtr bsdf = make_conductor(eta / kAir, k / kAir);
    const auto s = bsdf->sample({}, normal, 0.5f, Vec2(0.5f));
    ASSERT_TRUE(s) << m.name;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(s->weight[c], m.r0[size_t(c)], 2e-5) << m.name << " channel " << c;
      EXPECT_NEAR(s->weight[c], normal_reflectance(eta[c] / kAir, k[c] / kAir), 1e-5)
          << m.name << " channel " << c;
    }
  }
}

TEST(ConductorPresets, NamesAreMitsubasFileNames) {
  Rgb eta, k;
  // Mitsuba's palik files are separate data, not aliases: Cu_palik differs from Cu.
  Rgb cu_eta, cu_k;
  ASSERT_TRUE(conductor_preset("Cu", &cu_eta, &cu_k));
  ASSERT_TRUE(conductor_preset("Cu_palik", &eta, &k));
  EXPECT_GT(std::abs(eta.x - cu_eta.x), 0.01f);
  // Names with data in Mitsuba 0.6, beyond the common metals.
  for (const char* name : {"a-C", "d-C_palik", "TiO2-e", "V_palik", "Na_palik", "Ni_palik"})
    EXPECT_TRUE(conductor_preset(name, &eta, &k)) << name;
  // Kept as they are: AlSb's red eta is negative in Mitsuba's conversion too.
  ASSERT_TRUE(conductor_preset("AlSb", &eta, &k));
  EXPECT_NEAR(eta.x, -0.0484389812, 1e-4);
  // Mitsuba ships no Ag_palik, and file names are case-sensitive; "none" is not.
  eta = Rgb(7.0f);
  EXPECT_FALSE(conductor_preset("Ag_palik", &eta, &k));
  EXPECT_FALSE(conductor_preset("cu", &eta, &k));
  EXPECT_EQ(eta, Rgb(7.0f));
  ASSERT_TRUE(conductor_preset("None", &eta, &k));
  EXPECT_EQ(eta, Rgb(0.0f));
  EXPECT_EQ(k, Rgb(1.0f));
}

}  // namespace
