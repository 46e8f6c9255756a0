#pragma once
// pbrt-v4 parameter lists ("type name" value or [ values ]) after a directive's own
// arguments (internal to the pbrt reader). Each parameter remembers whether the reader
// asked for it, so that what it never reads can be reported (unused()).
#include <string>
#include <vector>

#include "emlt/core/math.h"
#include "src/scene/loaders/pbrt_tokenizer.h"

namespace emlt::pbrt {

struct Param {
  std::string type, name;  // "float", "roughness"
  std::vector<double> numbers;
  std::vector<std::string> strings;
  std::vector<bool> bools;
  std::string file;
  int line = 0;
  mutable bool used = false;
  size_t size() const { return numbers.size() + strings.size() + bools.size(); }
  // "'float roughness'", for messages.
  std::string quoted() const { return "'" + type + " " + name + "'"; }
};

class Params {
 public:
  // Reads parameters from `tokens` until a token that cannot start one (put back).
  static Params read(Tokenizer& tokens);

  bool has(const std::string& name) const { return find(name) != nullptr; }
  // The parameter `name` marked as used, or null. Type aliases are resolved on reading
  // ("point" is "point3", "color" is "rgb", "normal3" is "normal").
  const Param* get(const std::string& name) const;

  float get_float(const std::string& name, float fallback) const;
  int get_int(const std::string& name, int fallback) const;
  bool get_bool(const std::string& name, bool fallback) const;
  std::string get_string(const std::string& name, const std::string& fallback) const;
  Vec3 get_point3(const std::string& name, const Vec3& fallback) const;
  std::vector<float> get_floats(const std::string& name) const;
  std::vector<int> get_ints(const std::string& name) const;
  // point3/vector3/normal values in threes; point2 in twos.
  std::vector<Vec3> get_vec3s(const std::string& name, const char* type) const;
  std::vector<Vec2> get_point2s(const std::string& name) const;

  // Parameters never read, in file order.
  std::vector<const Param*> unused() const;
  // Marks `name` as read without reading it (its effect is reported elsewhere, or nil).
  void ignore(const std::string& name) const { (void)get(name); }

  [[noreturn]] static void fail(const Param& param, const std::string& problem);

  // Parameters given again later in the same list, which replaced them: "'name' at line N".
  const std::vector<std::string>& replaced() const { return replaced_; }

 private:
  const Param* find(const std::string& name) const;
  const Param& typed(const std::string& name, const char* type) const;
  std::vector<Param> list_;
  std::vector<std::string> replaced_;
};

}  // namespace emlt::pbrt
