#include "src/scene/loaders/pbrt_parameters.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "emlt/core/error.h"

namespace emlt::pbrt {

namespace {

[[noreturn]] void fail_at(const std::string& file, int line, const std::string& problem) {
  throw file_error(file, "line " + std::to_string(line) + ": " + problem);
}

// pbrt-v3 names that pbrt-v4 still reads.
std::string canonical_type(const std::string& type) {
  if (type == "point") return "point3";
  if (type == "vector") return "vector3";
  if (type == "normal3") return "normal";
  if (type == "color") return "rgb";
  return type;
}

bool known_type(const std::string& type) {
  for (const char* t : {"integer", "float", "point2", "vector2", "point3", "vector3", "normal",
                        "spectrum", "rgb", "blackbody", "bool", "string", "texture"})
    if (type == t) return true;
  return false;
}

// Whether values of `type` are numbers, strings or booleans.
enum class ValueKind { Number, String, Bool, NumberOrString };
ValueKind value_kind(const std::string& type) {
  if (type == "string" || type == "texture") return ValueKind::String;
  if (type == "bool") return ValueKind::Bool;
  if (type == "spectrum") return ValueKind::NumberOrString;  // samples, or a named/file spectrum
  return ValueKind::Number;
}

bool parse_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  const char* begin = text.c_str();
  char* end = nullptr;
  value = std::strtod(begin, &end);
  return end == begin + text.size() && std::isfinite(value);
}

void add_value(Param& param, const Token& token, const std::string& file) {
  const ValueKind kind = value_kind(param.type);
  if (kind == ValueKind::Bool) {
    if (token.text == "true" || token.text == "false") {
      param.bools.push_back(token.text == "true");
      return;
    }
    fail_at(file, token.line, param.quoted() + ": '" + token.text + "' is not true or false");
  }
  if (token.kind == Token::Kind::String) {
    if (kind == ValueKind::Number)
      fail_at(file, token.line, param.quoted() + ": expected a number, got \"" + token.text + "\"");
    if (!param.numbers.empty())
      fail_at(file, token.line, param.quoted() + ": numbers and strings mixed");
    param.strings.push_back(token.text);
    return;
  }
  if (kind == ValueKind::String)
    fail_at(file, token.line,
            param.quoted() + ": expected a quoted string, got '" + token.text + "'");
  double value = 0.0;
  if (!parse_number(token.text, value))
    fail_at(file, token.line, param.quoted() + ": '" + token.text + "' is not a finite number");
  if (!param.strings.empty())
    fail_at(file, token.line, param.quoted() + ": numbers and strings mixed");
  param.numbers.push_back(value);
}

}  // namespace

Params Params::read(Tokenizer& tokens) {
  Params params;
  for (;;) {
    std::optional<Token> head = tokens.next();
    if (!head) break;
    if (head->kind != Token::Kind::String) {
      tokens.unget(std::move(*head));
      break;
    }
    Param param;
    param.file = tokens.path();
    param.line = head->line;
    std::istringstream words(head->text);
    std::string type, name, extra;
    words >> type >> name;
    if (name.empty() || (words >> extra))
      fail_at(tokens.path(), head->line,
              "\"" + head->text + "\" is not a parameter declaration (\"type name\")");
    param.type = canonical_type(type);
    param.name = name;
    if (!known_type(param.type))
      fail_at(tokens.path(), head->line, "unknown parameter type '" + type + "' of '" + name + "'");
    std::optional<Token> value = tokens.next();
    if (!value) fail_at(tokens.path(), head->line, param.quoted() + " has no value");
    if (value->kind == Token::Kind::Open) {
      for (;;) {
        std::optional<Token> item = tokens.next();
        if (!item)
          fail_at(tokens.path(), head->line, param.quoted() + ": '[' without a closing ']'");
        if (item->kind == Token::Kind::Close) break;
        if (item->kind == Token::Kind::Open)
          fail_at(tokens.path(), item->line, param.quoted() + ": nested '['");
        add_value(param, *item, tokens.path());
      }
    } else if (value->kind == Token::Kind::Close) {
      fail_at(tokens.path(), value->line, param.quoted() + ": ']' without '['");
    } else {
      add_value(param, *value, tokens.path());
    }
    if (param.size() == 0) fail_at(tokens.path(), head->line, param.quoted() + " has no value");
    // pbrt-v4 looks a parameter up from the end of the list: given twice, the last one
    // counts and the earlier one is never read (public scenes do this, e.g. a camera's
    // focus written for two subjects).
    std::erase_if(params.list_, [&](const Param& earlier) {
      if (earlier.name != param.name) return false;
      params.replaced_.push_back("'" + earlier.name + "' at line " + std::to_string(earlier.line));
      return true;
    });
    params.list_.push_back(std::move(param));
  }
  return params;
}

