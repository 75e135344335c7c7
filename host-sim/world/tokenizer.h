// Splits the text of one world file into tokens, Stage 4's lexical rules:
// `#` starts a comment to the end of the line; a word starts with a letter and
// goes on with letters, digits and `.-_[]` (so `point[0]` is one word); a
// number starts with one of `+-.0123456789`; strings are double-quoted on one
// line; `( ) [ ]` stand alone. Numbers may also carry an exponent (1e-3),
// which Stage did not read.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "host-sim/world/diagnostics.h"

namespace troupe::world {

enum class TokenKind { Word, Number, String, OpenEntity, CloseEntity, OpenTuple, CloseTuple };

/// One token, 32 bytes: a 100,000-robot world has millions of them, so the
/// text is a view into the file's text (which must outlive the tokens) and
/// the location is a line of the one file being tokenized.
struct Token {
  TokenKind kind;
  /// Line in the file, from 1.
  int line = 0;
  /// The word, the number's text or the string without its quotes.
  std::string_view text;
  /// Numbers only: the value (unitless as written; the loader converts).
  double number = 0;
};

/// A readable name for error messages: "word 'pose'", "'('", "number 3".
std::string describe(const Token& token);

/// Tokenizes `text` (the contents of `file`); the tokens view `text`.
/// Returns false after reporting the first lexical error (an unexpected
/// character, an unterminated string, a malformed number) to `diags`; `out`
/// then holds the tokens before it.
bool tokenize(std::string_view text, const std::shared_ptr<const std::string>& file, std::vector<Token>& out,
              Diagnostics& diags);

}  // namespace troupe::world
