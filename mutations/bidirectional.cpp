#include "mutations/bidirectional.h"

#include "emlt/mcmc/two_tailed_geometric.h"
#include "emlt/path/connection.h"
#include "emlt/path/random_walk.h"

namespace emlt {

namespace {

// Whether the inserted n_new vertices may be split as s light-side + t eye-side, given
// the kept prefix length a and suffix length c.
bool split_allowed(int a, int c, int n_new, int s) {
  const int t = n_new - s;
  if (a == 1 && s > 0) return false;  // no walk from a lone kept light point
  if (c == 1 && t > 0) return false;  // no walk from a lone kept lens point
  if (c == 0 && t == 0) return false; // the lens is only ever generated from the eye side
  return true;
}

// The number of s in [0, n_new] that split_allowed accepts, in closed form: the move
// proposes, and both densities evaluate, it for every candidate position.
int count_splits(int a, int c, int n_new) {
  int low = 0, high = n_new;
  if (a == 1) high = std::min(high, 0);           // s = 0 only
  if (c == 1) low = std::max(low, n_new);         // t = 0 only
  if (c == 0) high = std::min(high, n_new - 1);   // t >= 1
  return std::max(high - low + 1, 0);
}

bool position_allowed(const Path& x, int a, int d, int n_new) {
  const int n = int(x.vertices.size()), c = n - a - d;
  if (c < 0) return false;
  if (d == 0 && (a == 0 || c == 0)) return false;  // x0 or the lens would become interior
  if (a >= 1 && x.vertices[size_t(a - 1)].delta) return false;
  if (c >= 1 && x.vertices[size_t(a + d)].delta) return false;
  return count_splits(a, c, n_new) > 0;
}

// How many positions a admit deleting d vertices of x and inserting n_new.
int count_positions(const Path& x, int d, int n_new) {
  const int n = int(x.vertices.size());
  int positions = 0;
  for (int p = 0; p <= n - d; ++p) positions += position_allowed(x, p, d, n_new);
  return positions;
}

int deletion_minimum(int edges, int new_edges) {
  return std::max(edges - new_edges, new_edges == edges ? 1 : 0);
}

// P(new length) P(d) P(a) of deleting [a, a + d) from x to reach new_edges segments.
double selection_pmf(const Path& x, int new_edges, int a, int d, const MutationContext& ctx) {
  const int edges = x.edges(), n = edges + 1;
  const double p_length = TwoTailedGeometric(edges, ctx.min_edges, ctx.max_edges).pmf(new_edges);
  const int d_min = deletion_minimum(edges, new_edges);
  const double p_delete = TwoTailedGeometric(1, d_min, n).pmf(d);
  const int n_new = d + new_edges - edges;
  if (!(p_length > 0.0) || !(p_delete > 0.0) || n_new < 0) return 0.0;
  if (!position_allowed(x, a, d, n_new)) return 0.0;
  return p_length * p_delete / double(count_positions(x, d, n_new));
}

// (1/|S|) sum over splits of the density of y's vertices [a, a + n_new), each from its side.
double split_average_density(const Path& y, int a, int n_new, int c) {
  const int splits = count_splits(a, c, n_new);
  if (splits == 0) return 0.0;
  const auto& v = y.vertices;
  const int n = int(v.size());
  double sum = 0.0;
  for (int s = 0; s <= n_new; ++s) {
    if (!split_allowed(a, c, n_new, s)) continue;
    const int light_end = a + s - 1, eye_end = a + s;
    if (light_end >= 0 && v[size_t(light_end)].delta) continue;
    if (eye_end < n && v[size_t(eye_end)].delta) continue;
    if (light_end < 0 && !v[0].is_emitter()) continue;
    // The sky joined to an orthographic film (connect_vertices: never seen that way).
    if (eye_end == n - 1 && light_end >= 0 && v[size_t(light_end)].is_environment() &&
        v[size_t(eye_end)].kind == VertexKind::OrthographicCamera)
      continue;
    double p = 1.0;
    for (int i = a; i < a + s; ++i) p *= double(v[size_t(i)].pdf_from_light);
    for (int i = a + s; i < a + n_new; ++i) p *= double(v[size_t(i)].pdf_from_eye);
    sum += p;
  }
  return sum / double(splits);
}

}  // namespace

double BidirectionalMutation::proposal_density(const Path& from, const Path& to, int a, int d,
                                               const MutationContext& ctx) {
  const int n_new = int(to.vertices.size()) - (int(from.vertices.size()) - d);
  const int c = int(from.vertices.size()) - a - d;
  return selection_pmf(from, to.edges(), a, d, ctx) * split_average_density(to, a, n_new, c);
}

std::optional<Proposal> BidirectionalMutation::propose(const Path& x, Rng& rng,
                                                       const MutationContext& ctx) const {
  const int edges = x.edges(), n = edges + 1;

  // Lengths, deleted stretch, position, split.
  const TwoTailedGeometric lengths(edges, ctx.min_edges, ctx.max_edges);
  if (lengths.empty()) return std::nullopt;
  const int new_edges = lengths.sample(rng.uniform());
  const int d_min = deletion_minimum(edges, new_edges);
  if (d_min > n) return std::nullopt;
  const TwoTailedGeometric deletions(1, d_min, n);
  const int d = deletions.sample(rng.uniform());
  const int n_new = d + new_edges - edges;
  bool local[kMaxPathVertices + 1];
  std::vector<bool> heap;  // only for paths longer than the path layer's cap
  if (n > kMaxPathVertices) heap.resize(size_t(n + 1));
  const auto allowed = [&](int p) { return n > kMaxPathVertices ? bool(heap[size_t(p)]) : local[p]; };
  int positions = 0;
  for (int p = 0; p <= n - d; ++p) {
    const bool ok = position_allowed(x, p, d, n_new);
    if (n > kMaxPathVertices) heap[size_t(p)] = ok;
    else local[p] = ok;
    positions += ok;
  }
  if (positions == 0) return std::nullopt;
  int a = -1;
  for (int p = 0, pick = int(rng.uniform_index(uint32_t(positions))); p <= n - d; ++p)
    if (allowed(p) && pick-- == 0) {
      a = p;
      break;
    }
  const int c = n - a - d;
  int s = -1;
  for (int q = 0, pick = int(rng.uniform_index(uint32_t(count_splits(a, c, n_new)))); q <= n_new; ++q)
    if (split_allowed(a, c, n_new, q) && pick-- == 0) {
      s = q;
      break;
    }
  auto y = regenerate(x, a, d, n_new, s, rng, ctx);
  if (!y) return std::nullopt;
  Proposal proposal;
  proposal.path = std::move(*y);
  // The forward selection terms are the ones just sampled from (selection_pmf's values).
  const double p_length = lengths.pmf(new_edges), p_delete = deletions.pmf(d);
  const double forward = p_length > 0.0 && p_delete > 0.0 && n_new >= 0
                             ? p_length * p_delete / double(positions) *
                                   split_average_density(proposal.path, a, n_new, c)
                             : 0.0;
  if (!(forward > 0.0) || !std::isfinite(forward)) return std::nullopt;
  const double reverse = proposal_density(proposal.path, x, a, n_new, ctx);
  // One logarithm where the quotient is representable (almost always); two where the
  // densities are so far apart that it over- or underflows.
  const double quotient = reverse / forward;
  proposal.log_reverse_over_forward =
      !(reverse > 0.0)                                  ? -std::numeric_limits<double>::infinity()
      : std::isnormal(quotient) && std::isfinite(quotient) ? std::log(quotient)
                                                        : std::log(reverse) - std::log(forward);
  return proposal;
}

double BidirectionalMutation::inserted_density(const Path& y, int a, int n_new, int c) {
  return split_average_density(y, a, n_new, c);
}

std::optional<Path> BidirectionalMutation::regenerate(const Path& x, int a, int d, int n_new, int s,
                                                      Rng& rng, const MutationContext& ctx) {
  const Scene& scene = ctx.scene;
  const auto& xv = x.vertices;
  const int n = int(xv.size()), c = n - a - d;
  if (a < 0 || d < 0 || c < 0 || s < 0 || s > n_new || !split_allowed(a, c, n_new, s)) return std::nullopt;
  const int t = n_new - s;
  // Light side: a fresh light subpath, or a walk on from the kept prefix end. The walks'
  // buffers are reused across calls on a thread: a chain step should not allocate for them.
  thread_local PathVertices light_walk, eye_walk;
  light_walk.clear();
  eye_walk.clear();
  if (s > 0) {
    if (a == 0) {
      if (generate_light_subpath(scene, rng, {s, -1}, light_walk) != s) return std::nullopt;
    } else {
      light_walk.push_back(xv[size_t(a - 2)]);
      light_walk.push_back(xv[size_t(a - 1)]);
      light_walk[1].throughput = Rgb(1.0f);
      if (random_walk(scene, rng, TransportMode::Importance, s, -1, light_walk) != s)
        return std::nullopt;
    }
  }
  // Eye side: a fresh camera subpath through a uniformly chosen raster position, or a walk
  // on from the kept suffix start.
  if (t > 0) {
    if (c == 0) {
      const Camera& camera = scene.camera();
      const Vec2 raster(rng.uniform() * float(camera.width()), rng.uniform() * float(camera.height()));
      const Vec2 u_lens = rng.uniform2();
      if (generate_camera_subpath(scene, rng, raster, u_lens, {t, -1}, eye_walk) != t)
        return std::nullopt;
    } else {
      eye_walk.push_back(xv[size_t(a + d + 1)]);
      eye_walk.push_back(xv[size_t(a + d)]);
      eye_walk[1].throughput = Rgb(1.0f);
      if (random_walk(scene, rng, TransportMode::Radiance, t, -1, eye_walk) != t)
        return std::nullopt;
    }
  }

  // Assemble y: prefix, light-side vertices, eye-side vertices reversed, suffix. A kept end
  // that a walk left from carries that walk's sampling record, so take the walk's copy.
  Path y;
  auto& yv = y.vertices;
  yv.reserve(size_t(n - d + n_new));
  for (int i = 0; i < a; ++i) yv.push_back(xv[size_t(i)]);
  if (a >= 2 && s > 0) yv.back() = light_walk[1];
  const size_t light_skip = a == 0 ? 0 : 2;
  for (size_t i = light_skip; i < light_walk.size(); ++i) yv.push_back(light_walk[i]);
  const size_t eye_skip = c == 0 ? 0 : 2;
  for (size_t i = eye_walk.size(); i > eye_skip; --i) yv.push_back(eye_walk[i - 1]);
  for (int i = a + d; i < n; ++i) yv.push_back(xv[size_t(i)]);
  if (c >= 2 && t > 0) yv[size_t(a + n_new)] = eye_walk[1];
  const int m = int(yv.size());
  if (m != n - d + n_new || m < 2) return std::nullopt;

  // Structure: the sky only as x0, an emitter at x0, the lens only at the end.
  if (!yv[0].is_emitter() || !yv.back().is_camera()) return std::nullopt;
  for (int i = 1; i < m; ++i)
    if (yv[size_t(i)].is_environment()) return std::nullopt;
  for (int i = 0; i + 1 < m; ++i)
    if (yv[size_t(i)].is_camera()) return std::nullopt;

  // The connection edge (none when the eye walk itself reached the emitter).
  const int light_end = a + s - 1, eye_end = a + s;
  if (light_end >= 0) {
    PathVertex& y = yv[size_t(light_end)];
    PathVertex& z = yv[size_t(eye_end)];
    y.delta = false;
    z.delta = false;
    // An orthographic camera's film point is the one that sees y: it moves to y's
    // projection (a function of y, so no density of its own: camera.h).
    if (z.kind == VertexKind::OrthographicCamera) {
      if (y.is_environment()) return std::nullopt;  // connect_vertices: never seen
      const auto film = scene.camera().sample_direct(y.position, Vec2(0.5f));
      if (!film) return std::nullopt;
      z.position = film->lens_point;
      z.raster = film->raster;
    }
    const Rgb connection = connect_vertices(scene, light_end >= 1 ? &yv[size_t(light_end - 1)] : nullptr,
                                            y, z, eye_end + 1 < m ? &yv[size_t(eye_end + 1)] : nullptr);
    if (is_black(connection) || !is_finite(connection)) return std::nullopt;
    if (z.kind == VertexKind::Camera) {  // connected straight to a kept lens point: the pixel moves
      const auto raster = scene.camera().raster_position(z.position, direction_between(z, y));
      if (!raster) return std::nullopt;
      z.raster = *raster;
    }
  }
  y.type = compute_path_type(yv);
  // Records changed only from the kept light end to the kept eye end (the walks' copies,
  // the connection ends' Dirac flags); the rest carry x's densities.
  recompute_densities(scene, y, a - 1, a + n_new);
  return y;
}

}  // namespace emlt
