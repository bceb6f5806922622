"""The tutorial's agent in Python (docs/agents.md, "A complete agent" and "The same agent in
Python"): it greets every person in the shared graph, one action run per person under a priority
lock on that person; it counts the person changes it sees and reports every five seconds whether it
hears an agent named `speech`. Run it beside `quiver agent --name speech` (from the repository root):

    quiver agent --name speech --world examples/worlds/kitchen.json &
    python3 examples/tutorial/greeter.py --world examples/worlds/kitchen.json --text "Good morning" --run-for 10

CI runs it so (python/tests/test_tutorial.py)."""
import argparse

import quiver


class Greet(quiver.Action):
    def __init__(self, text):
        super().__init__("greet")
        self.text = text

    def find(self, ctx):
        g = ctx.graph
        return [quiver.Match(g.name_of(n), {"person": n}) for n in g.nodes("person")
                if not g.get(n, "greeted", False)]

    def holds(self, ctx, m):
        return ctx.graph.has_node(m.at("person"))

    def lock(self, ctx, m):
        return (m.at("person"), 1)  # a priority lock on the person: one greeter at a time

    def start(self, ctx, m):  # the mark others see
        with ctx.graph.transaction() as t:
            t.set(m.at("person"), "greeting", "executing")

    def finish(self, ctx, m):  # the result
        with ctx.graph.transaction() as t:
            t.set(m.at("person"), "greeting", self.text)
            t.set(m.at("person"), "greeted", True)

    def cancel(self, ctx, m, reason):
        ctx.log("greeting " + m.key + " cancelled: " + reason.name)
        if ctx.graph.has_node(m.at("person")):
            with ctx.graph.transaction() as t:
                t.remove_attr(m.at("person"), "greeting")  # take the mark back


class Greeter(quiver.AgentBase):
    def __init__(self, text):
        super().__init__("greeter")
        self.text = text
        self.seen = 0

    def setup(self, ctx):
        self.add_action(Greet(self.text), node_types=["person"])
        self.subscribe(self.count, node_types=["person"])
        ctx.every(5.0, lambda: ctx.log("speech is here" if ctx.hears("speech") else "no speech"))

    def count(self, ctx, batch):
        self.seen += len(batch.nodes)

    def teardown(self, ctx):
        ctx.log("bye")

    def status(self):
        return {"person_changes": self.seen}


def main():
    p = argparse.ArgumentParser(description="greets every person in the shared graph")
    p.add_argument("--text", default="Hello", help="what to say")
    p.add_argument("--world", help="seed the shared graph from this world file")
    p.add_argument("--domain", type=int, default=0)
    p.add_argument("--run-for", type=float, default=0.0, help="seconds (0: until Ctrl-C)")
    p.add_argument("--status-ms", type=int, default=0)
    a = p.parse_args()
    quiver.run_agent(Greeter(a.text), domain=a.domain, world=a.world, run_for=a.run_for, status_ms=a.status_ms)


if __name__ == "__main__":
    main()
