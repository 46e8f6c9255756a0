#pragma once
// CLI11 validators that state a numeric flag's valid range in words. CLI11's own
// CLI::Range prints its raw limits (a 309-digit number for an unbounded double) and
// accepts no words for special values such as "0 for all cores"; these refuse a value
// with one line, "--threads must be 1..1024, or 0 for all cores (got 5000)", once main
// has joined CLI11's "--threads: " prefix to it (readable_parse_error).
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace emlt::cli {

// A whole number in [low, high] (written as digits; "1e18" or "2.5" are refused too, as
// the option's integer type could not hold them). `range` completes "must be ...".
CLI::Validator whole_number(int64_t low, int64_t high, std::string range);

// A finite real number in [low, high]; `low_open` excludes `low` itself ("positive").
CLI::Validator real_number(double low, bool low_open, double high, std::string range);

// The message of a command-line error as one line: "--spp: must be ..." becomes
// "--spp must be ..."; every other message is returned unchanged.
std::string readable_parse_error(const std::string& message);

}  // namespace emlt::cli
