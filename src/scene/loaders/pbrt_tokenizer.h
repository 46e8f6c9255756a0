#pragma once
// pbrt-v4 scene files, first stage: the text as tokens (internal to the pbrt reader).
// A token is a bare word or number, a quoted string (quotes removed), '[' or ']'; '#'
// starts a comment to the end of the line. Each token keeps its line for messages.
#include <optional>
#include <string>

namespace emlt::pbrt {

struct Token {
  enum class Kind { Word, String, Open, Close } kind = Kind::Word;
  std::string text;
  int line = 0;
};

class Tokenizer {
 public:
  // `path` names the file in messages; `text` is its contents.
  Tokenizer(std::string path, std::string text);
  // The next token, or nothing at the end of the file. Throws "<file>: line N: ..." for an
  // unterminated string or an unknown escape.
  std::optional<Token> next();
  // Puts `token` back: the next call to next() returns it.
  void unget(Token token);
  const std::string& path() const { return path_; }

 private:
  std::string path_, text_;
  size_t pos_ = 0;
  int line_ = 1;
  std::optional<Token> pending_;
};

}  // namespace emlt::pbrt
