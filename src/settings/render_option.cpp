#include "emlt/settings/render_option.h"

#include <fmt/core.h>

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "emlt/core/error.h"

namespace emlt {

namespace {

// The value as the user typed it, shortened so that a pasted megabyte stays one line.
std::string quoted(const std::string& text) {
  return text.size() <= 24 ? text : text.substr(0, 21) + "...";
}

bool parse_whole(const std::string& text, int64_t& value) {
  const char* end = text.data() + text.size();
  // from_chars takes no leading '+' or whitespace, and reports overflow itself.
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  return !text.empty() && error == std::errc() && stop == end;
}

bool parse_real(const std::string& text, double& value) {
  // strtod, as the command line has always read numbers: "0x10" and " 5" keep their meaning.
  char* stop = nullptr;
  value = text.empty() ? std::nan("") : std::strtod(text.c_str(), &stop);
  return !text.empty() && stop == text.c_str() + text.size() && std::isfinite(value);
}

}  // namespace

bool RenderOption::accepts(const std::string& text) const {
  switch (values.kind) {
    case OptionValues::Kind::Whole: {
      int64_t v = 0;
      return parse_whole(text, v) && double(v) >= values.low && double(v) <= values.high;
    }
    case OptionValues::Kind::Real: {
      double v = 0.0;
      return parse_real(text, v) && v >= values.low && !(values.low_open && v == values.low) &&
             v <= values.high;
    }
    case OptionValues::Kind::Word:
      for (const std::string& w : values.words)
        if (w == text) return true;
      return false;
    case OptionValues::Kind::Text:
      return true;
  }
  return false;
}

void RenderOption::set(RenderSettings& settings, const std::string& text) const {
  if (!accepts(text))
    throw Error(flag + " must be " + values.takes + " (got " + quoted(text) + ")");
  assign(settings, text);
}

RenderOption whole_option(std::string flag, int RenderSettings::*field, int64_t low, int64_t high,
                          std::string takes, std::string help) {
  RenderOption o;
  o.flag = std::move(flag);
  o.help = std::move(help);
  o.values = {OptionValues::Kind::Whole, double(low), double(high), false, {}, std::move(takes)};
  o.assign = [field](RenderSettings& s, const std::string& text) {
    int64_t v = 0;
    parse_whole(text, v);
    s.*field = int(v);
  };
  o.recorded = [field](const RenderSettings& s) { return recorded_number(int64_t(s.*field)); };
  return o;
}

RenderOption real_option(std::string flag, double RenderSettings::*field, double low, bool low_open,
                         double high, std::string takes, std::string help) {
  RenderOption o;
  o.flag = std::move(flag);
  o.help = std::move(help);
  o.values = {OptionValues::Kind::Real, low, high, low_open, {}, std::move(takes)};
  o.assign = [field](RenderSettings& s, const std::string& text) {
    double v = 0.0;
    parse_real(text, v);
    s.*field = v;
  };
  o.recorded = [field](const RenderSettings& s) { return recorded_number(s.*field); };
  return o;
}

RenderOption switch_option(std::string flag, bool RenderSettings::*field, std::string off,
                           std::string on, std::string help) {
  RenderOption o;
  o.flag = std::move(flag);
  o.help = std::move(help);
  o.values = {OptionValues::Kind::Word, 0, 0, false, {off, on}, off + " or " + on};
  o.assign = [field, on](RenderSettings& s, const std::string& text) { s.*field = text == on; };
  o.recorded = [field, off, on](const RenderSettings& s) { return s.*field ? on : off; };
  return o;
}

void apply_only_where(std::vector<RenderOption>& options,
                      const std::function<bool(const RenderSettings&)>& predicate) {
  for (RenderOption& option : options) option.applies = predicate;
}

RenderOption path_option(std::string flag, std::string RenderSettings::*field, std::string help) {
  RenderOption o;
  o.flag = std::move(flag);
  o.help = std::move(help);
  o.values = {OptionValues::Kind::Text, 0, 0, false, {}, "a file name"};
  o.assign = [field](RenderSettings& s, const std::string& text) { s.*field = text; };
  return o;
}

std::string recorded_number(double value) {
  return fmt::format("{}", value);
}
std::string recorded_number(int64_t value) {
  return fmt::format("{}", value);
}
std::string recorded_number(uint64_t value) {
  return fmt::format("{}", value);
}

}  // namespace emlt
