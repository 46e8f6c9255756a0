#pragma once
// Veach's bidirectional mutation (1997, §11.4.2) in the form Mitsuba uses: delete a
// stretch of d vertices from x at position a, insert d' new ones (a new path length drawn
// from a two-tailed geometric distribution around the old one) by random walks from both
// kept ends, s from the light side and t = d' - s from the eye side, and connect. It can
// change every vertex and any length, so it keeps every chain ergodic.
//
// T(x -> y) = P(length) P(d) P(a) * (1/|S|) sum_{s in S} p_s(inserted vertices of y),
// summed over every split S that could have produced y; the reverse move deletes what
// was inserted. Restrictions, the same in both directions so detailed balance holds:
//   * kept ends of the deleted stretch are non-specular (a walk or a connection starts
//     there);
//   * a kept light vertex alone (a = 1) is only connected to, never walked from (that would
//     need emission-direction sampling from a fixed point), and likewise a kept lens point;
//   * an emitter or the lens never becomes an interior vertex.
#include "emlt/mcmc/mutation.h"

namespace emlt {

class BidirectionalMutation final : public Mutation {
 public:
  std::string_view name() const override { return "bidir"; }
  bool applies_to(const Path& x, const MutationContext&) const override {
    return x.vertices.size() >= 2;
  }
  std::optional<Proposal> propose(const Path& x, Rng& rng, const MutationContext& ctx) const override;

  // The proposal density of the move that deletes [a, a + d) of `from` and leaves `to`
  // (T(x->y) and T(y->x) are both this function).
  static double proposal_density(const Path& from, const Path& to, int a, int d,
                                 const MutationContext& ctx);

  // The building blocks, for strategies that reuse them: y from x with [a, a + d) replaced
  // by n_new vertices, s of them walked from the light side; and the density of y's
  // inserted vertices averaged over every split that could have made them (c = number of
  // kept vertices after the inserted ones). regenerate recomputes only the densities that
  // the new stretch changes: x's own densities must be current (path.h).
  static std::optional<Path> regenerate(const Path& x, int a, int d, int n_new, int s, Rng& rng,
                                        const MutationContext& ctx);
  static double inserted_density(const Path& y, int a, int n_new, int c);
};

}  // namespace emlt
