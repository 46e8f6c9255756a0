#pragma once
// One render option, declared once, by the part of the engine that reads it (the run loop's
// budgets, an integrator's knobs): its command-line flag, what values it takes, where the
// value lands in RenderSettings and how a checkpoint records it (a resumed render must have
// been made with the same value). The command line and the checkpoint header derive from
// these declarations (render_options() in integrators/registry.h gathers them), so an
// option is added in one place. The few a scene file may set also carry their Mitsuba
// parameter (settings/scene_options.h), which the loaders read by it.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "emlt/settings/settings.h"

namespace emlt {

// What an option's value may be; `takes` completes "must be ..." in a refusal.
struct OptionValues {
  enum class Kind { Whole, Real, Word, Text };
  Kind kind = Kind::Text;
  double low = 0.0, high = 0.0;  // Whole and Real: the closed range (low excluded if low_open)
  bool low_open = false;
  std::vector<std::string> words;  // Word: the words it takes
  std::string takes;
};

struct RenderOption {
  std::string flag;  // "--ensemble-alpha"
  std::string help;
  OptionValues values;
  // Sets the option from text that `values` accepts (accepts() checked first).
  std::function<void(RenderSettings&, const std::string& text)> assign;
  // The value as a checkpoint records it; empty function: not part of a checkpoint's identity
  // (where output goes, what is reported).
  std::function<std::string(const RenderSettings&)> recorded;
  // Whether the option can change a render with these settings (its integrator reads it);
  // empty function: every render. A checkpoint records only the options that apply, so that
  // a change to another integrator's option (or its default) never stops a resume.
  std::function<bool(const RenderSettings&)> applies;

  // Whether `text` is a value the option takes.
  bool accepts(const std::string& text) const;
  // Sets the option from `text`; throws Error("<flag> must be <takes> (got <text>)") when it is
  // not one of its values.
  void set(RenderSettings& settings, const std::string& text) const;
};

// Builders for the common shapes. The field is a member of RenderSettings.
RenderOption whole_option(std::string flag, int RenderSettings::*field, int64_t low, int64_t high,
                          std::string takes, std::string help);
RenderOption real_option(std::string flag, double RenderSettings::*field, double low, bool low_open,
                         double high, std::string takes, std::string help);
// Two words for a bool field: `off` sets false, `on` true.
RenderOption switch_option(std::string flag, bool RenderSettings::*field, std::string off,
                           std::string on, std::string help);
// A file or folder name the render writes to; not part of a checkpoint's identity unless
// `recorded` is given.
RenderOption path_option(std::string flag, std::string RenderSettings::*field, std::string help);

// Sets `applies` of each option in `options` to `predicate`.
void apply_only_where(std::vector<RenderOption>& options,
                      const std::function<bool(const RenderSettings&)>& predicate);

// A number as the checkpoint header writes it (shortest round-trip form).
std::string recorded_number(double value);
std::string recorded_number(int64_t value);
std::string recorded_number(uint64_t value);

}  // namespace emlt
