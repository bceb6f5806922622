// Pictures laid out with Graphviz's C library (one caller at a time), and Graphviz's own DOT and SVG output of
// them.
#include "quiver/agents/view/render/layout.h"

#include <graphviz/cgraph.h>
#include <graphviz/gvc.h>

#include <algorithm>
#include <mutex>
#include <string>
#include <unordered_set>

#include "quiver/agents/view/render/type_colour.h"

namespace quiver::agents::inline view::render {
namespace {

// Graphviz keeps global state (the error handler, the layouts' statics): one user at a time.
std::mutex& graphviz_mutex() {
  static std::mutex m;
  return m;
}

// One context for the process, made on first use: it reads the plugin configuration once.
GVC_t* context() {
  static GVC_t* gvc = gvContext();
  return gvc;
}

// What Graphviz reported while we held the lock (its handler is global, hence static).
std::string& graphviz_messages() {
  static std::string text;
  return text;
}
int collect_message(char* text) {
  if (graphviz_messages().size() < 4096) graphviz_messages() += text;
  return 0;
}

char* c(const char* s) { return const_cast<char*>(s); }
char* c(const std::string& s) { return const_cast<char*>(s.c_str()); }

// Graphviz reads backslashes in labels as escapes (\n, \N, \G ...): double them, then break
// the lines with \n.
std::string label_text(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 4);
  for (char ch : text) {
    if (ch == '\\')
      out += "\\\\";
    else if (ch == '\n')
      out += "\\n";
    else
      out += ch;
  }
  return out;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// A picture built as a Graphviz graph and laid out; the lock is held for its whole life.
class GvGraph {
 public:
  GvGraph() : lock_(graphviz_mutex()) {
    graphviz_messages().clear();
    previous_handler_ = agseterrf(collect_message);
    previous_level_ = agseterr(AGWARN);
  }
  ~GvGraph() {
    if (g_ != nullptr) {
      if (laid_out_) gvFreeLayout(context(), g_);
      agclose(g_);
    }
    agseterrf(previous_handler_);
    agseterr(previous_level_);
  }
  GvGraph(const GvGraph&) = delete;
  GvGraph& operator=(const GvGraph&) = delete;

