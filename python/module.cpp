// `import emlt`: the renderer from Python. Scenes load as the command line loads them,
// renders run through the command line's own render job (src/cli/render_job.h) and come
// back as numpy arrays, and images are compared with `emlt compare`'s metrics.
#include "bindings.h"

PYBIND11_MODULE(emlt, m) {
  m.doc() =
      "emlt: Monte Carlo and Markov chain Monte Carlo light transport.\n\n"
      "scene = emlt.load('scene.xml', name=value)    # Mitsuba XML, JSON or pbrt-v4, with defines\n"
      "image, stats = emlt.render(scene, integrator='mlt', mpp=16, max_depth=5)\n"
      "metrics = emlt.compare(reference, image)\n\n"
      "Every option of `emlt render` is a keyword of render(): --max-depth 5 is max_depth=5.";
  m.attr("__version__") = "0.1.0";
  emlt::python::bind_errors(m);
  emlt::python::bind_scene(m);
  emlt::python::bind_render(m);
  emlt::python::bind_compare(m);
}
