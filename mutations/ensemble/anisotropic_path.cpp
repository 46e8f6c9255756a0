#include "mutations/ensemble/anisotropic_path.h"

#include <deque>
#include <optional>

#include "mutations/perturbation_common.h"

namespace emlt {

namespace {

using ensemble::AnisotropicParams;
using ensemble::TangentGaussian;

// Image points live on the plane z = 0 of a 3-D frame, so the tangent-plane Gaussian of
// kernels.h serves the image plane too.
Vec3 on_image_plane(const Vec2& raster) {
  return {raster.x, raster.y, 0.0f};
}

bool printed_covariance(const MutationContext& ctx) {
  return !ctx.ensemble || ctx.ensemble->params().aniso_printed_covariance;
}

// The render's --ensemble-aniso-scale where given, else the form's own: 1 for eq. 11 as
// printed, the strategy's factor for the weighted covariance.
double covariance_scale(double own, const MutationContext& ctx) {
  if (ctx.ensemble && ctx.ensemble->params().aniso_covariance_scale > 0.0)
    return ctx.ensemble->params().aniso_covariance_scale;
  return printed_covariance(ctx) ? 1.0 : own;
}

AnisotropicParams world_params(const AnisotropicPathParams& p, const MutationContext& ctx) {
  AnisotropicParams params;
  params.similarity = ensemble::similarity_params(ctx);
  const double radius = double(ctx.scene.bounds_radius());
  params.covariance_scale = covariance_scale(p.covariance_scale, ctx);
  params.printed_normalisation = printed_covariance(ctx);
  params.floor_sigma = p.floor_fraction * radius;
  params.fallback_concentration =
      ctx.ensemble && ctx.ensemble->params().plane_fallback ? 0.0 : p.fallback_concentration;
  params.fallback_sigma = p.fallback_fraction * radius;
  params.min_effective_guides = p.min_effective_guides;
  if (ctx.ensemble) params.smallest_scale = ctx.ensemble->params().aniso_smallest_scale;
  return params;
}

AnisotropicParams image_params(const AnisotropicPathParams& p, const MutationContext& ctx) {
  AnisotropicParams params;
  // Guides are weighted by the similarity of their world-space vertex only (context).
  params.weight_by_similarity = false;
  params.covariance_scale = covariance_scale(p.image_covariance_scale, ctx);
  params.printed_normalisation = printed_covariance(ctx);
  params.floor_sigma = p.image_floor_sigma;
  params.fallback_sigma = p.image_fallback_sigma;
  params.min_effective_guides = p.min_effective_guides;
  if (ctx.ensemble) params.smallest_scale = ctx.ensemble->params().aniso_smallest_scale;
  return params;
}

// S(v, guide's vertex `index`) for every guide: one row, computed once per step and vertex
// and shared by the fits that use it (as a fit's own weight, and as the context of the fit
// at the neighbouring vertex).
struct SimilarityRow {
  ensemble::GuideBuffer<double> values;
  SimilarityRow(const PathVertex& v, const GuideView& guides, int index, const MutationContext& ctx)
      : values(guides.size()) {
    ensemble::vertex_similarities(v, guides, index, ensemble::similarity_params(ctx),
                                  values.span());
  }
};

constexpr int kImagePoints = -1;

// The guides' points for a fit, as coordinate arrays (GuideSet::point_x...): their vertex j,
// read where Υ keeps them, or their image points on the plane z = 0.
class GuidePoints {
 public:
  GuidePoints(const GuideView& guides, int j)
      : x(guides.coordinates(j, 0)),
        y(guides.coordinates(j, 1)),
        z(guides.coordinates(j, 2)),
        image_(0) {}
  explicit GuidePoints(const GuideView& guides) : image_(3 * guides.size()) {
    const size_t count = guides.size();
    const std::span<double> image = image_.span();
    for (size_t n = 0; n < count; ++n) {
      image[n] = guides.rasters()[n].x;
      image[count + n] = guides.rasters()[n].y;
      image[2 * count + n] = 0.0;
    }
    x = image.subspan(0, count);
    y = image.subspan(count, count);
    z = image.subspan(2 * count, count);
  }
  GuidePoints(const GuidePoints&) = delete;
  GuidePoints& operator=(const GuidePoints&) = delete;

