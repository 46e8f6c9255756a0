#pragma once
// Energy redistribution path tracing (Cline, Talbot & Egbert 2005), as Mitsuba 0.6's `erpt`:
// each pixel sample is a bidirectional sample whose every strategy's path is a seed; a seed
// of MIS-weighted luminance w starts on average c w / b chains (c: --erpt-chains per pixel
// over the --spp seeds, Mitsuba's numChains over its sampleCount; b: the image's mean
// luminance), each of L steps (--erpt-chain-length) of the MLT
// strategies of --mutations (by default Veach's perturbations without the bidirectional
// mutation, as Mitsuba's ERPT); every step deposits w / (chains on average * L) of energy,
// split between the proposal and the current path by the acceptance probability (expected
// values). The chains keep f* invariant and the seeds' energy density is f*, so the deposits
// are unbiased: the image converges to BDPT's whatever c, L and b. With `--direct separate`
// paths of one and two segments are deposited as BDPT computes them, not redistributed.
//
// The chains' deposits go into fixed-point films, whose integer sums do not depend on the
// order of their additions; the seeds come from the pass runner's pixel samples (pass_runner.h),
// so the image is the same bits at any thread or rank count, with stops, checkpoints, --spp
// and --time from the runner.
#include <memory>
#include <vector>

#include "emlt/run/integrator.h"
#include "emlt/settings/render_option.h"

namespace emlt {

// Test switches: bugs injected to show that the tests notice them.
struct ErptOptions {
  bool deposit_ignores_bound = false;  // a seed whose chains --erpt-max-chains bounds deposits
                                       // as if it had its unbounded number of them
  bool chains_rounded_down = false;    // floor(mean) chains instead of floor(u + mean)
};

std::unique_ptr<Integrator> make_erpt(ErptOptions options = {});
const std::vector<RenderOption>& erpt_options();

}  // namespace emlt
