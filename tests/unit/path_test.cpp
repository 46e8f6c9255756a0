// The path layer: density bookkeeping, contributions, MIS weights and connections, checked
// on random paths of the shipped scenes (diffuse, specular glass + rough metal, sky-lit).
#include "emlt/path/path.h"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>

#include "emlt/path/connection.h"
#include "emlt/path/random_walk.h"
#include "emlt/scene/loaders/loader.h"
#include "support/test_support.h"

using namespace emlt;

namespace {

std::unique_ptr<Scene> shipped_scene(const std::string& name) {
  SceneDescription desc =
      load_scene_description(test::source_path("scenes/" + name + "/scene.json"), {});
  desc.camera.width = desc.camera.height = 16;
  return Scene::build(std::move(desc));
}

const char* const kScenes[] = {"cornell-box", "cornell-glass", "env-sky"};

bool close(double a, double b, double tolerance = 1e-3) {
  return a == b || std::abs(a - b) <= tolerance * std::max(std::abs(a), std::abs(b));
}

// A BDPT sample's connection, as a whole path plus the estimator BDPT computes for it.
struct SampledPath {
  Path path;
  int s = 0, t = 0;
  Rgb estimate{0.0f};  // throughput(y) * connection * throughput(z), unweighted
};

// Calls `visit` for every strategy of `samples` random subpath pairs whose connection
// carries light (no Russian roulette, at most 5 vertices per subpath).
void for_each_random_path(const Scene& scene, int samples,
                          const std::function<void(const SampledPath&)>& visit) {
  const WalkLimits limits{5, -1};
  PathVertices light, camera;
  for (int i = 0; i < samples; ++i) {
    Rng rng(42, uint64_t(i));
    const Vec2 raster =
        rng.uniform2() * Vec2(float(scene.camera().width()), float(scene.camera().height()));
    generate_camera_subpath(scene, rng, raster, rng.uniform2(), limits, camera);
    generate_light_subpath(scene, rng, limits, light);
    for (int t = 1; t <= int(camera.size()); ++t) {
      for (int s = 0; s <= int(light.size()); ++s) {
        if (s + t < 2) continue;
        SampledPath sample;
        sample.s = s;
        sample.t = t;
        PathVertex lens;
        std::span<const PathVertex> camera_side(camera);
        if (s == 0) {
          const PathVertex& z = camera[size_t(t - 1)];
          if (!z.is_emitter()) continue;
          sample.estimate = z.throughput * vertex_factor(scene, z, nullptr, &camera[size_t(t - 2)]);
        } else if (t == 1) {
          const auto sampled = sample_camera_vertex(scene, light[size_t(s - 1)], rng.uniform2());
          if (!sampled) continue;
          lens = *sampled;
          camera_side = std::span<const PathVertex>(&lens, 1);
          sample.estimate = light[size_t(s - 1)].throughput *
                            connect_vertices(scene, s >= 2 ? &light[size_t(s - 2)] : nullptr,
                                             light[size_t(s - 1)], lens, nullptr) *
                            lens.throughput;
        } else {
          sample.estimate = light[size_t(s - 1)].throughput *
                            connect_vertices(scene, s >= 2 ? &light[size_t(s - 2)] : nullptr,
                                             light[size_t(s - 1)], camera[size_t(t - 1)],
                                             &camera[size_t(t - 2)]) *
                            camera[size_t(t - 1)].throughput;
        }
        if (is_black(sample.estimate)) continue;
        ASSERT_TRUE(join_subpaths(scene, light, s, camera_side, t, sample.path));
        visit(sample);
      }
    }
  }
}

}  // namespace

TEST(PathType, HeckbertNotation) {
  PathVertices vertices(5);
  vertices[2].delta = true;
  const PathType type = compute_path_type(vertices);
  EXPECT_EQ(type.to_string(), "L D S D E");
  EXPECT_EQ(type.edges(), 4);
  vertices[3].delta = true;
  const PathType other = compute_path_type(vertices);
  EXPECT_EQ(other.to_string(), "L D S S E");
  EXPECT_FALSE(type == other);
  EXPECT_NE(std::hash<PathType>()(type), std::hash<PathType>()(other));
}

