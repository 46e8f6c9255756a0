#include "emlt/integrators/mlt/mlt_step.h"

#include <cmath>

#include "emlt/core/interruption.h"
#include "emlt/mcmc/delayed_acceptance.h"
#include "emlt/path/path.h"

namespace emlt {

void prefetch_path(const Path& path) {
  const char* data = reinterpret_cast<const char*>(path.vertices.data());
  const size_t bytes = path.vertices.size() * sizeof(PathVertex);
  for (size_t offset = 0; offset < bytes; offset += 64) __builtin_prefetch(data + offset);
}

size_t film_index(const Path& path, int width, int height) {
  const Vec2 raster = path.raster();
  const int x = std::clamp(int(raster.x), 0, width - 1),
            y = std::clamp(int(raster.y), 0, height - 1);
  return size_t(y) * size_t(width) + size_t(x);
}

void FilmSlot::splat(int width, int height, const Path& path, const DVec3& contribution,
                     double target, double weight) const {
  if (!(weight > 0.0) || !(target > 0.0)) return;
  const DVec3 value = contribution * (weight * scale / target);
  if (filter.is_box()) {
    film.add(film_index(path, width, height), value, shared);
    return;
  }
  filter.splat(path.raster(),
               [&](uint32_t pixel, float w) { film.add(pixel, value * double(w), shared); });
}

uint64_t run_chain(MltChain& chain, uint64_t chain_index, const StrategyMix& mix,
                   MutationContext ctx, const StepRules& rules, BlockOutput& out,
                   const FilmSlot& film, int width, int height) {
  ctx.chain = chain_index;
  // Steps taken with the current applicability, credited to the strategies that did not
  // apply whenever it changes (one loop per accepted move instead of one per step).
  uint64_t steps_with_mask = 0;
  const auto count_not_applicable = [&] {
    for (size_t i = 0; i < mix.size(); ++i)
      if (!((chain.applicable >> i) & 1u)) out.stats[i].not_applicable += steps_with_mask;
    steps_with_mask = 0;
  };
  uint64_t step = 0;
  for (; chain.sweep_left > 0; ++step) {
    // Every 1024 steps (about a millisecond): a stop is seen well within a second.
    if ((step & 1023) == 1023 && interruption::requested()) break;
    --chain.sweep_left;
    ctx.step = chain.steps_taken++;
    double p_forward = 0.0;
    const int chosen = mix.choose(chain.applicable, chain.rng.uniform(), &p_forward);
    ++steps_with_mask;
    if (chosen < 0) {  // nothing applies: the path stays
      chain.carried += 1.0;
      continue;
    }
    StrategyStats& stats = out.stats[size_t(chosen)];
    ++stats.proposed;

    // The proposal's expected-value weight: its acceptance probability, or under delayed
    // acceptance 1{first stage passed}·a2, whose expectation that is (delayed_acceptance.h).
    double acceptance = 0.0;
    double accept_below = 0.0;  // the step's uniform accepts the proposal below this
    const Mutation& strategy = mix.strategy(size_t(chosen));
    auto proposal = strategy.propose(chain.current, chain.rng, ctx);
    if (proposal && proposal->fallback) ++stats.fallbacks;
    if (proposal && proposal->alpha >= 0.0) out.alpha.add(proposal->alpha);
    if (proposal && film.moves) {
      const Vec2 move = proposal->path.raster() - chain.current.raster();
      film.moves->add(film_index(chain.current, width, height),
                      DVec3(double(move.x) * move.x, double(move.y) * move.y, 1.0), film.shared);
    }
    DVec3 contribution(0.0);
    double target = 0.0;
    StrategyMask proposal_applicable = 0;
    bool two_stages = false;
    double first_ratio = 0.0;  // the whole ratio, or the first stage's with two stages
    if (proposal) {
      // Proposals land anywhere on the image, so the splat below would usually wait on
      // memory (a film is larger than the caches): start loading the pixel now, while the
      // contribution is evaluated.
      film.film.prefetch(film_index(proposal->path, width, height));
      contribution = path_contribution(ctx.scene, proposal->path);
      target = luminance(contribution);
      if (target > 0.0 && std::isfinite(target)) {
        proposal_applicable = mix.applicable(proposal->path, ctx);
        const double p_reverse =
            rules.ignore_selection ? p_forward
                                   : mix.selection_probability(size_t(chosen), proposal_applicable);
        // A deferred factor (only under delayed acceptance, ctx.may_defer) is evaluated only
        // after the first stage has passed (below).
        two_stages = proposal->deferred;
        first_ratio = target / chain.target * std::exp(proposal->log_reverse_over_forward) *
                      (p_reverse / p_forward);
        acceptance = acceptance_probability(first_ratio);
      }
    }
    // Nothing draws from the chain's stream after the proposal, so this is the number the
    // step has always used, drawn before the splats since the second stage needs it.
    const double u = chain.rng.uniform();
    if (two_stages) {
      const TwoStageDecision d = two_stage_decision(first_ratio, u, [&] {
        return strategy.deferred_log_ratio(chain.current, *proposal, ctx);
      });
      acceptance = d.weight;
      accept_below = d.accept_below;
    } else {
      accept_below = acceptance;
    }
    if (!proposal || !(target > 0.0)) ++stats.failed;
    stats.acceptance_sum += acceptance;

    // Expected values: the proposal's share now, the current path's when it is left. Without
    // them, the state after the step gets the step's whole weight (carried to the proposal
    // when it is accepted).
    if (rules.expected_values) {
      chain.carried += 1.0 - acceptance;
      if (acceptance > 0.0)
        film.splat(width, height, proposal->path, contribution, target, acceptance);
    }
    if (u < accept_below) {
      film.splat(width, height, chain.current, chain.contribution, chain.target, chain.carried);
      chain.current = std::move(proposal->path);
      chain.moved = true;
      chain.contribution = contribution;
      chain.target = target;
      if (proposal_applicable != chain.applicable) count_not_applicable();
      chain.applicable = proposal_applicable;
      chain.carried = rules.expected_values ? 0.0 : 1.0;
      ++stats.accepted;
    } else if (!rules.expected_values && !rules.drop_rejected_steps) {
      chain.carried += 1.0;
    }
  }
  count_not_applicable();
  return step;
}

}  // namespace emlt
