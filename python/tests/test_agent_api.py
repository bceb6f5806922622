"""Runtime agents written in Python (quiver.AgentBase, quiver.Action, quiver.run_agent): the DSR
loop run by the C++ process host over Cyclone DDS (loopback configuration), observed by a
quiver.Agent in this process."""
import os
import pathlib
import signal
import subprocess
import sys
import textwrap
import time

import pytest
import quiver

PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable

# A runtime agent that serves "request" nodes: it marks one executing, works on it for `work`
# seconds (forever with slow=True), then writes its result; it is cancelled when the request is no
# longer wanted.
SERVER = textwrap.dedent("""
    import sys
    import quiver

    class Serve(quiver.Action):
        def __init__(self, agent):
            super().__init__("serve")
            self.agent = agent
            self.started = {}

        def find(self, ctx):
            g = ctx.graph
            return [quiver.Match("req@" + g.name_of(n), {"request": n}) for n in g.nodes("request")
                    if g.get(n, "state", None) is None and g.get(n, "wanted", False)]

        def holds(self, ctx, m):
            g = ctx.graph
            return g.has_node(m.at("request")) and g.get(m.at("request"), "wanted", False)

        def start(self, ctx, m):
            with ctx.graph.transaction() as t:
                t.set(m.at("request"), "state", "executing")
            self.started[m.key] = ctx.now()

        def process(self, ctx, m):
            g = ctx.graph
            if g.get(m.at("request"), "slow", False) or ctx.now() - self.started[m.key] < 0.5e9:
                return quiver.Progress.RUNNING
            return quiver.Progress.DONE

        def finish(self, ctx, m):
            n = m.at("request")
            with ctx.graph.transaction() as t:
                t.set(n, "result", ctx.graph.get(n, "n") * 2)
                t.set(n, "state", "done")
            self.agent.served += 1

        def cancel(self, ctx, m, reason):
            with ctx.graph.transaction() as t:
                t.set(m.at("request"), "state", "cancelled")
                t.set(m.at("request"), "reason", reason.name)
            ctx.log("cancelled " + m.key + ": " + reason.name)
            self.agent.cancelled += 1

    class Server(quiver.AgentBase):
        def __init__(self):
            super().__init__("py-server")
            self.served = 0
            self.cancelled = 0

        def setup(self, ctx):
            self.add_action(Serve(self), node_types=["request"], attributes=["wanted", "slow"])
            ctx.log("ready")

        def status(self):
            return {"served": self.served, "cancelled": self.cancelled}

    quiver.run_agent(Server(), domain=int(sys.argv[1]), dds_config="loopback", join_wait=0.5)
""")


