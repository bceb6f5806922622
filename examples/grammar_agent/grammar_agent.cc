// A grammar-checked agent with no executive: every local change must be one rule of its grammar,
// and it takes a priority lock on the person before acting. DDS on loopback. Run from the
// repository root:  grammar_agent examples/grammars/speech.aggl examples/worlds/kitchen.json
#include <cstdio>
#include <string>

#include "quiver/agents/runtime/process/dds_replica.h"
#include "quiver/agents/rules/grammar/grammar_guard.h"
#include "quiver/agents/rules/locks/locks.h"
#include "quiver/graph/world_file.h"
using namespace quiver;

template <class T>
bool check(const Result<T>& r) {
  if (!r.ok()) std::fprintf(stderr, "%s\n", r.error().to_string().c_str());
  return r.ok();
}

int main(int argc, char** argv) {
  auto grammar = agents::load_grammar_file(argc > 1 ? argv[1] : "examples/grammars/speech.aggl");
  auto world = graph::world_seed_file(argc > 2 ? argv[2] : "examples/worlds/kitchen.json");
  agents::DdsReplicaOptions o;
  o.name = "speech";  // o.dds defaults to the loopback configuration
  auto created = agents::DdsReplica::create(o);
  if (!check(grammar) || !check(world) || !check(created)) return 1;
  agents::DdsReplica& agent = **created;
  graph::Graph& g = agent.graph();
  // The same world as every agent started with this file (a seed depends on the file alone).
  if (!check(agent.replicator().seed(world->delta))) return 1;

  agents::GrammarGuard guard(g, agents::GrammarChecker(std::move(grammar).value()), "speech");
  agents::LockManager locks(g, &agent.replicator(), agents::monotonic_ns);
  locks.install(guard.validator());  // both checks run before every commit
  const graph::NodeId person = *g.find_node("person");
  const graph::NodeId robot = *g.find_node("robot");
  const graph::NodeId speaking = *g.find_node("speaking");
  if (!locks.acquire(person, /*priority=*/2).ok()) return 1;
  // Held once every live peer acknowledged the claim.
  agent.spin_until([&] { locks.tick(); return locks.holds(person); }, 2'000'000'000);

  // One application of rule startSpeaking: robot -[is_not]-> speaking becomes -[is]->.
  auto tx = g.begin();
  (void)tx.delete_edge(robot, speaking, graph::Symbol("is_not"));
  (void)tx.insert_edge(robot, speaking, graph::Symbol("is"));
  auto started = tx.commit();
  std::printf("startSpeaking: %s\n", started.ok() ? "committed" : started.error().to_string().c_str());

  // No rule deletes a person: the guard refuses, nothing is applied or published.
  auto bad = g.begin();
  (void)bad.delete_node(person);
  auto refused = bad.commit();
  std::printf("delete person: %s\n", refused.ok() ? "committed (?)" : refused.error().to_string().c_str());
  return started.ok() && !refused.ok() ? 0 : 1;
}