TEST(PathDensities, StoredDensitiesEqualADirectRecomputationForEverySplit) {
  for (const char* name : kScenes) {
    const auto scene = shipped_scene(name);
    int paths = 0, splits = 0;
    for_each_random_path(*scene, 300, [&](const SampledPath& sample) {
      Path recomputed = sample.path;
      recompute_densities(*scene, recomputed);
      const int n = int(sample.path.vertices.size());
      for (int i = 0; i < n; ++i) {
        const PathVertex &a = sample.path.vertices[size_t(i)], &b = recomputed.vertices[size_t(i)];
        EXPECT_TRUE(close(a.pdf_from_light, b.pdf_from_light))
            << name << " s=" << sample.s << " t=" << sample.t << " vertex " << i << ": "
            << a.pdf_from_light << " vs " << b.pdf_from_light;
        EXPECT_TRUE(close(a.pdf_from_eye, b.pdf_from_eye))
            << name << " s=" << sample.s << " t=" << sample.t << " vertex " << i << ": "
            << a.pdf_from_eye << " vs " << b.pdf_from_eye;
      }
      for (int split = 0; split <= n; ++split) {
        EXPECT_TRUE(close(path_density(sample.path, split), path_density(recomputed, split)))
            << name << " p_" << split;
        ++splits;
      }
      // The split that generated the path is possible and has a positive density.
      EXPECT_GT(path_density(sample.path, sample.s), 0.0) << name << " s=" << sample.s;
      ++paths;
    });
    EXPECT_GT(paths, 200) << name;
    EXPECT_GT(splits, 1000) << name;
  }
}

// The mutations recompute only the densities that depend on the vertices they moved
// (recompute_densities(scene, path, first, last)). Move a stretch [first, last] of a path
// (its vertices replaced by those of another path of the same length, so positions,
// normals, BSDFs and Dirac records all change), scramble every density the window must
// cover, and the windowed recomputation must give exactly the full one's bits; a window one
// vertex too narrow on either side must not.
TEST(PathDensities, WindowedRecomputationEqualsTheFullOneBitForBit) {
  for (const char* name : kScenes) {
    const auto scene = shipped_scene(name);
    std::vector<Path> paths;
    // Current densities, as every path a mutation starts from has them (a walk's own stored
    // values agree with a recomputation only to rounding).
    for_each_random_path(*scene, 200, [&](const SampledPath& sample) {
      paths.push_back(sample.path);
      recompute_densities(*scene, paths.back());
    });
    int compared = 0, narrow_caught = 0, narrow_tried = 0;
    for (size_t p = 0; p + 1 < paths.size(); ++p) {
      const Path& x = paths[p];
      const Path* donor = nullptr;
      for (size_t q = p + 1; q < paths.size() && !donor; ++q)
        if (paths[q].vertices.size() == x.vertices.size()) donor = &paths[q];
      if (!donor) continue;
      const int k = int(x.vertices.size()) - 1;
      for (int first = 1; first <= k - 1; ++first)
        for (int last = first; last <= k - 1; ++last) {
          Path moved = x;
          for (int i = first; i <= last; ++i)
            moved.vertices[size_t(i)] = donor->vertices[size_t(i)];
          Path full = moved;
          recompute_densities(*scene, full);
          const auto windowed = [&](int a, int b) {
            Path y = moved;
            for (int i = 0; i <= k; ++i) {  // stale values where the window must write
              if (i >= first && i <= last + 2) y.vertices[size_t(i)].pdf_from_light = -1.0f;
              if (i >= first - 2 && i <= last) y.vertices[size_t(i)].pdf_from_eye = -1.0f;
            }
            // Outside the moved stretch, x's (current) densities stand in the copy.
            recompute_densities(*scene, y, a, b);
            for (int i = 0; i <= k; ++i) {
              const PathVertex &u = y.vertices[size_t(i)], &v = full.vertices[size_t(i)];
              if (std::memcmp(&u.pdf_from_light, &v.pdf_from_light, sizeof(float)) != 0 ||
                  std::memcmp(&u.pdf_from_eye, &v.pdf_from_eye, sizeof(float)) != 0)
                return false;
            }
            return true;
          };
          // Densities outside the window come from `moved`, i.e. from x: they are only
          // right if they do not depend on the moved stretch, which is the window's claim.
          EXPECT_TRUE(windowed(first, last)) << name << " window [" << first << ", " << last << "]";
          ++compared;
          if (last < k - 1) {
            ++narrow_tried;
            narrow_caught += !windowed(first, last - 1);
          }
        }
    }
    EXPECT_GT(compared, 100) << name;
    // A narrowed window leaves some scrambled or stale density behind.
    EXPECT_EQ(narrow_caught, narrow_tried) << name;
  }
}