def spawn(tmp_path, source, *args):
    script = tmp_path / "agent.py"
    script.write_text(source)
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in [os.path.dirname(quiver.__file__), env.get("PYTHONPATH", "")] if p)
    return subprocess.Popen([PYTHON, str(script), *map(str, args)], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def stop(proc, timeout=20):
    if proc.poll() is None:
        proc.send_signal(signal.SIGTERM)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
        pytest.fail(f"the agent process did not stop on SIGTERM:\n{err}")
    return proc.returncode, out, err


def state(observer, name):
    return observer.call(lambda g: g.get(name, "state", None) if g.find_node(name) else None)


def test_python_action_marks_processes_and_finishes(tmp_path):
    with quiver.Agent("py-observer", domain=97) as obs:
        seen = []
        obs.subscribe(lambda b: seen.append(obs.graph.get("req1", "state", None) if obs.graph.find_node("req1") else None))
        proc = spawn(tmp_path, SERVER, 97)
        try:
            assert obs.wait_until(lambda g: "py-server" in obs.peers(), timeout=20), "the server never joined"
            obs.write(lambda t: t.create_node("request", "req1", {"n": 21, "wanted": True}))
            assert obs.wait_until(lambda g: g.get("req1", "state", None) == "executing", timeout=20)
            assert obs.wait_until(lambda g: g.get("req1", "state", None) == "done", timeout=20)
            assert obs.call(lambda g: g.get("req1", "result")) == 42
            # The mark came before the result, and both came from the other process.
            assert seen.index("executing") < seen.index("done")
        finally:
            rc, out, err = stop(proc)
        assert rc == 0, err
        last = out.strip().splitlines()[-1]
        assert '"served":1' in last and '"cancelled":0' in last, last
        assert "ready" in err


def test_precondition_gone_cancels_the_action(tmp_path):
    with quiver.Agent("py-observer2", domain=98) as obs:
        proc = spawn(tmp_path, SERVER, 98)
        try:
            assert obs.wait_until(lambda g: "py-server" in obs.peers(), timeout=20), "the server never joined"
            obs.write(lambda t: t.create_node("request", "slow1", {"n": 1, "wanted": True, "slow": True}))
            assert obs.wait_until(lambda g: g.get("slow1", "state", None) == "executing", timeout=20)
            obs.write(lambda t: t.set("slow1", "wanted", False))
            assert obs.wait_until(lambda g: g.get("slow1", "state", None) == "cancelled", timeout=20)
            assert obs.call(lambda g: g.get("slow1", "reason")) == "PRECONDITION_GONE"
            assert obs.call(lambda g: g.get("slow1", "result", None)) is None
        finally:
            rc, out, err = stop(proc)
        assert rc == 0, err
        assert "cancelled req@slow1: PRECONDITION_GONE" in err
        assert '"cancelled":1' in out.strip().splitlines()[-1]


def test_exception_in_a_callback_is_raised_by_run_agent():
    class Failing(quiver.AgentBase):
        def __init__(self):
            super().__init__("py-failing")
            self.ticks = 0
            self.torn_down = False
            self.ctx = None

        def setup(self, ctx):
            self.ctx = ctx
            assert ctx.name == "py-failing" and ctx.graph.node_count >= 0

        def on_tick(self, ctx):
            self.ticks += 1
            if self.ticks == 3:
                raise ZeroDivisionError("tick three")

        def teardown(self, ctx):
            self.torn_down = True

    agent = Failing()
    t0 = time.monotonic()
    with pytest.raises(ZeroDivisionError, match="tick three"):
        quiver.run_agent(agent, domain=99, join_wait=0, run_for=30)
    assert time.monotonic() - t0 < 10, "the failure did not stop the agent"
    assert agent.ticks == 3 and agent.torn_down  # no tick after the failure; cleanup still ran
    # The context lent to callbacks is dead once run_agent() returns.
    with pytest.raises(quiver.Error, match="run_agent"):
        agent.ctx.now()
    # Python's SIGINT handler is back (run_process() had replaced it at the C level).
    with pytest.raises(KeyboardInterrupt):
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(5)


def test_timers_and_run_for_end_normally():
    class Timed(quiver.AgentBase):
        def __init__(self):
            super().__init__("py-timed")
            self.fired = []

        def setup(self, ctx):
            ctx.after(0.05, lambda: self.fired.append("after"))
            dead = ctx.after(0.05, lambda: self.fired.append("cancelled"))
            ctx.cancel(dead)
            ctx.every(0.05, lambda: self.fired.append("every"))
            self.fired.append(0 <= ctx.random() < 1 and 1 <= ctx.randint(1, 3) <= 3)

    agent = Timed()
    assert quiver.run_agent(agent, domain=99, join_wait=0, run_for=0.5) == 0
    assert agent.fired[0] is True
    assert "after" in agent.fired and agent.fired.count("every") >= 3 and "cancelled" not in agent.fired


def test_exception_exits_the_agent_process_non_zero(tmp_path):
    proc = spawn(tmp_path, textwrap.dedent("""
        import quiver
        class Broken(quiver.AgentBase):
            def setup(self, ctx):
                raise ValueError("broken setup: no camera")
        quiver.run_agent(Broken("py-broken"), domain=99, join_wait=0, run_for=30)
    """))
    try:
        out, err = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail("a failing setup() did not end the process")
    assert proc.returncode != 0
    assert "ValueError: broken setup: no camera" in err


def test_sigterm_stops_a_python_agent(tmp_path):
    proc = spawn(tmp_path, textwrap.dedent("""
        import quiver
        class Idle(quiver.AgentBase):
            def setup(self, ctx):
                ctx.log("idle and ready")
            def teardown(self, ctx):
                print("teardown ran", flush=True)
        quiver.run_agent(Idle("py-idle"), domain=99, join_wait=0)
        print("returned", flush=True)
    """))
    # Wait until it runs (its log line), then stop it.
    deadline = time.monotonic() + 20
    lines = []
    while time.monotonic() < deadline:
        line = proc.stderr.readline()
        if not line:
            break
        lines.append(line)
        if "idle and ready" in line:
            break
    assert any("idle and ready" in l for l in lines), "".join(lines)
    rc, out, err = stop(proc)
    assert rc == 0, err
    assert "teardown ran" in out and "returned" in out


def test_request_stop_ends_run_agent():
    class Stopper(quiver.AgentBase):
        def __init__(self):
            super().__init__("py-stopper")
            self.ticks = 0

        def setup(self, ctx):
            ctx.after(0.2, quiver.request_stop)

        def on_tick(self, ctx):
            self.ticks += 1

    agent = Stopper()
    start = time.monotonic()
    assert quiver.run_agent(agent, domain=99, join_wait=0, run_for=30) == 0
    assert time.monotonic() - start < 10, "request_stop() did not end the run (run_for is 30 s)"
    assert agent.ticks > 0


def test_post_and_call_run_on_the_agents_thread():
    import threading

    class Posted(quiver.AgentBase):
        def __init__(self):
            super().__init__("py-posted")
            self.seen = {}

        def setup(self, ctx):
            self.ctx = ctx
            self.agent_thread = threading.get_ident()

            def from_elsewhere():
                def write():
                    with self.ctx.graph.transaction() as t:
                        t.create_node("note", "posted")
                    self.seen["post_thread"] = threading.get_ident()

                self.post(write)
                f = self.call(lambda: (threading.get_ident(), self.ctx.graph.find_node("posted") is not None))
                self.seen["call"] = f.result(timeout=10)
                failed = self.call(lambda: 1 / 0)
                self.seen["raised"] = type(failed.exception(timeout=10)).__name__
                quiver.request_stop()

            threading.Thread(target=from_elsewhere, daemon=True).start()

    agent = Posted()
    assert quiver.run_agent(agent, domain=99, join_wait=0, run_for=30) == 0
    assert agent.seen["post_thread"] == agent.agent_thread
    assert agent.seen["call"] == (agent.agent_thread, True), "call() ran after post(), on the agent's thread"
    assert agent.seen["raised"] == "ZeroDivisionError"


def test_run_agent_takes_every_process_flag(tmp_path):
    class Writer(quiver.AgentBase):
        def __init__(self):
            super().__init__("py-stored")

        def setup(self, ctx):
            with ctx.graph.transaction() as t:
                t.create_node("note", "kept")
            ctx.after(0.3, quiver.request_stop)

    store = tmp_path / "store"
    assert quiver.run_agent(Writer(), domain=99, join_wait=0, run_for=30, store=str(store), durability="always",
                            lease=2.0, hand_over=0.0, store_compact_mb=8.0, membership="all-to-all") == 0
    assert store.is_dir() and any(store.iterdir()), "the store was written"
    for bad in ({"durability": "sometimes"}, {"membership": "star"}, {"lease": 0.0}):
        with pytest.raises(quiver.Error) as e:
            quiver.run_agent(Writer(), domain=99, join_wait=0, run_for=1, **bad)
        assert "run_agent(): " in str(e.value), str(e.value)


def test_an_agent_that_cannot_start_says_why(tmp_path):
    class Ruled(quiver.AgentBase):
        def __init__(self):
            super().__init__("py-ruled")
            self.set_grammar_file(str(tmp_path / "missing.aggl"))

        def setup(self, ctx):
            pass

    with pytest.raises(quiver.Error) as e:
        quiver.run_agent(Ruled(), domain=99, join_wait=0, run_for=1)
    assert "could not start: " in str(e.value) and "missing.aggl" in str(e.value), str(e.value)
