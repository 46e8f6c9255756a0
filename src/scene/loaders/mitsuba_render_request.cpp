// What a Mitsuba scene's <integrator> and <sampler> say about rendering: emlt's name for the
// integrator, and the options a scene file shares with the command line (maxDepth, rrDepth,
// hideEmitters, sampleCount: settings/scene_options.h) in their flags' words; what only
// changes how fast an integrator converges is noted, what changes the image and emlt does
// not do is reported.
#include "emlt/settings/scene_options.h"
#include "emlt/settings/settings.h"
#include "src/scene/loaders/mitsuba_parser.h"

namespace emlt::mitsuba {

namespace {

// The options of `element` that a scene file shares with the command line, by their Mitsuba
// names, checked against the flags' own values (settings/scene_options.h). A parameter
// already ignored (hideEmitters of a ptracer) is left alone.
void read_scene_file_options(Properties& props, MitsubaElement element,
                             SceneRenderRequest& request) {
  for (const SceneFileOption& o : scene_file_options()) {
    if (o.element != element || !props.has(o.mitsuba) || props.used(o.mitsuba)) continue;
    request.set(o.option.flag, o.boolean()
                                   ? o.word(props.get_boolean(o.mitsuba, false))
                                   : std::to_string(props.get_integer(
                                         o.mitsuba, 0, loader::whole_range(o.option.values))));
  }
}

// Mitsuba's ERPT parameters under emlt's flags: they change only how its chains spread the
// seeds' energy (the image is the same), but a comparison at equal work needs them.
// The strategy mix a Mitsuba mlt or erpt file switches on, each strategy with weight 1:
// Mitsuba picks among the applicable ones with equal probability. Its manifold
// perturbation's lambda (or probFactor) becomes --manifold-lambda.
std::string chain_strategies(const Document& doc, pugi::xml_node node, Properties& props,
                             bool bidirectional_by_default) {
  std::string mix;
  const auto take = [&](const char* flag, bool fallback, const char* strategy) {
    if (!props.get_boolean(flag, fallback)) return;
    if (!mix.empty()) mix.push_back(',');
    mix.append(strategy);
  };
  take("bidirectionalMutation", bidirectional_by_default, "bidir=1");
  take("lensPerturbation", true, "lens=1");
  take("causticPerturbation", true, "caustic=1");
  take("multiChainPerturbation", true, "multichain=1");
  take("manifoldPerturbation", false, "manifold=1");
  if (mix.empty())
    doc.fail(node, doc.attribute(node, "type") +
                       ": every mutation and perturbation is switched off (Mitsuba needs at "
                       "least one)");
  return mix;
}

// Mitsuba's lambda (its documented name) or probFactor (what its code reads first).
void read_manifold_lambda(Properties& props, SceneRenderRequest& request) {
  constexpr loader::RealRange kLambda{0.0f, true, 1e6f, false,
                                      "a positive number, at most a million"};
  for (const char* name : {"probFactor", "lambda"})
    if (props.has(name)) {
      request.set_integrator_option(
          "--manifold-lambda", recorded_number(double(props.get_float(name, 50.0f, kLambda))));
      return;
    }
}

void read_erpt(const Document& doc, pugi::xml_node node, Properties& props,
               SceneRenderRequest& request) {
  // The ranges of the flags the parameters set (erpt_integrator.cpp declares them above this
  // layer), so that a bad value is refused here, naming the file, its line and the parameter.
  constexpr loader::RealRange kChains{0.0f, true, 1e9f, false,
                                      "a positive number, at most a billion"};
  constexpr loader::RealRange kMaxChains{0.0f, false, 1e6f, false,
                                         "a number from 0 (no bound) to a million"};
  constexpr loader::IntegerRange kChainLength{1, 1 << 24, "a whole number from 1 to 2^24"};
  constexpr loader::IntegerRange kLuminanceSamples{1, kMaxBootstrapSamples,
                                                   "a whole number from 1 to 2^24"};
  if (props.has("numChains"))
    request.set_integrator_option(
        "--erpt-chains", recorded_number(double(props.get_float("numChains", 1.0f, kChains))));
  if (props.has("maxChains"))
    request.set_integrator_option(
        "--erpt-max-chains",
        recorded_number(double(props.get_float("maxChains", 0.0f, kMaxChains))));
  if (props.has("chainLength"))
    request.set_integrator_option(
        "--erpt-chain-length", std::to_string(props.get_integer("chainLength", 100, kChainLength)));
  // directSamples -1 leaves the direct light to the chains; otherwise it is rendered apart
  // (by Mitsuba's direct integrator, here by the seeds' BDPT strategies: the same image).
  if (props.has("directSamples"))
    request.set_integrator_option("--direct",
                                  props.get_integer("directSamples", 16) < 0 ? "mlt" : "separate");
  if (props.has("luminanceSamples"))
    request.set_integrator_option(
        "--bootstrap",
        std::to_string(props.get_integer("luminanceSamples", 15000, kLuminanceSamples)));
  // The manifold perturbation's offset manifolds: Mitsuba's typical microfacet turn per
  // move, when the file fixes it (0, Mitsuba's default, has it measured while rendering,
  // racing between threads; emlt keeps its fixed starting guess, --manifold-angle-change).
  constexpr loader::RealRange kAngle{0.0f, false, 90.0f, false, "a number of degrees from 0 to 90"};
  if (props.has("avgAngleChangeSurface")) {
    const float angle = props.get_float("avgAngleChangeSurface", 0.0f, kAngle);
    if (angle > 0.0f)
      request.set_integrator_option("--manifold-angle-change", recorded_number(double(angle)));
  }
  // The chains' strategies, Mitsuba's defaults for ERPT: Veach's perturbations alone.
  request.set_integrator_option("--mutations", chain_strategies(doc, node, props, false));
}

}  // namespace

bool read_integrator(const Document& doc, pugi::xml_node node, SceneRenderRequest& request) {
  const std::string type = doc.attribute(node, "type");
  Properties props(doc, node);
  if (type == "path")
    request.integrator = "pt";
  else if (type == "direct")
    request.integrator = "direct";
  else if (type == "bdpt")
    request.integrator = "bdpt";
  else if (type == "mlt")
    request.integrator = "mlt";
  else if (type == "pssmlt")  // its bidirectional and pLarge steer sampling only (below)
    request.integrator = "pssmlt";
  else if (type == "ptracer")
    request.integrator = "ptracer";
  else if (type == "erpt")
    request.integrator = "erpt";
  else if (doc.mitsuba3() && (type == "volpath" || type == "volpathmis" || type == "prb" ||
                              type == "prb_basic" || type == "prbvolpath")) {
    // Mitsuba 3's path tracers with media or differentiation: without a medium (emlt has
    // none; a medium is reported where it is named) each renders what `path` renders.
    request.integrator = "pt";
    doc.warn(node,
             "integrator '" + type +
                 "' rendered by emlt's path tracer (the same image "
                 "without participating media)",
             Document::Warning::Note);
  } else  // any unbiased or consistent integrator converges to the same image
    doc.warn(node,
             "integrator type '" + type + "' is not supported; using '" +
                 (request.integrator.empty() ? RenderSettings().integrator : request.integrator) +
                 "'",
             Document::Warning::Approximated);
  if (type == "erpt") read_erpt(doc, node, props, request);
  // Mitsuba's mlt with the manifold perturbation on is manifold exploration (MEMLT): its
  // switched-on strategies become the mix, as Mitsuba would pick them. Without it the
  // switches steer only sampling, and emlt's mlt keeps its own mix.
  if (type == "mlt" && props.get_boolean("manifoldPerturbation", false)) {
    request.integrator = "memlt";
    request.set_integrator_option("--mutations", chain_strategies(doc, node, props, true));
  }
  if ((type == "erpt" || request.integrator == "memlt")) read_manifold_lambda(props, request);
  // Parameters that steer how fast an integrator converges, never what it converges to:
  // emlt's integrators have their own (command line) controls.
  std::vector<std::string> tuning;
  for (const char* name :
       {"lightImage", "sampleDirect", "luminanceSamples", "twoStage", "directSamples",
        "separateDirect", "bidirectionalMutation", "lensPerturbation", "multiChainPerturbation",
        // multiChain and caustic: the names Mitsuba's documentation gives the multi-chain and
        // caustic perturbations' switches (its code does not read them: it warns, ignores them)
        "multiChain", "caustic", "causticPerturbation", "manifoldPerturbation", "bidirectional",
        "pLarge", "kelemenStyleWeights", "directSampling", "mutationSizeLow", "mutationSizeHigh",
        "firstStage", "lambda", "probFactor", "firstStageSizeReduction", "workUnits", "timeout",
        "emitterSamples", "bsdfSamples", "shadingSamples", "granularity"})
    if (props.has(name) && !props.used(name)) tuning.push_back(name);
  for (const std::string& name : tuning) props.ignore({name.c_str()});
  if (type == "ptracer" && doc.mitsuba3()) {
    // Mitsuba 3 changed this: its particle tracer reads hide_emitters (every integrator
    // does), and emlt's draws the lights seen directly.
    props.note_sampling_only({"samples_per_pass"}, "how Mitsuba 3 splits the work");
    if (props.get_boolean("hideEmitters", false))
      doc.warn(props.node_of("hideEmitters"),
               "'hide_emitters' of a ptracer is not supported: emlt's particle tracer draws "
               "the lights seen directly");
  } else if (type == "ptracer") {
    // Mitsuba's particle tracer does not read hideEmitters (only its camera-side
    // integrators do): it draws the lights seen directly whatever the flag says.
    if (props.has("hideEmitters")) {
      props.ignore({"hideEmitters"});
      doc.warn(node,
               "'hideEmitters' is not a parameter of Mitsuba's ptracer, which draws the "
               "lights seen directly; ignored, as Mitsuba does",
               Document::Warning::Note);
    }
    // Brute force only lets particles reach the camera by hitting its aperture (never, for
    // a pinhole: Mitsuba's image is black): an estimator emlt does not have.
    if (props.get_boolean("bruteForce", false))
      doc.warn(node,
               "'bruteForce' is not supported: every light vertex is connected to the "
               "camera instead (Mitsuba's brute-force mode counts only the particles "
               "that hit the camera's aperture: a perspective camera's image is black)");
  }
  // Mitsuba's bdpt writes each strategy's image beside the render when asked; the render
  // itself is the same.
  if (type == "bdpt" && props.get_boolean("showWeighted", false))
    doc.warn(props.node_of("showWeighted"),
             "'showWeighted': the strategies' own images are not written (the render is the same)",
             Document::Warning::Note);
  read_scene_file_options(props, MitsubaElement::Integrator, request);
  // Mitsuba's path, direct and volumetric path tracers read strictNormals (default false);
  // its other integrators ignore it, treating shading normals strictly (the bidirectional
  // ones say so; the particle tracer, too, drops what the two normals disagree on).
  const bool reads_strict =
      type == "path" || type == "direct" || type == "volpath" || type == "volpath_simple";
  bool strict = true;
  if (reads_strict) {
    strict = props.get_boolean("strictNormals", false);
  } else if (props.has("strictNormals")) {
    props.ignore({"strictNormals"});
    doc.warn(node,
             "'strictNormals' is not a parameter of Mitsuba's " + type +
                 ", which treats shading normals strictly; ignored, as Mitsuba does",
             Document::Warning::Note);
  }
  if (!tuning.empty()) {
    std::string names;
    for (const std::string& name : tuning) names += (names.empty() ? "'" : ", '") + name + "'";
    doc.warn(node,
             "convergence parameters " + names + " ignored (they change the noise, not the image)",
             Document::Warning::Note);
  }
  for (pugi::xml_node child : props.objects())
    doc.warn(child,
             "unsupported element <" + std::string(child.name()) + "> inside <integrator> ignored");
  props.warn_unused();
  return strict;
}

void read_sampler(const Document& doc, pugi::xml_node node, SceneRenderRequest& request) {
  Properties props(doc, node);
  read_scene_file_options(props, MitsubaElement::Sampler, request);
  // Every sampler converges to the same image; only its sequence differs. Mitsuba 0.6's
  // read scramble and dimension; seed (Mitsuba 2's, written by exporters), resolution and
  // depth are read by none of them, and change nothing there either.
  props.note_sampling_only({"seed", "scramble", "dimension", "resolution", "depth"},
                           "the sample sequence");
  // Mitsuba 3's stratified and multijitter jitter, orthogonal's strength: the same.
  if (doc.mitsuba3()) props.note_sampling_only({"jitter", "strength"}, "the sample sequence");
  props.warn_unused();
}

}  // namespace emlt::mitsuba
