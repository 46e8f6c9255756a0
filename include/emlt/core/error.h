#pragma once
// One exception type for every user-facing failure. Its message is the single line the
// command line prints: "<file>: <problem>".
#include <stdexcept>
#include <string>

namespace emlt {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline Error file_error(const std::string& file, const std::string& problem) {
  return Error(file + ": " + problem);
}

}  // namespace emlt