TEST(PathDensities, MisWeightsOfEveryPathSumToOne) {
  for (const char* name : kScenes) {
    const auto scene = shipped_scene(name);
    for_each_random_path(*scene, 100, [&](const SampledPath& sample) {
      const auto densities = path_densities(sample.path);
      for (MisHeuristic h : {MisHeuristic::Balance, MisHeuristic::Power, MisHeuristic::Max,
                             MisHeuristic::SecondOrder}) {
        double sum = 0.0;
        for (int split = 0; split <= int(densities.size()); ++split)
          if (split_is_possible(densities, split)) sum += mis_weight(densities, split, h);
        EXPECT_NEAR(sum, 1.0, 1e-6) << name << " " << sample.path.type.to_string();
      }
      // The balance heuristic is p_s / sum of p_s' by definition.
      double total = 0.0;
      for (int split = 0; split <= int(densities.size()); ++split)
        total += split_density(densities, split);
      EXPECT_TRUE(close(mis_weight(densities, sample.s, MisHeuristic::Balance),
                        split_density(densities, sample.s) / total, 1e-4));
      // The maximum heuristic gives nothing to a split another one beats.
      double largest = 0.0;
      for (int split = 0; split <= int(densities.size()); ++split)
        largest = std::max(largest, split_density(densities, split));
      const double own = split_density(densities, sample.s);
      if (own < largest * (1.0 - 1e-6)) {
        EXPECT_EQ(mis_weight(densities, sample.s, MisHeuristic::Max), 0.0);
      }
    });
  }
}

TEST(PathContribution, OverTheGeneratingDensityEqualsTheBdptEstimate) {
  for (const char* name : kScenes) {
    const auto scene = shipped_scene(name);
    int checked = 0;
    for_each_random_path(*scene, 200, [&](const SampledPath& sample) {
      const DVec3 f = path_contribution(*scene, sample.path);
      const double p = path_density(sample.path, sample.s);
      for (int c = 0; c < 3; ++c)
        EXPECT_TRUE(close(f[c] / p, sample.estimate[c], 2e-3))
            << name << " s=" << sample.s << " t=" << sample.t << " " << sample.path.type.to_string()
            << ": " << f[c] / p << " vs " << sample.estimate[c];
      EXPECT_DOUBLE_EQ(path_luminance(*scene, sample.path),
                       0.2126 * f.x + 0.7152 * f.y + 0.0722 * f.z);
      ++checked;
    });
    EXPECT_GT(checked, 100) << name;
  }
}

TEST(PathLayer, NoNonFiniteValueLeavesIt) {
  for (const char* name : kScenes) {
    const auto scene = shipped_scene(name);
    InvalidCounter invalid;
    PathVertices light, camera;
    for (int i = 0; i < 2000; ++i) {
      Rng rng(7, uint64_t(i));
      generate_camera_subpath(*scene, rng, rng.uniform2() * 16.0f, rng.uniform2(), {12, 3}, camera,
                              &invalid);
      generate_light_subpath(*scene, rng, {12, 3}, light, &invalid);
      for (const auto* subpath : {&light, &camera})
        for (const PathVertex& v : *subpath) {
          EXPECT_TRUE(is_finite(v.throughput));
          EXPECT_TRUE(std::isfinite(v.pdf_from_light) && v.pdf_from_light >= 0.0f);
          EXPECT_TRUE(std::isfinite(v.pdf_from_eye) && v.pdf_from_eye >= 0.0f);
        }
    }
    EXPECT_EQ(invalid.count, 0u) << name;
  }
  InvalidCounter counter;
  Rgb bad(std::numeric_limits<float>::quiet_NaN(), 1.0f, 1.0f);
  EXPECT_FALSE(counter.keep(bad));
  EXPECT_TRUE(is_black(bad));
  EXPECT_EQ(counter.count, 1u);
}

TEST(Connection, SpecularVerticesAreNeverConnectedAndMarkTheirPathType) {
  const auto scene = shipped_scene("cornell-glass");
  PathVertices light, camera;
  int glass_vertices = 0, specular_types = 0;
  for (int i = 0; i < 500; ++i) {
    Rng rng(3, uint64_t(i));
    generate_camera_subpath(*scene, rng, rng.uniform2() * 16.0f, rng.uniform2(), {6, -1}, camera);
    generate_light_subpath(*scene, rng, {3, -1}, light);
    if (light.empty()) continue;
    for (size_t j = 1; j < camera.size(); ++j) {
      const PathVertex& z = camera[j];
      if (!z.bsdf || !z.bsdf->is_purely_delta()) continue;
      ++glass_vertices;
      EXPECT_TRUE(
          is_black(connect_vertices(*scene, light.size() > 1 ? &light[light.size() - 2] : nullptr,
                                    light.back(), z, &camera[j - 1])));
    }
  }
  for_each_random_path(*scene, 500, [&](const SampledPath& sample) {
    const auto densities = path_densities(sample.path);
    for (size_t i = 1; i + 1 < densities.size(); ++i) {
      if (!sample.path.vertices[i].delta) continue;
      EXPECT_EQ(sample.path.type.to_string()[2 * i], 'S');
      EXPECT_FALSE(split_is_possible(densities, int(i)));
      EXPECT_FALSE(split_is_possible(densities, int(i) + 1));
      ++specular_types;
    }
  });
  EXPECT_GT(glass_vertices, 20);
  EXPECT_GT(specular_types, 5);
}

