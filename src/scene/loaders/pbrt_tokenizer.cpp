#include "src/scene/loaders/pbrt_tokenizer.h"

#include <cctype>

#include "emlt/core/error.h"

namespace emlt::pbrt {

Tokenizer::Tokenizer(std::string path, std::string text)
    : path_(std::move(path)), text_(std::move(text)) {}

void Tokenizer::unget(Token token) {
  pending_ = std::move(token);
}

std::optional<Token> Tokenizer::next() {
  if (pending_) {
    std::optional<Token> token = std::move(pending_);
    pending_.reset();
    return token;
  }
  for (;;) {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ >= text_.size()) return std::nullopt;
    if (text_[pos_] != '#') break;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  Token token;
  token.line = line_;
  const char c = text_[pos_];
  if (c == '[' || c == ']') {
    token.kind = c == '[' ? Token::Kind::Open : Token::Kind::Close;
    token.text = std::string(1, c);
    ++pos_;
    return token;
  }
  if (c == '"') {
    token.kind = Token::Kind::String;
    ++pos_;
    for (;;) {
      if (pos_ >= text_.size() || text_[pos_] == '\n')
        throw file_error(path_, "line " + std::to_string(token.line) + ": unterminated string");
      const char s = text_[pos_++];
      if (s == '"') break;
      if (s != '\\') {
        token.text += s;
        continue;
      }
      if (pos_ >= text_.size())
        throw file_error(path_, "line " + std::to_string(token.line) + ": unterminated string");
      const char e = text_[pos_++];
      switch (e) {
        case 'n':
          token.text += '\n';
          break;
        case 't':
          token.text += '\t';
          break;
        case 'b':
          token.text += '\b';
          break;
        case 'f':
          token.text += '\f';
          break;
        case 'r':
          token.text += '\r';
          break;
        case '\\':
        case '\'':
        case '"':
          token.text += e;
          break;
        default:
          throw file_error(path_, "line " + std::to_string(token.line) + ": unknown escape '\\" +
                                      std::string(1, e) + "' in a string");
      }
    }
    return token;
  }
  // A bare word runs to whitespace, a bracket, a quote or a comment.
  const size_t begin = pos_;
  while (pos_ < text_.size()) {
    const char w = text_[pos_];
    if (std::isspace(static_cast<unsigned char>(w)) || w == '[' || w == ']' || w == '"' || w == '#')
      break;
    ++pos_;
  }
  token.text = text_.substr(begin, pos_ - begin);
  return token;
}

}  // namespace emlt::pbrt
