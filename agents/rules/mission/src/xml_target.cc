// AGM's XML targets: <AGMModel> with <symbol id type [x y]> and <link src dst label [enabled]>, the
// form of AGM's own planner examples (AGGLPlanner/example_HRI/*/target*.xml).
#include "xml_target.h"

#include <pugixml.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <map>
#include <optional>
#include <string>

namespace quiver::agents::inline rules::internal {
namespace {

class Locator {
 public:
  Locator(std::string_view source, std::string_view text) : source_(source), text_(text) {}
  SourceLoc where(std::ptrdiff_t offset) const {
    SourceLoc l{1, 1};
    const auto end = static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(offset, 0, static_cast<std::ptrdiff_t>(text_.size())));
    for (std::size_t i = 0; i < end; ++i) {
      if (text_[i] == '\n') {
        ++l.line;
        l.column = 1;
      } else {
        ++l.column;
      }
    }
    return l;
  }
  // "source:line:column: "
  std::string at(std::ptrdiff_t offset) const {
    const SourceLoc l = where(offset);
    return std::string(source_) + ":" + std::to_string(l.line) + ":" + std::to_string(l.column) + ": ";
  }
  // An element's place is its '<' (pugixml's offset is its name's).
  std::string at(const pugi::xml_node& n) const { return at(n.offset_debug() - 1); }
  SourceLoc where(const pugi::xml_node& n) const { return where(n.offset_debug() - 1); }

 private:
  std::string_view source_, text_;
};

bool is_number(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
}

// "05" is AGM id 5 (AGM reads ids with atoi); ids too long for 64 bits stay as written.
std::string canonical(std::string_view id) {
  std::uint64_t n = 0;
  auto [p, ec] = std::from_chars(id.data(), id.data() + id.size(), n);
  return ec == std::errc() && p == id.data() + id.size() ? std::to_string(n) : std::string(id);
}

bool disabled(std::string_view v) {  // AGM's spellings of false
  std::string s(v);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s == "false" || s == "f" || s == "fa" || s == "fal" || s == "fals" || s == "0" || s == "n" || s == "no";
}

std::optional<int> coordinate(const pugi::xml_attribute& a) {
  if (!a) return std::nullopt;
  std::string_view s = a.value();
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  int v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size()) return std::nullopt;
  return v;
}

}  // namespace

bool looks_like_xml(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first != std::string_view::npos && text.substr(first, 3) == "\xEF\xBB\xBF") return looks_like_xml(text.substr(first + 3));
  return first != std::string_view::npos && text[first] == '<';
}

Result<Mission> parse_xml_target(std::string_view text, std::string_view source) {
  const Locator loc(source, text);
  auto bad = [&](const std::string& where, const std::string& what) {
    return make_error(ErrorCode::kMalformed, where + what);
  };
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!parsed) return bad(loc.at(parsed.offset), std::string("XML syntax error: ") + parsed.description());
  const pugi::xml_node root = doc.document_element();
  if (std::string_view(root.name()) != "AGMModel")
    return bad(loc.at(root), "the root element is <" + std::string(root.name()) +
                                 ">: not a mission (a mission is an AGM target: a .aggt file, or an AGM XML "
                                 "target with the root <AGMModel>)");
  Mission m;
  m.source = std::string(source);
  std::map<std::string, std::size_t> symbols;
  auto required = [&](const pugi::xml_node& e, const char* name, std::string& out) -> Status {
    const pugi::xml_attribute a = e.attribute(name);
    if (!a || *a.value() == '\0')
      return make_error(ErrorCode::kMalformed, loc.at(e) + "<" + e.name() + "> without " + name);
    out = a.value();
    return {};
  };
  for (const pugi::xml_node& e : root.children()) {
    if (e.type() != pugi::node_element) continue;
    const std::string_view name = e.name();
    if (name == "symbol") {
      std::string id, type;
      if (Status s = required(e, "id", id); !s.ok()) return s.error();
      if (Status s = required(e, "type", type); !s.ok()) return s.error();
      const bool constant = is_number(id);
      if (constant) id = canonical(id);
      if (!symbols.emplace(id, m.pattern.nodes.size()).second)
        return bad(loc.at(e), "a second symbol with id " + id);
      PatternNode n;
      n.var = id;
      n.type = type;
      n.loc = loc.where(e);
      if (auto x = coordinate(e.attribute("x")), y = coordinate(e.attribute("y")); x && y) n.pos = std::make_pair(*x, *y);
      m.pattern.nodes.push_back(std::move(n));
      m.constant.push_back(constant);
      if (e.child("attribute"))
        m.notes.push_back(loc.at(e.child("attribute")) + "symbol " + id +
                          ": attributes are not part of a target (AGM's planner does not match them): ignored");
    } else if (name == "link") {
      std::string src, dst, label;
      if (Status s = required(e, "src", src); !s.ok()) return s.error();
      if (Status s = required(e, "dst", dst); !s.ok()) return s.error();
      if (Status s = required(e, "label", label); !s.ok()) return s.error();
      for (std::string* end : {&src, &dst}) {
        if (is_number(*end)) *end = canonical(*end);
        if (!symbols.count(*end))
          return bad(loc.at(e), "the link names symbol " + *end + ", which no <symbol> before it declares");
      }
      PatternEdge edge;
      edge.from = src;
      edge.to = dst;
      edge.label = label;
      edge.symbol = graph::Symbol(label);
      edge.negated = disabled(e.attribute("enabled").value());
      edge.loc = loc.where(e);
      m.pattern.edges.push_back(std::move(edge));
    } else {
      m.notes.push_back(loc.at(e) + "<" + std::string(name) + "> is not part of an AGM target: ignored");
    }
  }
  return m;
}

}  // namespace quiver::agents::inline rules::internal