TEST(Connection, CameraVertexRasterIsWhereThePathLands) {
  const auto scene = shipped_scene("cornell-box");
  const Camera& camera = scene->camera();
  PathVertices light, camera_path;
  int lens_vertices = 0;
  for (int i = 0; i < 200; ++i) {
    Rng rng(9, uint64_t(i));
    const Vec2 raster = rng.uniform2() * 16.0f;
    generate_camera_subpath(*scene, rng, raster, rng.uniform2(), {3, -1}, camera_path);
    ASSERT_FALSE(camera_path.empty());
    EXPECT_EQ(camera_path[0].raster, raster);
    generate_light_subpath(*scene, rng, {3, -1}, light);
    for (const PathVertex& y : light) {
      const auto lens = sample_camera_vertex(*scene, y, rng.uniform2());
      if (!lens) continue;
      const auto expected = camera.raster_position(lens->position, direction_between(*lens, y));
      ASSERT_TRUE(expected.has_value());
      EXPECT_NEAR(lens->raster.x, expected->x, 1e-3f);
      EXPECT_NEAR(lens->raster.y, expected->y, 1e-3f);
      ++lens_vertices;
    }
  }
  EXPECT_GT(lens_vertices, 50);
}

// Russian roulette in the bidirectional walks starts where Mitsuba's bidirectional
// integrators start it for the same rrDepth: it may end a subpath's rrDepth-th segment
// (subpath_rr_depth). Inside a closed sphere little but the roulette ends a walk, so with
// rrDepth 3 the subpaths have at least 2 segments, and many exactly 2 (the roulette's
// survival there is the throughput, 0.5 per bounce). Counting from one segment later left
// every subpath at least 3 segments long.
TEST(RandomWalk, BidirectionalRouletteStartsAtMitsubasSegment) {
  const auto dir = test::scratch_dir("walk-roulette");
  const std::string path = test::write_file(dir, "sphere.json", R"({
    "camera": {"lookat": {"origin": [0, 0, 0], "target": [0, 0, 1], "up": [0, 1, 0]},
               "fov": 40, "width": 16, "height": 16},
    "integrator": {"type": "bdpt", "max_depth": -1, "rr_depth": 3},
    "materials": {"grey": {"type": "diffuse", "reflectance": [0.5, 0.5, 0.5]}},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 10, "flip_normals": true,
                "material": "grey", "emission": [1, 1, 1]}]
  })");
  SceneDescription desc = load_scene_description(path, {});
  const int rr_depth = 3;
  ASSERT_EQ(desc.render.said("--rr-depth"), std::to_string(rr_depth));
  const auto scene = Scene::build(std::move(desc));
  const WalkLimits limits{64, subpath_rr_depth(rr_depth)};
  Rng rng(11, 0);
  PathVertices subpath;
  std::vector<int> camera_segments(64, 0), light_segments(64, 0);
  for (int i = 0; i < 4000; ++i) {
    generate_camera_subpath(*scene, rng, rng.uniform2() * 16.0f, rng.uniform2(), limits, subpath);
    ASSERT_GE(subpath.size(), 2u);
    ++camera_segments[subpath.size() - 1];
    generate_light_subpath(*scene, rng, limits, subpath);
    ASSERT_GE(subpath.size(), 2u);
    ++light_segments[subpath.size() - 1];
  }
  // Before the roulette only the rare grazing ray that slips off the sphere's tangent
  // ends a walk (3 light subpaths of 4000 here).
  for (int k = 0; k < rr_depth - 1; ++k) {
    EXPECT_LT(camera_segments[size_t(k)], 20) << k << " segments";
    EXPECT_LT(light_segments[size_t(k)], 20) << k << " segments";
  }
  // About half of the subpaths stop at the first roulette (survival 0.5).
  EXPECT_GT(camera_segments[size_t(rr_depth - 1)], 1000);
  EXPECT_GT(light_segments[size_t(rr_depth - 1)], 1000);
}