void Params::fail(const Param& param, const std::string& problem) {
  fail_at(param.file, param.line, param.quoted() + ": " + problem);
}

const Param* Params::find(const std::string& name) const {
  for (const Param& p : list_)
    if (p.name == name) return &p;
  return nullptr;
}

const Param* Params::get(const std::string& name) const {
  const Param* p = find(name);
  if (p) p->used = true;
  return p;
}

const Param& Params::typed(const std::string& name, const char* type) const {
  const Param* p = get(name);
  if (p->type != type) fail(*p, std::string("expected a ") + type + " parameter");
  return *p;
}

float Params::get_float(const std::string& name, float fallback) const {
  if (!has(name)) return fallback;
  const Param& p = typed(name, "float");
  if (p.numbers.size() != 1) fail(p, "expected one value");
  if (std::abs(p.numbers[0]) > std::numeric_limits<float>::max()) fail(p, "value out of range");
  return float(p.numbers[0]);
}

int Params::get_int(const std::string& name, int fallback) const {
  if (!has(name)) return fallback;
  const Param& p = typed(name, "integer");
  if (p.numbers.size() != 1) fail(p, "expected one value");
  const double v = p.numbers[0];
  if (v != std::floor(v) || std::abs(v) > 2147483647.0) fail(p, "not an integer");
  return int(v);
}

bool Params::get_bool(const std::string& name, bool fallback) const {
  if (!has(name)) return fallback;
  const Param& p = typed(name, "bool");
  if (p.bools.size() != 1) fail(p, "expected one value");
  return p.bools[0];
}

std::string Params::get_string(const std::string& name, const std::string& fallback) const {
  if (!has(name)) return fallback;
  const Param& p = typed(name, "string");
  if (p.strings.size() != 1) fail(p, "expected one value");
  return p.strings[0];
}

Vec3 Params::get_point3(const std::string& name, const Vec3& fallback) const {
  if (!has(name)) return fallback;
  const std::vector<Vec3> v = get_vec3s(name, "point3");
  if (v.size() != 1) fail(*find(name), "expected one point");
  return v[0];
}

std::vector<float> Params::get_floats(const std::string& name) const {
  if (!has(name)) return {};
  const Param& p = typed(name, "float");
  std::vector<float> out;
  for (double v : p.numbers) {
    if (std::abs(v) > std::numeric_limits<float>::max()) fail(p, "value out of range");
    out.push_back(float(v));
  }
  return out;
}

std::vector<int> Params::get_ints(const std::string& name) const {
  if (!has(name)) return {};
  const Param& p = typed(name, "integer");
  std::vector<int> out;
  for (double v : p.numbers) {
    if (v != std::floor(v) || std::abs(v) > 2147483647.0) fail(p, "not an integer");
    out.push_back(int(v));
  }
  return out;
}

std::vector<Vec3> Params::get_vec3s(const std::string& name, const char* type) const {
  if (!has(name)) return {};
  const Param& p = typed(name, type);
  if (p.numbers.size() % 3 != 0) fail(p, "the number of values is not a multiple of 3");
  std::vector<Vec3> out;
  for (size_t i = 0; i < p.numbers.size(); i += 3) {
    const Vec3 v(float(p.numbers[i]), float(p.numbers[i + 1]), float(p.numbers[i + 2]));
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      fail(p, "value out of range");
    out.push_back(v);
  }
  return out;
}

std::vector<Vec2> Params::get_point2s(const std::string& name) const {
  if (!has(name)) return {};
  const Param& p = typed(name, "point2");
  if (p.numbers.size() % 2 != 0) fail(p, "the number of values is not a multiple of 2");
  std::vector<Vec2> out;
  for (size_t i = 0; i < p.numbers.size(); i += 2) {
    const Vec2 v(float(p.numbers[i]), float(p.numbers[i + 1]));
    if (!std::isfinite(v.x) || !std::isfinite(v.y)) fail(p, "value out of range");
    out.push_back(v);
  }
  return out;
}

std::vector<const Param*> Params::unused() const {
  std::vector<const Param*> out;
  for (const Param& p : list_)
    if (!p.used) out.push_back(&p);
  return out;
}

}  // namespace emlt::pbrt
