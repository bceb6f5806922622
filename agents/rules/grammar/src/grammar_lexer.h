#pragma once
// Tokens of grammar files and the cursor both parsers (our dialect, AGM's) read them with. Every
// error names file:line:column, what was expected and what was found.

#include <string>
#include <string_view>
#include <vector>

#include "quiver/agents/rules/grammar/grammar.h"
#include "quiver/graph/limits.h"

namespace quiver::agents::inline rules::internal {

struct Token {
  enum Kind { kIdent, kNumber, kString, kSymbol, kEnd } kind = kEnd;
  std::string text;
  SourceLoc loc;
};

/// The two spellings of a grammar file.
enum class Dialect : std::uint8_t {
  kQuiver,  ///< `grammar`, `rule`, `constraint`, `allow`; `#` starts a comment anywhere
  kAgm,     ///< AGM's editor files: words of [A-Za-z0-9_.] (node names may be numbers), `*`,
            ///< `=`, `===`, `<`, `>`; `#` comments a whole line only; `include(PATH)` gives the
            ///< path as one string token
};

/// Splits `text` into tokens (the last one kEnd). Returns false and fills `err`/`err_loc` on a
/// lexical error.
bool lex(std::string_view text, Dialect dialect, std::vector<Token>& out, std::string& err,
         SourceLoc& err_loc);

/// True if `text` is written in AGM's dialect: it starts (after comments) with the editor's
/// header, `key=value` lines.
bool looks_like_agm(std::string_view text);

struct ParseError {
  SourceLoc loc;
  std::string message;
};

/// Reading tokens with the checks both parsers share; failures throw ParseError, which the
/// parser's entry point turns into "file:line:column: message".
class TokenCursor {
 public:
  explicit TokenCursor(std::vector<Token> toks) : t_(std::move(toks)) {}

  const Token& peek(std::size_t k = 0) const { return t_[std::min(p_ + k, t_.size() - 1)]; }
  bool at_end() const { return peek().kind == Token::kEnd; }
  bool is(const char* sym) const { return peek().kind == Token::kSymbol && peek().text == sym; }
  bool is_word(const char* w) const { return peek().kind == Token::kIdent && peek().text == w; }
  Token take() { return t_[p_ < t_.size() - 1 ? p_++ : p_]; }
  void expect(const char* sym, const std::string& context) {
    if (!is(sym)) fail(std::string("'") + sym + "' " + context, peek());
    take();
  }
  /// A name (rule, variable, type, label: they travel in deltas, so the limits table bounds them).
  std::string ident(const std::string& what) {
    if (peek().kind != Token::kIdent) fail(what, peek());
    check_name(peek());
    return take().text;
  }
  static void check_name(const Token& t) {
    if (t.text.size() > graph::limits::kMaxNameBytes)
      fail_at(t.loc, "a name of " + std::to_string(t.text.size()) + " bytes (the limit is " +
                         std::to_string(graph::limits::kMaxNameBytes) + ")");
  }
  static std::string describe(const Token& t) {
    switch (t.kind) {
      case Token::kEnd:
        return "the end of the file";
      case Token::kString:
        return "string \"" + t.text + "\"";
      case Token::kNumber:
        return "number " + t.text;
      default:
        return "'" + t.text + "'";
    }
  }
  [[noreturn]] static void fail(const std::string& expected, const Token& at) {
    throw ParseError{at.loc, "expected " + expected + ", found " + describe(at)};
  }
  [[noreturn]] static void fail_at(SourceLoc loc, const std::string& msg) {
    throw ParseError{loc, msg};
  }

 private:
  std::vector<Token> t_;
  std::size_t p_ = 0;
};

/// "source:line:column: message".
std::string located(std::string_view source, SourceLoc loc, const std::string& message);

}  // namespace quiver::agents::inline rules::internal