  std::span<const double> x, y, z;

 private:
  ensemble::GuideBuffer<double> image_;
};

// Guide points and weights for a fit: the context is the similarity of one vertex of the
// path to the guides'; `centre` (when the fit weighs by similarity) that of the vertex the
// fit is centred on. Both rows are passed as they are (GuideSet::context_row).
struct GuideData {
  const GuidePoints& points;
  std::span<const double> context, centre;
  GuideData(const GuidePoints& guide_points, const SimilarityRow& context_row,
            const SimilarityRow* centre_row = nullptr)
      : points(guide_points), context(context_row.values.span()) {
    if (centre_row) centre = centre_row->values.span();
  }
  ensemble::GuideSet set() const {
    return {{}, {}, {}, centre, context, points.x, points.y, points.z};
  }
};

// y's Υ for the reverse fits, and what they read from it: the forward move's own points and
// similarity rows where y's Υ is x's (always, with the counter's Υ), else y's, built here.
class ReverseGuides {
 public:
  ReverseGuides(const Path& y, const GuideView& forward, const MutationContext& ctx,
                const ensemble::InjectedBugs& bugs)
      : view(ensemble::reverse_guides_for(y, forward, ctx, bugs)), same_(view.same_as(forward)) {}
  // The guides' vertex j (kImagePoints: their image points), `forward`'s where Υ is the same.
  const GuidePoints& points(const GuidePoints& forward, int j) {
    if (same_) return forward;
    return j == kImagePoints ? points_.emplace_back(view) : points_.emplace_back(view, j);
  }
  // The similarity row of v (vertex j) to the guides, `forward`'s where Υ is the same.
  const SimilarityRow& row(const SimilarityRow& forward, const PathVertex& v, int j,
                           const MutationContext& ctx) {
    if (same_) return forward;
    return rows_.emplace_back(v, view, j, ctx);
  }

  const GuideView view;

