#pragma once
// The valid range of every numeric scene parameter that has one, with the words that state
// it, shared by the JSON and Mitsuba XML loaders (internal to src/scene). Where the command
// line sets the same quantity the bounds and the words are the flag's: --width and --height
// (src/cli/render_command.cpp) state these ranges, and the options a scene file shares with
// the command line (--spp, --max-depth, ...) are read through their own declarations
// (settings/scene_options.h, whole_range below). A value is accepted or refused alike
// wherever it comes from. A refusal states the range in words and never prints a raw limit
// (an unbounded float's would be 3.40282e+38).
#include <limits>
#include <string>

#include "emlt/settings/render_option.h"
#include "emlt/settings/settings.h"

namespace emlt::loader {

struct IntegerRange {
  int low, high;
  const char* words;  // completes "must be ..."
  bool contains(int value) const { return value >= low && value <= high; }
};

struct RealRange {
  float low;
  bool low_open;  // low itself excluded
  float high;     // infinity: no upper bound
  bool high_open;
  const char* words;
  bool contains(float value) const {
    return (low_open ? value > low : value >= low) && (high_open ? value < high : value <= high);
  }
};

// "must be <words> (got <value as the file gives it>)", the value shortened so that a
// pasted megabyte stays one line.
inline std::string refusal(const char* words, const std::string& given) {
  const std::string shown = given.size() <= 24 ? given : given.substr(0, 21) + "...";
  return std::string("must be ") + words + " (got " + shown + ")";
}

// A film side: 16384 x 16384 (2^28 pixels) is 3 GiB of float RGB per film, and the MCMC
// integrators keep several. Scene::build applies the same bound to descriptions that no
// loader produced.
inline constexpr IntegerRange kFilmSideRange{1, 16384, "a whole number of pixels from 1 to 16384"};
// A whole-number option's range, in its own words (the declaration outlives the range).
inline IntegerRange whole_range(const OptionValues& values) {
  return {int(values.low), int(values.high), values.takes.c_str()};
}

// The index of a mesh in a Mitsuba .serialized file; the file's own count bounds it above
// (checked when the file is read, which names the count).
inline constexpr IntegerRange kShapeIndexRange{0, std::numeric_limits<int>::max(),
                                               "a whole number, 0 or more"};

inline constexpr float kUnbounded = std::numeric_limits<float>::infinity();
// As Mitsuba's perspective and thin-lens cameras: 180 degrees and more have no pinhole
// projection.
inline constexpr RealRange kFovRange{0.0f, true, 180.0f, true,
                                     "a number of degrees between 0 and 180, both excluded"};
// Lengths and indices of refraction (a radius, a focus distance, intIOR).
inline constexpr RealRange kPositiveRange{0.0f, true, kUnbounded, false, "a positive number"};
// An aperture radius (0: a pinhole) and an environment map's scale (0: black).
inline constexpr RealRange kNonNegativeRange{0.0f, false, kUnbounded, false,
                                             "zero or a positive number"};
// Reconstruction filters: either bound lets a footprint reach 64 pixels from its centre (a
// Gaussian's reaches 4 stddev); a wider one would splat each sample over more than 16000 pixels.
inline constexpr RealRange kFilterRadiusRange{0.0f, true, 64.0f, false,
                                              "a positive number of pixels, at most 64"};
inline constexpr RealRange kFilterStddevRange{0.0f, true, 16.0f, false,
                                              "a positive number of pixels, at most 16"};
// A Lanczos filter's lobes are its radius in pixels: the same bound.
inline constexpr IntegerRange kFilterLobesRange{1, 64, "a whole number from 1 to 64"};

}  // namespace emlt::loader