  Status build_and_lay_out(const Picture& p, Engine engine, bool with_title,
                           const LayoutStyle& style = {}) {
    engine_ = resolve_engine(engine, p.nodes.size());
    style_ = style;
    if (context() == nullptr)
      return make_error(ErrorCode::kInternal, "lay_out(): Graphviz gave no context");
    g_ = agopen(c("quiver"), Agdirected, nullptr);
    graph_defaults(with_title ? p.title : std::string());
    Agsym_t* label = agattr(g_, AGNODE, c("label"), c("\\N"));
    Agsym_t* shape = agattr(g_, AGNODE, c("shape"), c("ellipse"));
    Agsym_t* fill = agattr(g_, AGNODE, c("fillcolor"), c("white"));
    Agsym_t* colour = agattr(g_, AGNODE, c("color"), c(css_hex(kInkColour)));
    Agsym_t* pen = agattr(g_, AGNODE, c("penwidth"), c("1"));
    Agsym_t* font = agattr(g_, AGNODE, c("fontname"), c("Helvetica"));
    Agsym_t* klass = agattr(g_, AGNODE, c("class"), c(""));
    agattr(g_, AGNODE, c("style"), c("filled"));
    agattr(g_, AGNODE, c("fontsize"), c(number(kNodeFontPt)));
    agattr(g_, AGNODE, c("margin"), c("0.08,0.04"));

    // Graphviz names must be unique; a picture's names are, but a timeline's union of every
    // node that ever lived may hold two nodes of one name.
    std::unordered_set<std::string> taken;
    nodes_.reserve(p.nodes.size());
    for (const PictureNode& n : p.nodes) {
      std::string key = n.name;
      for (int i = 2; !taken.insert(key).second; ++i) key = n.name + "~" + std::to_string(i);
      Agnode_t* v = agnode(g_, c(key), 1);
      agxset(v, label, c(label_text(node_label(n))));
      if (n.geometric) agxset(v, shape, c("box"));
      agxset(v, fill, c(css_hex(type_colour(n.type))));
      if (n.highlighted) {
        agxset(v, colour, c(css_hex(kHighlightColour)));
        agxset(v, pen, c("3"));
        agxset(v, font, c("Helvetica-Bold"));
        agxset(v, klass, c("highlight"));
      }
      nodes_.push_back(v);
    }

    Agsym_t* elabel = agattr(g_, AGEDGE, c("label"), c(""));
    Agsym_t* ecolour = agattr(g_, AGEDGE, c("color"), c(css_hex(kInkColour)));
    Agsym_t* efont_colour = agattr(g_, AGEDGE, c("fontcolor"), c(css_hex(kInkColour)));
    Agsym_t* estyle = agattr(g_, AGEDGE, c("style"), c("solid"));
    Agsym_t* epen = agattr(g_, AGEDGE, c("penwidth"), c("1"));
    Agsym_t* efont = agattr(g_, AGEDGE, c("fontname"), c("Helvetica"));
    Agsym_t* eclass = agattr(g_, AGEDGE, c("class"), c(""));
    agattr(g_, AGEDGE, c("fontsize"), c(number(kEdgeFontPt)));
    agattr(g_, AGEDGE, c("arrowsize"), c("0.7"));
    edges_.reserve(p.edges.size());
    for (const PictureEdge& e : p.edges) {
      // The type is the key: several types may link one pair.
      Agedge_t* a = agedge(g_, nodes_.at(e.from), nodes_.at(e.to), c(e.type), 1);
      agxset(a, elabel, c(label_text(e.type)));
      const std::string stroke = css_hex(e.highlighted ? kHighlightColour
                                         : e.geometric ? kGeometryColour
                                                       : type_stroke_colour(e.type));
      agxset(a, ecolour, c(stroke));
      agxset(a, efont_colour, c(stroke));
      if (e.geometric) agxset(a, estyle, c("dashed"));
      if (e.highlighted) {
        agxset(a, epen, c("3"));
        agxset(a, efont, c("Helvetica-Bold"));
        agxset(a, eclass, c("highlight"));
      }
      edges_.push_back(a);
    }

    if (gvLayout(context(), g_, to_string(engine_)) != 0)
      return make_error(ErrorCode::kInternal, std::string("lay_out(): Graphviz's '") +
                                                  to_string(engine_) +
                                                  "' layout failed: " + messages());
    laid_out_ = true;
    return {};
  }

  Layout read() const {
    Layout l;
    l.engine = engine_;
    const boxf bb = GD_bb(g_);
    l.width = bb.UR.x - bb.LL.x;
    l.height = bb.UR.y - bb.LL.y;
    auto at = [&](pointf q) { return Point{q.x - bb.LL.x, bb.UR.y - q.y}; };
    l.nodes.reserve(nodes_.size());
    for (Agnode_t* v : nodes_)
      l.nodes.push_back(NodePlace{at(ND_coord(v)), ND_width(v) * 72.0, ND_height(v) * 72.0});
    l.edges.reserve(edges_.size());
    for (Agedge_t* a : edges_) {
      EdgePlace place;
      if (const splines* spl = ED_spl(a); spl != nullptr && spl->size > 0) {
        const bezier& bz = spl->list[0];
        place.curve.reserve(bz.size);
        for (int i = 0; i < bz.size; ++i) place.curve.push_back(at(bz.list[i]));
        if (bz.eflag) {
          place.arrow = true;
          place.arrow_tip = at(bz.ep);
        }
      }
      if (const textlabel_t* t = ED_label(a); t != nullptr && t->set) {
        place.has_label = true;
        place.label = at(t->pos);
      }
      l.edges.push_back(std::move(place));
    }
    return l;
  }

  Result<std::string> render(const char* format) {
    char* data = nullptr;
    unsigned int length = 0;
    if (gvRenderData(context(), g_, format, &data, &length) != 0 || data == nullptr)
      return make_error(ErrorCode::kInternal,
                        std::string("graphviz_text(): Graphviz could not render '") + format +
                            "': " + messages());
    std::string out(data, length);
    gvFreeRenderData(data);
    return out;
  }

