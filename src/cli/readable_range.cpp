#include "cli/readable_range.h"

#include <charconv>
#include <cstdlib>
#include <cmath>
#include <utility>

namespace emlt::cli {

namespace {

// The value as the user typed it, shortened so that a pasted megabyte stays one line.
std::string quoted(const std::string& text) {
  return text.size() <= 24 ? text : text.substr(0, 21) + "...";
}

std::string refusal(const std::string& range, const std::string& text) {
  return "must be " + range + " (got " + quoted(text) + ")";
}

}  // namespace

CLI::Validator whole_number(int64_t low, int64_t high, std::string range) {
  return CLI::Validator(
      [low, high, range](std::string& text) -> std::string {
        int64_t value = 0;
        const char* end = text.data() + text.size();
        // from_chars takes no leading '+' or whitespace, and reports overflow itself.
        const auto [stop, error] = std::from_chars(text.data(), end, value);
        if (text.empty() || error != std::errc() || stop != end || value < low || value > high)
          return refusal(range, text);
        return "";
      },
      range);
}

CLI::Validator real_number(double low, bool low_open, double high, std::string range) {
  return CLI::Validator(
      [low, low_open, high, range](std::string& text) -> std::string {
        // strtod, not from_chars: CLI11 converts the value with it too, so "0x10" and
        // " 5" mean here what they will mean to the option.
        char* stop = nullptr;
        const double value = text.empty() ? std::nan("") : std::strtod(text.c_str(), &stop);
        const bool whole = !text.empty() && stop == text.c_str() + text.size();
        if (!whole || !std::isfinite(value) || value < low || (low_open && value == low) ||
            value > high)
          return refusal(range, text);
        return "";
      },
      range);
}

std::string readable_parse_error(const std::string& message) {
  // CLI11 prefixes a validator's message with "<option name>: ".
  const size_t colon = message.find(": must be ");
  if (colon == std::string::npos || colon != message.find(": ")) return message;
  return message.substr(0, colon) + message.substr(colon + 1);
}

}  // namespace emlt::cli
