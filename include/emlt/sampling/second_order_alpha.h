#pragma once
// Lu's second-order estimate of the split between light and BSDF sampling (thesis 004,
// chapter 5, "Automatic Variance Reduction for MIS").
//
// The one-sample mixture draws a direction from light sampling with probability alpha and
// from BSDF sampling otherwise, and divides the integrand by alpha p_L + (1 - alpha) p_B
// (Eq. 5.3, the balance heuristic with counts alpha N and (1 - alpha) N). Its second moment
// E[L^2] = integral of f^2 / p_alpha, expanded to second order about alpha = 1/2 (section
// 5.3.2) and minimised, gives Eq. 5.4:
//
//   alpha = 1/4 (2 + I1 / I2),  I1 = integral f^2 dp / pbar^2,  I2 = integral f^2 dp^2 / pbar^3,
//   pbar = (p_L + p_B) / 2,  dp = (p_L - p_B) / 2.
//
// Orientation: alpha here is the share of LIGHT samples, as --mis-alpha is. The thesis's
// alpha is the BSDF share (N_B = alpha N, Eq. 5.3; its Fig. 5.6 legend says the opposite,
// the seed digest's typo list follows the equations). Swapping the two strategies turns dp
// into -dp, which flips I1 and leaves I2, so Eq. 5.4 reads the same with dp taken as the
// chosen strategy's density minus the other's; here alpha_light = 1 - alpha_thesis.
//
// The two integrals are estimated as Eq. 5.5 does, from M pilot directions drawn half by
// each strategy (density pbar): I ~ (1/M) sum g / pbar. The 1/M cancels in the ratio. The
// thesis leaves the scalar f of a colour integrand open; this uses the luminance. Dirac
// draws (delta lights, specular lobes) have no density to compare and are left out: each
// is found by one strategy only, whatever alpha is.
//
// Limits (section 5.3.4): where one strategy alone should be used the estimate stops at
// 3/4 or 1/4, and between those it may overshoot [0, 1]; the result is clamped to
// [c, 1 - c] (Fig. 5.4 and section 5.4.3: c = 0.025).
namespace emlt {

class SecondOrderAlpha {
 public:
  // One pilot direction: `f`, the integrand's scalar value (not divided by any density),
  // and the two strategies' densities there.
  void add(double f, double light_pdf, double bsdf_pdf);
  void merge(const SecondOrderAlpha& other);

  // Eq. 5.4 within [clamp, 1 - clamp]; 1/2 (the balance heuristic) when no pilot direction
  // carried light or the densities never differed.
  double alpha(double clamp) const;
  // The unclamped Eq. 5.4 value, or 1/2 as above.
  double unclamped() const;

  // Sums of Eq. 5.5's terms (without the 1/M), for tests and statistics.
  double first_integral() const { return first_; }
  double second_integral() const { return second_; }

 private:
  double first_ = 0.0;   // sum (f / pbar)^2 dp / pbar
  double second_ = 0.0;  // sum (f / pbar)^2 (dp / pbar)^2
};

}  // namespace emlt