 private:
  void graph_defaults(const std::string& title) {
    agattr(g_, AGRAPH, c("fontname"), c("Helvetica"));
    if (!title.empty()) {
      agattr(g_, AGRAPH, c("label"), c(label_text(title)));
      agattr(g_, AGRAPH, c("labelloc"), c("t"));
      agattr(g_, AGRAPH, c("fontsize"), c(number(kTitleFontPt)));
    }
    agattr(g_, AGRAPH, c("bgcolor"), c("white"));
    agattr(g_, AGRAPH, c("pad"), c("0.2"));
    if (engine_ == Engine::kDot) {
      if (style_.direction == LayoutStyle::Direction::kLeftRight)
        agattr(g_, AGRAPH, c("rankdir"), c("LR"));
      agattr(g_, AGRAPH, c("nodesep"), c("0.3"));
      agattr(g_, AGRAPH, c("ranksep"), c("0.5"));
    } else {
      // Nodes must not overlap (their labels would); sfdp and neato remove overlaps themselves.
      agattr(g_, AGRAPH, c("overlap"), c("false"));
      agattr(g_, AGRAPH, c("sep"), c("+6"));
    }
  }
  static std::string messages() {
    std::string m = graphviz_messages();
    while (!m.empty() && (m.back() == '\n' || m.back() == ' ')) m.pop_back();
    return m.empty() ? "no message" : m;
  }

  std::unique_lock<std::mutex> lock_;
  agusererrf previous_handler_ = nullptr;
  agerrlevel_t previous_level_ = AGWARN;
  Engine engine_ = Engine::kDot;
  LayoutStyle style_;
  Agraph_t* g_ = nullptr;
  bool laid_out_ = false;
  std::vector<Agnode_t*> nodes_;
  std::vector<Agedge_t*> edges_;
};

}  // namespace

const char* to_string(Engine e) {
  switch (e) {
    case Engine::kAuto:
      return "auto";
    case Engine::kDot:
      return "dot";
    case Engine::kNeato:
      return "neato";
    case Engine::kSfdp:
      return "sfdp";
  }
  return "?";
}

Result<Engine> parse_engine(std::string_view name) {
  for (Engine e : {Engine::kAuto, Engine::kDot, Engine::kNeato, Engine::kSfdp})
    if (name == to_string(e)) return e;
  return make_error(ErrorCode::kInvalidArgument, "parse_engine(): unknown layout engine '" +
                                                     std::string(name) +
                                                     "' (the engines are auto, dot, neato, sfdp)");
}

Engine resolve_engine(Engine e, std::size_t nodes) {
  if (e != Engine::kAuto) return e;
  return nodes <= kDotMaxNodes ? Engine::kDot : Engine::kSfdp;
}

Result<Layout> lay_out(const Picture& p, Engine engine, LayoutStyle style) {
  GvGraph g;
  if (Status s = g.build_and_lay_out(p, engine, /*with_title=*/false, style); !s.ok())
    return s.error();
  return g.read();
}

Result<Layout> lay_out_to_fit(const Picture& p, Engine engine, double width, double height) {
  auto down = lay_out(p, engine);
  if (!down.ok() || down->engine != Engine::kDot) return down;
  auto across = lay_out(p, engine, LayoutStyle{LayoutStyle::Direction::kLeftRight});
  if (!across.ok()) return across;
  auto fit = [&](const Layout& l) {
    return std::min(width / std::max(l.width, 1.0), height / std::max(l.height, 1.0));
  };
  // Across only when clearly larger: top-down is how the RT tree reads.
  if (fit(*across) > 1.2 * fit(*down)) return across;
  return down;
}

Result<std::string> graphviz_text(const Picture& p, TextFormat format, Engine engine) {
  GvGraph g;
  if (Status s = g.build_and_lay_out(p, engine, /*with_title=*/true); !s.ok()) return s.error();
  return g.render(format == TextFormat::kDot ? "dot" : "svg");
}

}  // namespace quiver::agents::inline view::render