 private:
  bool same_;
  std::deque<GuidePoints> points_;  // a deque: its elements stay where they are built
  std::deque<SimilarityRow> rows_;
};

TangentGaussian fit_at(const PathVertex& v, const GuideData& data,
                       const AnisotropicParams& params) {
  return ensemble::fit_tangent_gaussian(v.position, v.normal, data.set(), params);
}

TangentGaussian fit_at_raster(const Vec2& raster, const GuideData& data,
                              const AnisotropicParams& params) {
  return ensemble::fit_tangent_gaussian(on_image_plane(raster), Vec3(0.0f, 0.0f, 1.0f), data.set(),
                                        params);
}

// The Σ-not-refitted bug: x's Gaussian moved to y's point.
TangentGaussian recentred(TangentGaussian gaussian, const Vec3& centre) {
  gaussian.centre = DVec3(centre);
  return gaussian;
}

// The reverse move's Gaussian at y's vertex: refitted there, or (the injected bug) the
// forward one moved.
TangentGaussian reverse_fit(const TangentGaussian& forward, const PathVertex& at,
                            const GuideData& data, const AnisotropicParams& params,
                            const ensemble::InjectedBugs& bugs) {
  return bugs.sigma_not_refitted ? recentred(forward, at.position) : fit_at(at, data, params);
}

// The vertex hit by the ray from `origin` through `through`.
std::optional<PathVertex> cast_through(const Scene& scene, const PathVertex& origin,
                                       const Vec3& through) {
  const Vec3 d = through - origin.position;
  const float length = glm::length(d);
  if (!(length > 0.0f)) return std::nullopt;
  return perturbation::trace_surface(scene, spawn_ray(origin.position, origin.normal, d / length));
}

// Samples `gaussian` (or its vMF fallback), casts from `origin` through the sample and puts
// the hit in `slot`; false when the ray reaches no surface.
bool sample_and_cast(const Scene& scene, const TangentGaussian& gaussian, const PathVertex& origin,
                     Rng& rng, PathVertex& slot) {
  auto hit =
      cast_through(scene, origin, ensemble::sample_cast_target(gaussian, origin.position, rng));
  if (!hit) return false;
  slot = *hit;
  return true;
}

// The density per unit area of reaching `to` by sampling `gaussian` and casting from `from`,
// as parts: a step multiplies its densities and takes one log of the reverse over the forward
// product. With the keep_degenerate_casts bug, rays parallel to the plane are evaluated anyway.
ensemble::DensityParts cast_density(const TangentGaussian& gaussian, const PathVertex& from,
                                    const PathVertex& to, const ensemble::InjectedBugs& bugs) {
  return ensemble::ray_cast_area_density_parts(
      gaussian, from.position, to.position, to.normal,
      bugs.keep_degenerate_casts ? 0.0 : ensemble::kMinPlaneCosine);
}

ensemble::DensityParts product(ensemble::DensityParts a, const ensemble::DensityParts& b) {
  a *= b;
  return a;
}

// y was sampled, so T(x->y) > 0 in exact arithmetic; a forward density that evaluates to zero
// means the cast ran (within rounding) along the kernel's plane, where the plane point is
// not a function of the hit. Such moves are refused, exactly as their reverse evaluates to
// zero, so both directions agree; accepting them with the infinite ratio biases the image.
bool refused(const ensemble::DensityParts& forward, const ensemble::InjectedBugs& bugs) {
  return !forward.positive_and_finite() && !bugs.keep_degenerate_casts;
}

bool usable(const PathVertex& v) {
  return !v.delta && !v.is_camera();
}

}  // namespace

bool AnisotropicPathPerturbation::applies_to(const Path& x, const MutationContext&) const {
  const int k = x.edges();
  if (k < params_.min_edges || k < 3) return false;
  const auto& v = x.vertices;
  return v[size_t(k - 1)].is_surface() && v[size_t(k - 2)].is_surface() &&
         v[size_t(k - 3)].is_surface() && usable(v[size_t(k - 1)]) && usable(v[size_t(k - 2)]) &&
         !v[size_t(k - 3)].delta && !x.type.is_specular(k - 1) && !x.type.is_specular(k - 2) &&
         !x.type.is_specular(k - 3);
}

std::optional<Proposal> AnisotropicPathPerturbation::propose(const Path& x, Rng& rng,
                                                             const MutationContext& ctx) const {
  const auto guides = ensemble::guides_for(x, ctx);
  if (guides.size() < 2) return ensemble::unguided_step(fallback_, x, rng, ctx);
  if (rng.uniform_double() < params_.toward_camera_probability)
    return toward_camera(x, guides, rng, ctx);
  return from_camera(x, guides, rng, ctx);
}

std::optional<Proposal> AnisotropicPathPerturbation::toward_camera(
    const Path& x, const GuideView& guides, Rng& rng, const MutationContext& ctx) const {
  const Scene& scene = ctx.scene;
  const int k = x.edges(), a = k - 1, b = k - 2, c = k - 3;
  const auto& xv = x.vertices;
  const AnisotropicParams world = world_params(params_, ctx);

  // x_b: Gaussian on its tangent plane, weighted by x_b and the fixed x_c; cast from x_c.
  const GuidePoints points_b(guides, b);
  const SimilarityRow s_xc(xv[size_t(c)], guides, c, ctx), s_xb(xv[size_t(b)], guides, b, ctx);
  const TangentGaussian b_x = fit_at(xv[size_t(b)], GuideData(points_b, s_xc, &s_xb), world);
  Proposal proposal;
  Path& y = proposal.path;
  y = x;
  auto& yv = y.vertices;
  if (!sample_and_cast(scene, b_x, xv[size_t(c)], rng, yv[size_t(b)])) return std::nullopt;

  // x_a: Gaussian on its tangent plane, weighted by x_a and the centre path's own x_b (x's
  // here, y's for the reverse fit); cast from the new y_b.
  const GuidePoints points_a(guides, a);
  const SimilarityRow s_xa(xv[size_t(a)], guides, a, ctx);
  const TangentGaussian a_x = fit_at(xv[size_t(a)], GuideData(points_a, s_xb, &s_xa), world);
  if (!sample_and_cast(scene, a_x, yv[size_t(b)], rng, yv[size_t(a)])) return std::nullopt;

  // The fixed lens point sees y_a: the image point moves (an orthographic film point with it).
  PathVertex& lens = yv.back();
  if (!perturbation::aim_lens_at(scene, lens, yv[size_t(a)])) return std::nullopt;
  const Rgb connection = connect_vertices(scene, &yv[size_t(b)], yv[size_t(a)], lens, nullptr);
  if (is_black(connection) || !is_finite(connection)) return std::nullopt;
  // Only y_b and y_a moved (the lens point kept its position; its density does not depend on
  // the raster): the densities that depend on them are recomputed, the rest are x's.
  if (!perturbation::finish_proposal(scene, x, y, b, a)) return std::nullopt;

  // Both moves are densities per unit area of (y_b, y_a) and of (x_b, x_a): no Jacobian.
  const ensemble::DensityParts forward =
      product(cast_density(b_x, xv[size_t(c)], yv[size_t(b)], bugs_),
              cast_density(a_x, yv[size_t(b)], yv[size_t(a)], bugs_));
  if (refused(forward, bugs_)) return std::nullopt;
  // The reverse fits use y's Υ: the same as x's unless y's image point moved to another.
  ReverseGuides reverse_guides(y, guides, ctx, bugs_);
  const GuidePoints& rpoints_b = reverse_guides.points(points_b, b);
  const GuidePoints& rpoints_a = reverse_guides.points(points_a, a);
  const SimilarityRow& rs_xc = reverse_guides.row(s_xc, xv[size_t(c)], c, ctx);
  const SimilarityRow s_yb(yv[size_t(b)], reverse_guides.view, b, ctx),
      s_ya(yv[size_t(a)], reverse_guides.view, a, ctx);
  const TangentGaussian b_y =
      reverse_fit(b_x, yv[size_t(b)], GuideData(rpoints_b, rs_xc, &s_yb), world, bugs_);
  const TangentGaussian a_y =
      reverse_fit(a_x, yv[size_t(a)], GuideData(rpoints_a, s_yb, &s_ya), world, bugs_);
  const ensemble::DensityParts reverse =
      bugs_.drop_reverse_density ? forward
                                 : product(cast_density(b_y, xv[size_t(c)], xv[size_t(b)], bugs_),
                                           cast_density(a_y, xv[size_t(b)], xv[size_t(a)], bugs_));
  proposal.log_reverse_over_forward = ensemble::log_ratio(reverse, forward);
  if (std::isnan(proposal.log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

std::optional<Proposal> AnisotropicPathPerturbation::from_camera(const Path& x,
                                                                 const GuideView& guides, Rng& rng,
                                                                 const MutationContext& ctx) const {
  const Scene& scene = ctx.scene;
  const int k = x.edges(), a = k - 1, b = k - 2, c = k - 3;
  const auto& xv = x.vertices;
  const AnisotropicParams image = image_params(params_, ctx), world = world_params(params_, ctx);

  // Image point: Gaussian fitted to the guides' image points, weighted by their x_a.
  const GuidePoints image_points(guides);
  const SimilarityRow s_xa(xv[size_t(a)], guides, a, ctx);
  const TangentGaussian image_x = fit_at_raster(x.raster(), GuideData(image_points, s_xa), image);
  const Vec3 sample = ensemble::sample_tangent_gaussian(image_x, rng);
  const Vec2 raster(sample.x, sample.y);
  if (!perturbation::on_film(scene.camera(), raster)) return std::nullopt;

  Proposal proposal;
  Path& y = proposal.path;
  y = x;
  auto& yv = y.vertices;
  yv.back().raster = raster;
  const Ray eye_ray = scene.camera().generate_ray_from_lens_point(raster, xv.back().position);
  // An orthographic camera's film point moves with the image point (camera.h).
  if (yv.back().kind == VertexKind::OrthographicCamera) yv.back().position = eye_ray.origin;
  auto hit_a = perturbation::trace_surface(scene, eye_ray);
  if (!hit_a) return std::nullopt;
  yv[size_t(a)] = *hit_a;

  // x_b: Gaussian on its tangent plane, weighted by x_b and the fixed x_c; cast from y_a.
  const GuidePoints world_points(guides, b);
  const SimilarityRow s_xc(xv[size_t(c)], guides, c, ctx), s_xb(xv[size_t(b)], guides, b, ctx);
  const TangentGaussian world_x =
      fit_at(xv[size_t(b)], GuideData(world_points, s_xc, &s_xb), world);
  if (!sample_and_cast(scene, world_x, yv[size_t(a)], rng, yv[size_t(b)])) return std::nullopt;
  const Rgb connection = connect_vertices(scene, c >= 1 ? &yv[size_t(c - 1)] : nullptr,
                                          yv[size_t(c)], yv[size_t(b)], &yv[size_t(a)]);
  if (is_black(connection) || !is_finite(connection)) return std::nullopt;
  if (!perturbation::finish_proposal(scene, x, y, b, a)) return std::nullopt;  // as above

  const ensemble::DensityParts forward =
      product(ensemble::tangent_gaussian_pdf_parts(image_x, on_image_plane(raster)),
              cast_density(world_x, yv[size_t(a)], yv[size_t(b)], bugs_));
  if (refused(forward, bugs_)) return std::nullopt;
  // The reverse fits use y's Υ (near y's image point).
  ReverseGuides reverse_guides(y, guides, ctx, bugs_);
  const GuidePoints& rimage_points = reverse_guides.points(image_points, kImagePoints);
  const GuidePoints& rworld_points = reverse_guides.points(world_points, b);
  const SimilarityRow& rs_xc = reverse_guides.row(s_xc, xv[size_t(c)], c, ctx);
  const SimilarityRow s_ya(yv[size_t(a)], reverse_guides.view, a, ctx),
      s_yb(yv[size_t(b)], reverse_guides.view, b, ctx);
  const TangentGaussian image_y =
      bugs_.sigma_not_refitted ? recentred(image_x, on_image_plane(raster))
                               : fit_at_raster(raster, GuideData(rimage_points, s_ya), image);
  const TangentGaussian world_y =
      reverse_fit(world_x, yv[size_t(b)], GuideData(rworld_points, rs_xc, &s_yb), world, bugs_);
  const ensemble::DensityParts reverse =
      bugs_.drop_reverse_density
          ? forward
          : product(ensemble::tangent_gaussian_pdf_parts(image_y, on_image_plane(x.raster())),
                    cast_density(world_y, xv[size_t(a)], xv[size_t(b)], bugs_));
  proposal.log_reverse_over_forward = ensemble::log_ratio(reverse, forward) +
                                      perturbation::log_eye_jacobian(x, a) -
                                      perturbation::log_eye_jacobian(y, a);
  if (std::isnan(proposal.log_reverse_over_forward)) return std::nullopt;
  return proposal;
}

}  // namespace emlt
