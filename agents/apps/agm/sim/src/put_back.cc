// The 'person' of clean-table: puts the first mug back on the table once, under its own grammar.
#include "put_back.h"

#include "quiver/agents/apps/agm/agm_schema.h"

namespace quiver::agents::inline apps::agm::internal {
namespace {

using graph::NodeId;

// It moves the mug from wherever it is back onto the table: the clean-the-table plan no longer
// reaches the mission from there.
constexpr const char* kPersonGrammar = R"(grammar person
types {
  room
  table
  object
  mug : object
}
allow attributes
allow rt-poses
allow rt-moves
rule putBack : active {
  { o:object t:table a:room b:room  o->a(in)  t->b(in)  !o->t(on) }
  =>
  { o:object t:table a:room b:room  o->b(in)  t->b(in)  o->t(on) }
}
)";

}  // namespace

PutBack::PutBack(std::int64_t at_ns) : Agent("person"), at_ns_(at_ns) {
  set_grammar_text(kPersonGrammar, "person.aggl");
}

void PutBack::setup(AgentContext& ctx) {
  ctx.every(100'000'000, [this, &ctx] {
    if (done_ || ctx.now() < at_ns_) return;
    graph::Graph& g = ctx.graph();
    const NodeId mug = node_id(g, "mug"), table = node_id(g, "table"),
                 robot = node_id(g, node::kRobot), world = node_id(g, node::kWorld);
    if (mug.is_null() || table.is_null() || world.is_null() || g.has_edge(mug, table, edge::kOn) ||
        g.has_edge(robot, mug, edge::kCarrying) || g.has_edge(robot, mug, edge::kGrasping))
      return;
    auto from = room_of(g, mug), to = room_of(g, table);
    if (!from || !to || *from == *to) return;
    graph::Transaction tx = g.begin();
    graph::Pose X_WM;
    X_WM.translation = {8.70, 2.0, 0.81};
    Status st = tx.delete_edge(mug, *from, graph::Symbol(edge::kIn));
    if (st.ok()) st = tx.insert_edge(mug, *to, graph::Symbol(edge::kIn));
    if (st.ok()) st = tx.insert_edge(mug, table, graph::Symbol(edge::kOn));
    if (st.ok()) st = tx.set_rt(world, mug, X_WM, ctx.now());
    if (st.ok()) {
      if (auto c = tx.commit(); !c.ok()) st = c.error();
    }
    if (!st.ok()) {
      ctx.log("putBack refused: " + st.error().to_string());
      return;
    }
    done_ = true;
    ctx.log("a person put the mug back on the table");
  });
}

}  // namespace quiver::agents::inline apps::agm::internal
