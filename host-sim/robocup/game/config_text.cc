#include "host-sim/robocup/game/config_text.h"

#include <fstream>
#include <sstream>

namespace troupe::robocup {
namespace {

constexpr int kMaxIncludeDepth = 8;
constexpr size_t kMaxFileBytes = 4 << 20;

struct Token {
  enum class Kind { Word, Open, Close, End, EndOfFile } kind;
  std::string text;
  /// Where an '=' outside quotes splits key from value, or npos.
  size_t eq = std::string::npos;
  int line = 0;
};

class Lexer {
 public:
  Lexer(const std::string& text) : text_(text) {}

  bool next(Token& t, std::string& error) {
    while (pos_ < text_.size()) {
      char c = text_[pos_];
      if (c == '#') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else if (c == '\n' || c == ';') {
        t = {Token::Kind::End, "", std::string::npos, line_};
        if (c == '\n') ++line_;
        ++pos_;
        return true;
      } else if (c == ' ' || c == '\t' || c == '\r') {
        ++pos_;
      } else if (c == '{' || c == '}') {
        t = {c == '{' ? Token::Kind::Open : Token::Kind::Close, std::string(1, c), std::string::npos, line_};
        ++pos_;
        return true;
      } else {
        return word(t, error);
      }
    }
    t = {Token::Kind::EndOfFile, "", std::string::npos, line_};
    return true;
  }

  int line() const { return line_; }

 private:
  // A word, possibly with quoted parts: key="a b" is one word.
  bool word(Token& t, std::string& error) {
    t = {Token::Kind::Word, "", std::string::npos, line_};
    while (pos_ < text_.size()) {
      char c = text_[pos_];
      if (c == '"') {
        size_t end = text_.find('"', pos_ + 1);
        size_t newline = text_.find('\n', pos_ + 1);
        if (end == std::string::npos || end > newline) {
          error = std::to_string(line_) + ": unterminated quote";
          return false;
        }
        t.text += text_.substr(pos_ + 1, end - pos_ - 1);
        pos_ = end + 1;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ';' || c == '{' || c == '}' ||
                 c == '#') {
        break;
      } else {
        if (c == '=' && t.eq == std::string::npos) t.eq = t.text.size();
        t.text += c;
        ++pos_;
      }
    }
    return true;
  }

  const std::string& text_;
  size_t pos_ = 0;
  int line_ = 1;
};

bool read_file(const std::string& path, std::string& out, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot open";
    return false;
  }
  std::ostringstream buf;
  buf << in.rdbuf();
  out = buf.str();
  if (out.size() > kMaxFileBytes) {
    error = path + ": larger than 4 MiB";
    return false;
  }
  return true;
}

bool parse(const std::string& text, const std::string& file, int depth, std::vector<Statement>& out,
           std::string& error);

// Statements until a closing brace (depth > 0) or the end of the file.
bool parse_block(Lexer& lex, const std::string& file, int include_depth, bool nested,
                 std::vector<Statement>& out, std::string& error) {
  Token t;
  for (;;) {
    if (!lex.next(t, error)) {
      error = file + ":" + error;
      return false;
    }
    if (t.kind == Token::Kind::End) continue;
    if (t.kind == Token::Kind::EndOfFile) {
      if (nested) {
        error = file + ":" + std::to_string(t.line) + ": missing '}'";
        return false;
      }
      return true;
    }
    if (t.kind == Token::Kind::Close) {
      if (!nested) {
        error = file + ":" + std::to_string(t.line) + ": '}' without '{'";
        return false;
      }
      return true;
    }
    if (t.kind == Token::Kind::Open) {
      error = file + ":" + std::to_string(t.line) + ": '{' without a statement";
      return false;
    }
    Statement s;
    s.keyword = t.text;
    s.file = file;
    s.line = t.line;
    bool block = false;
    for (;;) {
      if (!lex.next(t, error)) {
        error = file + ":" + error;
        return false;
      }
      if (t.kind == Token::Kind::Word) {
        if (t.eq == 0) {
          error = file + ":" + std::to_string(t.line) + ": '" + t.text + "' has no key";
          return false;
        }
        if (t.eq != std::string::npos) {
          s.options.emplace_back(t.text.substr(0, t.eq), t.text.substr(t.eq + 1));
        } else {
          s.args.push_back(t.text);
        }
        continue;
      }
      if (t.kind == Token::Kind::Open) block = true;
      break;
    }
    const Token end = t;
    if (block && !parse_block(lex, file, include_depth, true, s.children, error)) return false;
    if (s.keyword == "include") {
      if (s.args.size() != 1 || !s.options.empty() || block) {
        error = s.where() + ": include takes one file name";
        return false;
      }
      if (include_depth >= kMaxIncludeDepth) {
        error = s.where() + ": includes nested deeper than 8 (a cycle?)";
        return false;
      }
      std::string path = s.args[0];
      if (!path.empty() && path[0] != '/' && !folder_of(file).empty()) path = folder_of(file) + "/" + path;
      std::string text;
      if (!read_file(path, text, error)) {
        error = s.where() + ": include: " + error;
        return false;
      }
      if (!parse(text, path, include_depth + 1, out, error)) return false;
    } else {
      out.push_back(std::move(s));
    }
    if (end.kind == Token::Kind::Close) {
      if (!nested) {
        error = file + ":" + std::to_string(end.line) + ": '}' without '{'";
        return false;
      }
      return true;
    }
    if (end.kind == Token::Kind::EndOfFile) {
      if (nested) {
        error = file + ":" + std::to_string(end.line) + ": missing '}'";
        return false;
      }
      return true;
    }
  }
}

bool parse(const std::string& text, const std::string& file, int depth, std::vector<Statement>& out,
           std::string& error) {
  Lexer lex(text);
  return parse_block(lex, file, depth, false, out, error);
}

}  // namespace

Options Statement::reader() const {
  Options o(where(), folder_of(file));
  for (const auto& [k, v] : options) o.set(k, v);
  return o;
}

std::string folder_of(const std::string& path) {
  size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash);
}

bool parse_config_text(const std::string& text, const std::string& file, std::vector<Statement>& out,
                       std::string& error) {
  return parse(text, file, 0, out, error);
}

bool parse_config_file(const std::string& path, std::vector<Statement>& out, std::string& error) {
  std::string text;
  if (!read_file(path, text, error)) return false;
  return parse(text, path, 0, out, error);
}

}  // namespace troupe::robocup
