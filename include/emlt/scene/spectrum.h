#pragma once
// Spectra in a scene file, turned into linear RGB exactly as Mitsuba 0.6 built in RGB mode
// (SPECTRUM_SAMPLES=3, its default build and the one our reference images come from) does
// when it loads a scene. emlt renders in linear RGB, so a spectrum has to mean the RGB
// triple Mitsuba would have rendered with, not a plausible colour of its own.
//
// What Mitsuba does (src/libcore/spectrum.cpp, src/librender/scenehandler.cpp):
// - A continuous spectrum s(λ) becomes CIE 1931 XYZ by averaging s·x̄, s·ȳ, s·z̄ over
//   360-830 nm, with the colour matching functions tabulated every 1 nm and linearly
//   interpolated (zero outside), and dividing by the average of ȳ over the same range (so
//   s ≡ 1 gives Y = 1; no illuminant or white-point weighting). XYZ goes to linear Rec.709
//   / sRGB primaries through a fixed matrix. The reflectance/illuminant "intent" changes
//   nothing in RGB mode.
// - A wavelength:value list or .spd file is piecewise linear, first extended by one extra
//   sample of value 0, one average sample spacing before the first and after the last
//   sample (unless that end is already 0), and zero beyond. Negative RGB results become 0.
// - <blackbody> is Planck's law in W m^-2 nm^-1 sr^-1 (temperature in kelvin), converted
//   as above, negatives clamped to 0, then multiplied by `scale`.
// Mitsuba averages the products with an adaptive Gauss-Lobatto quadrature in single
// precision (tolerance 1e-4, 47 nm panels); here they are integrated exactly (piecewise-
// linear products) or with 8-point Gauss-Legendre per 1 nm (the black body) in double
// precision. The two agree to a few 1e-5 relative, Mitsuba's own quadrature error, except
// for features narrower than about 2 nm, which Mitsuba's first quadrature nodes can step
// over entirely (a 1 nm-wide line renders black there); those are integrated exactly here.
#include <string>
#include <vector>

#include "emlt/core/math.h"

namespace emlt::spectrum {

// CIE 1931 2° colour matching functions: first and last tabulated wavelength (nm, 1 nm
// step); Mitsuba's conversion integrates over exactly this range.
inline constexpr int kCieFirstNm = 360;
inline constexpr int kCieLastNm = 830;

// A spectrum sampled at strictly increasing wavelengths (nm), linear in between and zero
// outside [wavelengths.front(), wavelengths.back()].
struct PiecewiseLinear {
  std::vector<double> wavelengths;
  std::vector<double> values;

  double eval(double lambda) const;
};

// Checks the samples (same count, strictly increasing wavelengths, finite); throws
// std::invalid_argument with a one-line reason otherwise.
PiecewiseLinear make_piecewise_linear(const std::vector<float>& wavelengths,
                                      const std::vector<float>& values);

// Mitsuba's extension of a measured spectrum: one sample of value 0 added an average
// spacing beyond each end whose value is not 0. Needs at least 2 samples
// (std::invalid_argument otherwise).
void zero_extend(PiecewiseLinear& s);

// Normalised CIE XYZ (Y of s ≡ 1 is 1) of s, integrated over 360-830 nm.
DVec3 to_xyz(const PiecewiseLinear& s);

// XYZ to linear RGB with Rec.709 primaries (Mitsuba's matrix, D65 white).
DVec3 xyz_to_linear_rgb(const DVec3& xyz);

// What a <spectrum value="λ:v, ..."/> or <spectrum filename="..."/> means in Mitsuba's RGB
// mode: zero_extend, convert, clamp negative components to 0. Throws std::invalid_argument
// for fewer than 2 samples.
Rgb sampled_to_rgb(PiecewiseLinear s);

// Spectral radiance of a black body (Planck's law) in W m^-2 nm^-1 sr^-1.
double planck(double lambda_nm, double kelvin);

// What <blackbody temperature="kelvin" scale="scale"/> means in Mitsuba's RGB mode (the
// RGB of planck(), negatives clamped, times scale). Throws std::invalid_argument unless
// kelvin is finite and > 0.
Rgb blackbody_to_rgb(double kelvin, double scale = 1.0);

// Reads Mitsuba's spectral text file: one "wavelength value" pair a line (further text on
// the line is ignored, as Mitsuba's stream read does), blank lines and lines starting
// with '#' skipped. Unlike Mitsuba, which silently stops at the first line that does not
// start with two numbers, such a line is an error. Throws emlt::Error "<file>: line N:
// ..." (or "<file>: cannot be read") on a problem.
PiecewiseLinear read_spd(const std::string& path);

}  // namespace emlt::spectrum
