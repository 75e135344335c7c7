#include "host-sim/world/tokenizer.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace troupe::world {
namespace {

bool is_alpha(char c) {
  return std::isalpha(static_cast<unsigned char>(c)) != 0;
}
bool is_digit(char c) {
  return std::isdigit(static_cast<unsigned char>(c)) != 0;
}
bool is_word_char(char c) {
  return is_alpha(c) || is_digit(c) || std::strchr(".-_[]", c) != nullptr;
}
bool is_number_start(char c) {
  return c != '\0' && std::strchr("+-.0123456789", c) != nullptr;
}

std::string printable(char c) {
  if (std::isprint(static_cast<unsigned char>(c))) return std::string("'") + c + "'";
  char buf[16];
  std::snprintf(buf, sizeof buf, "byte 0x%02x", static_cast<unsigned char>(c));
  return buf;
}

}  // namespace

std::string describe(const Token& t) {
  switch (t.kind) {
    case TokenKind::Word:
      return "word '" + std::string(t.text) + "'";
    case TokenKind::Number:
      return "number " + std::string(t.text);
    case TokenKind::String:
      return "string \"" + std::string(t.text) + "\"";
    case TokenKind::OpenEntity:
      return "'('";
    case TokenKind::CloseEntity:
      return "')'";
    case TokenKind::OpenTuple:
      return "'['";
    case TokenKind::CloseTuple:
      return "']'";
  }
  return "token";
}

bool tokenize(std::string_view text, const std::shared_ptr<const std::string>& file, std::vector<Token>& out,
              Diagnostics& diags) {
  int line = 1;
  size_t i = 0;
  const size_t n = text.size();
  auto loc = [&]() { return SourceLoc{file, line}; };
  // A generated world has a token every 6 bytes or so: reserving one per
  // 4 spares the doublings (and the moments both buffers are held) on a
  // large file; pages reserved but never written cost nothing.
  out.reserve(out.size() + text.size() / 4);
  while (i < n) {
    char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == '\r') {
      // \r\n and a lone \r both end one line.
      ++line;
      i += (i + 1 < n && text[i + 1] == '\n') ? 2 : 1;
    } else if (c == ' ' || c == '\t' || c == '\f' || c == '\v') {
      ++i;
    } else if (c == '#') {
      while (i < n && text[i] != '\n' && text[i] != '\r') ++i;
    } else if (is_alpha(c)) {
      size_t start = i;
      while (i < n && is_word_char(text[i])) ++i;
      out.push_back({TokenKind::Word, line, text.substr(start, i - start), 0});
    } else if (is_number_start(c)) {
      size_t start = i;
      while (i < n && (is_number_start(text[i]) || text[i] == 'e' || text[i] == 'E')) ++i;
      const std::string_view word = text.substr(start, i - start);
      // strtod needs a terminated copy; numbers are short (no allocation).
      const std::string s(word);
      char* end = nullptr;
      errno = 0;
      double v = std::strtod(s.c_str(), &end);
      if (end != s.c_str() + s.size() || s.empty() || errno == ERANGE || !std::isfinite(v)) {
        diags.error(loc(), "malformed number '" + s + "'");
        return false;
      }
      out.push_back({TokenKind::Number, line, word, v});
    } else if (c == '"') {
      size_t start = ++i;
      while (i < n && text[i] != '"' && text[i] != '\n' && text[i] != '\r') ++i;
      if (i >= n || text[i] != '"') {
        diags.error(loc(), "unterminated string");
        return false;
      }
      out.push_back({TokenKind::String, line, text.substr(start, i - start), 0});
      ++i;
    } else if (c == '(' || c == ')' || c == '[' || c == ']') {
      TokenKind k = c == '('   ? TokenKind::OpenEntity
                    : c == ')' ? TokenKind::CloseEntity
                    : c == '[' ? TokenKind::OpenTuple
                               : TokenKind::CloseTuple;
      out.push_back({k, line, text.substr(i, 1), 0});
      ++i;
    } else {
      diags.error(loc(), "unexpected character " + printable(c));
      return false;
    }
  }
  return true;
}

}  // namespace troupe::world
