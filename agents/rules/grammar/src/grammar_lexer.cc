// The tokens of grammar files in both dialects (ours and AGM's), and errors located at file:line:column.
#include "grammar_lexer.h"

#include <cctype>

namespace quiver::agents::inline rules::internal {
namespace {

bool alpha(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }
bool digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }
bool alnum(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; }
bool space(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

class Lexer {
 public:
  Lexer(std::string_view s, Dialect d) : s_(s), agm_(d == Dialect::kAgm) {}

  bool run(std::vector<Token>& out, std::string& err, SourceLoc& err_loc) {
    while (true) {
      skip_space();
      Token t;
      t.loc = {line_, col_};
      if (i_ >= s_.size()) {
        t.kind = Token::kEnd;
        out.push_back(t);
        return true;
      }
      const char c = s_[i_];
      const bool ok = agm_ ? agm_token(t, out) : quiver_token(t);
      if (!ok) {
        err = err_.empty() ? std::string("unexpected character '") + c + "'" : err_;
        err_loc = err_loc_.line ? err_loc_ : t.loc;
        return false;
      }
      out.push_back(std::move(t));
    }
  }

 private:
  // ---- our dialect
  bool quiver_token(Token& t) {
    const char c = s_[i_];
    if (alpha(c) || c == '_') {
      t.kind = Token::kIdent;
      while (i_ < s_.size()) {
        const char d = s_[i_];
        // A '-' continues a word (rt-poses) unless it starts an arrow.
        const bool dash = d == '-' && i_ + 1 < s_.size() && s_[i_ + 1] != '>' &&
                          (alnum(s_[i_ + 1]) || s_[i_ + 1] == '_');
        if (!alnum(d) && d != '_' && !dash) break;
        t.text += d;
        advance();
      }
      return true;
    }
    if (digit(c) || ((c == '-' || c == '.') && i_ + 1 < s_.size() && digit(s_[i_ + 1]))) {
      t.kind = Token::kNumber;
      while (i_ < s_.size() && (digit(s_[i_]) || s_[i_] == '.' || s_[i_] == 'e' || s_[i_] == 'E' ||
                                ((s_[i_] == '-' || s_[i_] == '+') && !t.text.empty() &&
                                 (t.text.back() == 'e' || t.text.back() == 'E')) ||
                                (t.text.empty() && s_[i_] == '-'))) {
        t.text += s_[i_];
        advance();
      }
      return true;
    }
    if (c == '"') return string(t);
    t.kind = Token::kSymbol;
    static const char* two[] = {"->", "=>", "==", "!=", "<=", ">="};
    for (const char* op : two)
      if (s_.substr(i_, 2) == op) t.text = op;
    if (t.text.empty()) {
      if (std::string_view("{}():!.,<>;").find(c) == std::string_view::npos) return false;
      t.text = std::string(1, c);
    }
    for (std::size_t k = 0; k < t.text.size(); ++k) advance();
    return true;
  }

  bool string(Token& t) {
    t.kind = Token::kString;
    advance();
    while (i_ < s_.size() && s_[i_] != '"') {
      if (s_[i_] == '\n') return fail(t.loc, "unterminated string");
      if (s_[i_] == '\\' && i_ + 1 < s_.size()) advance();
      t.text += s_[i_];
      advance();
    }
    if (i_ >= s_.size()) return fail(t.loc, "unterminated string");
    advance();
    return true;
  }

  // ---- AGM's dialect (AGM's parser: words [A-Za-z0-9_.], signed integers, `===`)
  bool agm_token(Token& t, const std::vector<Token>& out) {
    const char c = s_[i_];
    if (pending_path_) {
      pending_path_ = false;
      t.kind = Token::kString;
      while (i_ < s_.size() && s_[i_] != ')') {
        if (s_[i_] == '(') return fail({line_, col_}, "a '(' inside an include path");
        t.text += s_[i_];
        advance();
      }
      if (i_ >= s_.size()) return fail(t.loc, "an include path without its closing ')'");
      while (!t.text.empty() && space(t.text.back())) t.text.pop_back();
      return true;
    }
    const bool sign = (c == '-' || c == '+') && i_ + 1 < s_.size() && digit(s_[i_ + 1]);
    if (alnum(c) || c == '_' || c == '.' || sign) {
      t.text += c;
      advance();
      while (i_ < s_.size() && (alnum(s_[i_]) || s_[i_] == '_' || s_[i_] == '.')) {
        t.text += s_[i_];
        advance();
      }
      // Numbers are words made of digits (one '.' at most), signed or not: node names may be
      // numbers too (`1->2(stop)`), which the parser accepts where a name is expected.
      bool number = true;
      int dots = 0;
      for (std::size_t k = sign ? 1 : 0; k < t.text.size(); ++k) {
        if (t.text[k] == '.')
          ++dots;
        else if (!digit(t.text[k]))
          number = false;
      }
      number = number && dots <= 1 && t.text.back() != '.' && t.text[sign ? 1 : 0] != '.';
      if (sign && !number)
        return fail(t.loc, "a sign before '" + t.text.substr(1) + "', which is no number");
      t.kind = number ? Token::kNumber : Token::kIdent;
      return true;
    }
    if (c == '"') return fail(t.loc, "a string (AGM's dialect has none)");
    if (c == '(' && !out.empty() && out.back().kind == Token::kIdent &&
        out.back().text == "include") {
      // include(PATH): the path is every character up to ')', spaces around it dropped.
      t.kind = Token::kSymbol;
      t.text = "(";
      advance();
      pending_path_ = true;
      return true;
    }
    t.kind = Token::kSymbol;
    static const char* multi[] = {"===", "->", "=>", "=="};
    for (const char* op : multi)
      if (t.text.empty() && s_.substr(i_, std::string_view(op).size()) == op) t.text = op;
    if (t.text.empty()) {
      if (std::string_view("{}():,*!=<>").find(c) == std::string_view::npos) return false;
      t.text = std::string(1, c);
    }
    for (std::size_t k = 0; k < t.text.size(); ++k) advance();
    return true;
  }

  bool fail(SourceLoc loc, std::string msg) {
    err_ = std::move(msg);
    err_loc_ = loc;
    return false;
  }

  void advance() {
    if (s_[i_] == '\n') {
      ++line_;
      col_ = 1;
      line_blank_ = true;
    } else {
      ++col_;
      if (!space(s_[i_])) line_blank_ = false;
    }
    ++i_;
  }
  void skip_space() {
    if (pending_path_) {  // the path keeps its inner spaces; only leading ones go
      while (i_ < s_.size() && space(s_[i_])) advance();
      return;
    }
    while (i_ < s_.size()) {
      if (space(s_[i_])) {
        advance();
      } else if (s_[i_] == '#' && (!agm_ || line_blank_)) {
        // AGM drops lines that start with '#'; our dialect comments to the end of any line.
        while (i_ < s_.size() && s_[i_] != '\n') advance();
      } else {
        break;
      }
    }
  }

  std::string_view s_;
  bool agm_;
  std::size_t i_ = 0;
  int line_ = 1, col_ = 1;
  bool line_blank_ = true;
  bool pending_path_ = false;
  std::string err_;
  SourceLoc err_loc_;
};

}  // namespace

bool lex(std::string_view text, Dialect dialect, std::vector<Token>& out, std::string& err,
         SourceLoc& err_loc) {
  return Lexer(text, dialect).run(out, err, err_loc);
}

bool looks_like_agm(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && space(text[i])) ++i;
    if (i < text.size() && text[i] == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
      continue;
    }
    break;
  }
  // key=value: a word, optional blanks, then '=' that is not '=>' or '=='.
  std::size_t j = i;
  while (j < text.size() && (alnum(text[j]) || text[j] == '_' || text[j] == '.')) ++j;
  if (j == i) return text.substr(i, 3) == "===";
  while (j < text.size() && (text[j] == ' ' || text[j] == '\t')) ++j;
  return j < text.size() && text[j] == '=' &&
         (j + 1 >= text.size() || (text[j + 1] != '>' && text[j + 1] != '='));
}

std::string located(std::string_view source, SourceLoc loc, const std::string& message) {
  return std::string(source) + ":" + std::to_string(loc.line) + ":" + std::to_string(loc.column) +
         ": " + message;
}

}  // namespace quiver::agents::inline rules::internal
