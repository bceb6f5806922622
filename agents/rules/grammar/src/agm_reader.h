#pragma once
// Private: the one reader of AGM's syntax, shared by the parsers of its two file kinds — .aggl
// grammars (aggl_agm_parse.cc) and .aggt missions (agents/rules/mission) — names, numbers, a
// graph { v:type(x,y) ... a->b(label)[*] ... } and a [WORD { FORMULA }] section.

#include <string>
#include <utility>
#include <vector>

#include "aggl_agm_formula.h"
#include "grammar_lexer.h"
#include "quiver/agents/rules/grammar/grammar.h"

namespace quiver::agents::inline rules::internal {

/// A TokenCursor over one file in AGM's syntax; `source` names the file in messages.
class AgmReader : public TokenCursor {
 public:
  AgmReader(std::vector<Token> toks, std::string source)
      : TokenCursor(std::move(toks)), src_(std::move(source)) {}

 protected:
  /// A name: an identifier or a number (AGM's node names may be numbers).
  std::string name_token(const std::string& what);

  /// An integer (a number token, rounded).
  static int number(const Token& t, const std::string& what);

  /// { v:type(x,y) ... a->b(label)[*] ... }: its '{' expected `open` ("to open the target
  /// graph"); messages say where it is, `context` ("the target"), and call its nodes `node`
  /// ("variable", "node"). `on_type` (if set) is told each node's type; `on_bang` (if set) each
  /// '!' inside a link label, which AGM ignores, before it is skipped.
  Pattern graph(const std::string& open, const std::string& context, const char* node,
                const TypeUse& on_type, const TypeUse& on_bang);

  /// [WORD { FORMULA }]: `parse` reads the formula; an empty section is no formula. What follows
  /// the formula up to the '}' is ignored, with a note in `notes` (ignore_rest).
  template <class Parse>
  void section(const char* word, std::vector<std::string>& notes, const Parse& parse) {
    if (!is_word(word)) return;
    take();
    expect("{", std::string("to open the ") + word);
    if (!is("}")) {
      parse();
      ignore_rest(word, notes);
    }
    take();
  }

  /// AGM reads one formula and ignores what follows it up to the '}' (its parser does not ask
  /// for the end of the text). So do we, with a note in `notes`: it is often a stray ')',
  /// sometimes a second formula that should have been joined with (and ...).
  void ignore_rest(const char* section, std::vector<std::string>& notes);

  std::string src_;
};

}  // namespace quiver::agents::inline rules::internal
