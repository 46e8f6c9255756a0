#pragma once
// The render options a scene file may set as well as the command line: the sample count,
// the path length, Russian roulette's start and whether lights seen directly are drawn.
// They are declared here, below the scene layer, because the loaders read them: a Mitsuba
// file names each by its `mitsuba` parameter (of <integrator>, or of <sampler> for the
// sample count), a JSON scene by its json_key() under "integrator"; both accept exactly the
// values the flag accepts and say so in the flag's words. The run loop and path sampling
// list them among their options (run_options(), sampling_options()).
#include <string>
#include <string_view>
#include <vector>

#include "emlt/settings/render_option.h"

namespace emlt {

// The element of a Mitsuba scene whose parameter sets the option.
enum class MitsubaElement { Integrator, Sampler };

struct SceneFileOption {
  RenderOption option;
  std::string mitsuba;  // the parameter's name in a Mitsuba scene ("maxDepth")
  MitsubaElement element = MitsubaElement::Integrator;
  // Mitsuba's parameter is a <boolean> (the option's two words are false, true), otherwise an
  // <integer> (a Whole option).
  bool boolean() const { return option.values.kind == OptionValues::Kind::Word; }
  // The key in a JSON scene's "integrator" object: the flag without dashes ("max_depth").
  std::string json_key() const;
  // The option's text for a boolean parameter's value.
  const std::string& word(bool value) const { return option.values.words[value ? 1 : 0]; }
};

const std::vector<SceneFileOption>& scene_file_options();
// The declaration of `flag`; throws Error when no scene file option has it.
const SceneFileOption& scene_file_option(std::string_view flag);

}  // namespace emlt
