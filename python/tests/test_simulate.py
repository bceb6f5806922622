"""Python agents in the simulator (quiver.simulate): the same AgentBase classes run_agent() runs over
DDS, registered as roles and run from a scenario with a partition, packet loss, kill -9 and a
restart, in virtual time; checks written in Python judge the end. A seed replays exactly."""
import quiver


class Pinger(quiver.AgentBase):
    def __init__(self, name):
        super().__init__(name)
        self.sent = 0

    def setup(self, ctx):
        def ping():
            if ctx.now() > 5e9 or self.sent >= 40:
                return
            with ctx.graph.transaction() as t:
                t.create_node("ping", f"ping{self.sent}", {"answered": False})
            self.sent += 1
        ctx.every(0.1, ping)


class Answer(quiver.Action):
    def __init__(self):
        super().__init__("answer")

    def find(self, ctx):
        g = ctx.graph
        return [quiver.Match(g.name_of(n), {"ping": n}) for n in g.nodes("ping") if not g.get(n, "answered", True)]

    def holds(self, ctx, m):
        return ctx.graph.has_node(m.at("ping"))

    def lock(self, ctx, m):
        return m.at("ping")

    def start(self, ctx, m):
        pass

    def finish(self, ctx, m):
        with ctx.graph.transaction() as t:
            t.set(m.at("ping"), "answered", True)
            t.set(m.at("ping"), "by", ctx.name)

    def cancel(self, ctx, m, reason):
        pass


class Ponger(quiver.AgentBase):
    def setup(self, ctx):
        self.add_action(Answer(), node_types=["ping"])


def every_ping_answered(run, params):
    g = run.graph("pinger")
    if g is None:
        return ["the pinger is down at the end"]
    pings = g.nodes("ping")
    open_ = [g.name_of(n) for n in pings if not g.get(n, "answered", False)]
    out = []
    if len(pings) < params["min_pings"]:
        out.append(f"{len(pings)} pings, fewer than {params['min_pings']}")
    if open_:
        out.append(f"{len(open_)} of {len(pings)} pings unanswered")
    return out


def replicas_equal(run, params):
    digests = {n: run.graph(n).digest() for n in run.names if run.graph(n) is not None}
    return [] if len(set(digests.values())) == 1 else [f"replicas differ: {digests}"]


SCENARIO = {
    "name": "python ping-pong",
    "agents": ["pinger", "ponger", {"role": "ponger", "name": "backup"}],
    "faults": [{"at_s": 1.0, "loss": 0.3},
               {"at_s": 1.5, "partition": [["pinger"], ["ponger", "backup"]]},
               {"at_s": 2.5, "heal": True},
               {"at_s": 3.0, "kill": "ponger"},
               {"at_s": 4.0, "restart": "ponger"},
               {"at_s": 4.5, "loss": 0.0}],
    "checks": {"every_ping_answered": {"min_pings": 30}, "replicas_equal": True},
    "limit_s": 9,
}
ROLES = {"pinger": Pinger, "ponger": Ponger}
CHECKS = {"every_ping_answered": every_ping_answered, "replicas_equal": replicas_equal}


def test_python_agents_run_in_the_simulator_under_faults():
    lines = []
    out = quiver.simulate(SCENARIO, ROLES, checks=CHECKS, seed=3, log=lambda t, line: lines.append((t, line)))
    print(out)
    assert out["passed"], out["failures"]
    assert out["kills"] == 1 and out["partitions"] == 1, out
    assert any("restarts" in line for _, line in lines), "the ponger came back as a new incarnation"
    # The same seed replays exactly; another seed is another run.
    assert quiver.simulate(SCENARIO, ROLES, checks=CHECKS, seed=3) == {k: v for k, v in out.items()}


def test_a_check_that_does_not_hold_fails_the_run():
    bad = dict(SCENARIO, faults=[{"at_s": 1.0, "kill": "ponger"}, {"at_s": 1.0, "kill": "backup"}])
    out = quiver.simulate(bad, ROLES, checks=CHECKS, seed=1)
    assert not out["passed"]
    assert any("unanswered" in f for f in out["failures"]), out["failures"]


def test_scenario_errors_name_the_value():
    import pytest
    with pytest.raises(quiver.Error) as e:
        quiver.simulate(dict(SCENARIO, faults=[{"at_s": 1, "kill": "nobody"}]), ROLES, checks=CHECKS)
    assert "scenario:/faults/0/kill" in str(e.value)
    with pytest.raises(quiver.Error) as e:
        quiver.simulate(dict(SCENARIO, checks={"telepathy": True}), ROLES, checks=CHECKS)
    assert "/checks/telepathy" in str(e.value)
