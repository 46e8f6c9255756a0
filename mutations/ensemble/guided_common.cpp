#include "mutations/ensemble/guided_common.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <optional>

#include "mutations/ensemble/guide_lanes.h"

namespace emlt::ensemble {

GuideView guides_for(const Path& x, const MutationContext& ctx) {
  if (!ctx.ensemble) return {};
  // x is often cold (a chain takes few steps per swap, one on small images); its vertices
  // are read next.
  for (const PathVertex& v : x.vertices) __builtin_prefetch(&v);
  return ctx.ensemble->upsilon(x, ctx.chain, ctx.step);
}

GuideView reverse_guides_for(const Path& y, const GuideView& forward, const MutationContext& ctx,
                             const InjectedBugs& bugs) {
  if (!ctx.ensemble) return forward;
  if (bugs.upsilon_from_proposal)
    return ctx.ensemble->counter_upsilon(y.type, ctx.chain, ctx.step + 1);
  if (bugs.reverse_upsilon_of_x || ctx.ensemble->params().selection == GuideSelection::Counter)
    return forward;
  return ctx.ensemble->upsilon(y, ctx.chain, ctx.step);
}

GuideView counter_guides_for(const Path& x, const MutationContext& ctx) {
  if (!ctx.ensemble) return {};
  return ctx.ensemble->counter_upsilon(x.type, ctx.chain, ctx.step);
}

double stretch_reverse_correction(double lambda, const GuideView& forward, const GuideView& reverse,
                                  const InjectedBugs& bugs) {
  if (bugs.alpha_not_reversed) return 0.0;
  return stretch_reverse_correction(lambda, stretch_params(forward), stretch_params(reverse));
}

std::optional<Proposal> unguided_step(const Mutation& fallback, const Path& x, Rng& rng,
                                      const MutationContext& ctx) {
  auto proposal = fallback.propose(x, rng, ctx);
  if (proposal) proposal->fallback = true;
  return proposal;
}

PathVertex guide_vertex(const GuideView& guides, size_t n, int i) {
  PathVertex v;
  v.position = guides.position(n, i);
  if (guides.has_environment()) {
    if (guides.environment(i)[n]) v.kind = VertexKind::Environment;
    v.sky_direction = guides.sky_directions(i)[n];
  }
  return v;
}

void vertex_similarities(const PathVertex& a, const GuideView& guides, int i,
                         const SimilarityParams& params, std::span<double> out) {
  assert(out.size() == guides.size());
  const size_t count = guides.size();
  if (guides.same_point(i) && !a.is_environment()) {
    std::fill(out.begin(), out.end(), vertex_similarity(a.position, guides.position(0, i), params));
    return;
  }
  // A sky vertex is a direction: compare directions (unit vectors) instead of points.
  if (guides.has_environment()) {
    const std::span<const Vec3> sky = guides.sky_directions(i);
    const std::span<const uint8_t> environment = guides.environment(i);
    for (size_t n = 0; n < count; ++n)
      out[n] = a.is_environment() || environment[n]
                   ? vertex_similarity(a.sky_direction, sky[n], params)
                   : vertex_similarity(a.position, guides.position(n, i), params);
  } else if (a.is_environment()) {
    // No guide keeps a sky direction in Υ's arrays: read the paths (rare).
    for (size_t n = 0; n < count; ++n)
      out[n] =
          vertex_similarity(a.sky_direction, guides[n]->vertices[size_t(i)].sky_direction, params);
  } else {
    similarities_to_guides(a.position, guides.coordinates(i, 0), guides.coordinates(i, 1),
                           guides.coordinates(i, 2), params, out);
  }
}

namespace {

// The similarity row of x's vertex i (v) to the guides: the one `reuse` has for this path if
// any, else computed into `kept`'s row i (or into `scratch` when nothing keeps it).
std::span<const double> similarity_row(const Path& x, const PathVertex& v, int i,
                                       const GuideView& guides, const SimilarityParams& params,
                                       SimilarityRows* kept, const SimilarityRows* reuse,
                                       GuideBuffer<double>& scratch) {
  if (reuse) {
    const std::span<const double> row = reuse->reusable_row(x, i);
    if (!row.empty()) return row;
  }
  const std::span<double> computed = kept ? kept->row(i) : scratch.span();
  vertex_similarities(v, guides, i, params, computed);
  return computed;
}

// path_similarities, keeping the rows in `kept` and taking those `reuse` has for this path.
void path_similarities(const Path& x, const GuideView& guides, int first, int last,
                       const SimilarityParams& params, std::span<SimilarityProduct> out,
                       SimilarityRows* kept, const SimilarityRows* reuse) {
  assert(out.size() == guides.size());
  std::fill(out.begin(), out.end(), SimilarityProduct{});
  const size_t count = guides.size();
  GuideBuffer<double> scratch(count);
  if (kept) kept->assign(x, first, last, count);
  for (int i = first; i <= last; ++i) {
    const PathVertex& v = x.vertices[size_t(i)];
    if (guides.same_point(i) && !v.is_environment()) {
      // One similarity for every guide (the row's value in each entry). Where it is 1 (the
      // usual case: the same lens point), multiplying by it would change nothing.
      const double s = vertex_similarity(v.position, guides.position(0, i), params);
      if (s != 1.0)
        for (size_t n = 0; n < count; ++n) out[n].multiply(s);
      continue;
    }
    const std::span<const double> row =
        similarity_row(x, v, i, guides, params, kept, reuse, scratch);
    for (size_t n = 0; n < count; ++n) out[n].multiply(row[n]);
  }
}

// path_similarities as plain doubles: the products ((1 * S_first) * S_first+1) * ... formed
// as SimilarityProduct::multiply forms them, or nothing when some product did not stay plain
// (every factor and every partial product >= kRenormalise, so that the products' log parts
// are 0 and their values are the doubles). The weights are `out`, or, where a single row is
// the whole product (1 * S is S exactly), that row itself: copying it cost as much as
// testing it. The products cost more than the rows they multiply
// (docs/experiments.md, "Cost per mutation").
std::optional<std::span<const double>> plain_path_similarities(
    const Path& x, const GuideView& guides, int first, int last, const SimilarityParams& params,
    std::span<double> out, SimilarityRows* kept, const SimilarityRows* reuse) {
  assert(out.size() == guides.size());
  const size_t count = guides.size();
  GuideBuffer<double> scratch(count);
  if (kept) kept->assign(x, first, last, count);
  std::span<const double> product;  // empty: no factor yet
  for (int i = first; i <= last; ++i) {
    const PathVertex& v = x.vertices[size_t(i)];
    if (guides.same_point(i) && !v.is_environment()) {
      // One similarity for every guide (the row's value in each entry). Where it is 1 (the
      // usual case: the same lens point), multiplying by it would change nothing.
      const double s = vertex_similarity(v.position, guides.position(0, i), params);
      if (s == 1.0) continue;
      if (product.empty())
        std::fill(out.begin(), out.end(), s);
      else
        for (size_t n = 0; n < count; ++n) out[n] = product[n] * s;
      product = out;
      continue;
    }
    const std::span<const double> row =
        similarity_row(x, v, i, guides, params, kept, reuse, scratch);
    if (product.empty()) {
      product = row;
    } else {
      for (size_t n = 0; n < count; ++n) out[n] = product[n] * row[n];
      product = out;
    }
  }
  if (product.empty()) {
    std::fill(out.begin(), out.end(), 1.0);
    product = out;
  }
  // Every factor is a similarity, in [0, 1] or NaN, so a rounded product is never above any
  // of its factors or earlier partial products: all of them stayed >= kRenormalise exactly
  // when the final product did (NaN fails either test).
  if (!all_at_least(product, SimilarityProduct::kRenormalise)) return std::nullopt;
  return product;
}

}  // namespace

void SimilarityRows::assign(const Path& path, int first, int last, size_t guides) {
  path_ = &path;
  first_ = first;
  last_ = last;
  guides_ = guides;
  const size_t size = size_t(std::max(last - first + 1, 0)) * guides;
  if (size <= kStackEntries) {
    data_ = stack_.data();
  } else {
    heap_.resize(size);
    data_ = heap_.data();
  }
}

std::span<const double> SimilarityRows::reusable_row(const Path& other, int i) const {
  if (!path_ || i < first_ || i > last_ || size_t(i) >= other.vertices.size()) return {};
  const PathVertex& a = path_->vertices[size_t(i)];
  const PathVertex& b = other.vertices[size_t(i)];
  const bool same = a.position == b.position && a.is_environment() == b.is_environment() &&
                    (!a.is_environment() || a.sky_direction == b.sky_direction);
  if (!same) return {};
  return {data_ + size_t(i - first_) * guides_, guides_};
}

void path_similarities(const Path& x, const GuideView& guides, int first, int last,
                       const SimilarityParams& params, std::span<SimilarityProduct> out) {
  path_similarities(x, guides, first, last, params, out, nullptr, nullptr);
}

SimilarGuide choose_similar_guide(const Path& x, const GuideView& guides, int first, int last,
                                  const MutationContext& ctx, Rng& rng, SimilarityRows* rows) {
  const SimilarityParams params = similarity_params(ctx);
  GuideBuffer<double> buffer(guides.size());
  if (const auto plain =
          plain_path_similarities(x, guides, first, last, params, buffer.span(), rows, nullptr)) {
    SimilarGuide chosen;
    chosen.total = plain_weight_total(*plain);
    chosen.index = choose_index_from_plain(*plain, chosen.total, rng);
    chosen.weight = (*plain)[chosen.index];
    return chosen;
  }
  GuideBuffer<SimilarityProduct> weights(guides.size());
  path_similarities(x, guides, first, last, params, weights.span(), rows, nullptr);
  const GuideChoice choice = choose_guide(std::span<const SimilarityProduct>(weights.span()), rng);
  SimilarGuide chosen;
  chosen.index = choice.index;
  chosen.log_probability = choice.log_probability;
  return chosen;
}

double log_selection_ratio(const Path& y, const GuideView& guides, const GuideView& reverse,
                           const SimilarGuide& chosen, int first, int last,
                           const MutationContext& ctx, const InjectedBugs& bugs,
                           const SimilarityRows* rows_x) {
  if (bugs.ignore_selection) return 0.0;
  const GuideView& reverse_guides = reverse;
  const bool same = reverse.same_as(guides);
  // The injected bug of the counter's Υ re-chosen for y keeps the guide's place in the window.
  const long found = same || bugs.upsilon_from_proposal ? long(chosen.index)
                                                        : reverse.index_of(guides, chosen.index);
  if (found < 0 || size_t(found) >= reverse_guides.size())
    return -std::numeric_limits<double>::infinity();
  const uint32_t index = uint32_t(found);
  // x's rows hold for y's unmoved vertices only against the same Υ.
  const SimilarityRows* reuse = same ? rows_x : nullptr;
  const SimilarityParams params = similarity_params(ctx);
  GuideBuffer<double> buffer(reverse_guides.size());
  if (const auto plain = plain_path_similarities(y, reverse_guides, first, last, params,
                                                 buffer.span(), nullptr, reuse)) {
    const double total_y = plain_weight_total(*plain), weight_y = (*plain)[index];
    // (w_y / total_y) / (w_x / total_x) as one log; every factor lies in [1e-150, M], so
    // neither product under- or overflows.
    if (chosen.total > 0.0) return std::log((weight_y * chosen.total) / (total_y * chosen.weight));
    return (std::log(weight_y) - std::log(total_y)) - chosen.log_probability;
  }
  GuideBuffer<SimilarityProduct> weights(reverse_guides.size());
  path_similarities(y, reverse_guides, first, last, params, weights.span(), nullptr, reuse);
  return guide_log_probability(std::span<const SimilarityProduct>(weights.span()), index) -
         chosen.log_p();
}

}  // namespace emlt::ensemble
