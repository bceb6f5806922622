"""Agents whose code blocks (a speech synthesizer, a planner, a camera). A Python action whose
process() sleeps 3 s must keep its agent alive for its peers (never absent from their peers()),
keep its priority lock, and make its host warn once, naming the agent and the action. The same work
done as a job (ctx.run_job) keeps the agent's own loop going, with no warning at all."""
import os
import signal
import subprocess
import sys
import textwrap
import time

import quiver

PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable

# The agent both scripts run: its action Say (defined by each script) on every utterance.
SPEECH_AGENT = textwrap.dedent("""
    class Speech(quiver.AgentBase):
        def __init__(self):
            super().__init__("speech")

        def setup(self, ctx):
            self.add_action(Say(), node_types=["utterance"])

    quiver.run_agent(Speech(), domain=int(sys.argv[1]), dds_config="loopback", join_wait=0.5)
""")


def start_speech(tmp_path, text, domain):
    """Runs the script `text` as the speech agent's process on `domain`; stdout, stderr piped."""
    script = tmp_path / "speech.py"
    script.write_text(text)
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in [os.path.dirname(quiver.__file__), env.get("PYTHONPATH", "")] if p)
    return subprocess.Popen([PYTHON, str(script), str(domain)], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)

SPEECH = textwrap.dedent("""
    import sys, time
    import quiver

    class Say(quiver.Action):
        def __init__(self):
            super().__init__("say")

        def find(self, ctx):
            g = ctx.graph
            return [quiver.Match("say@" + g.name_of(n), {"utterance": n}) for n in g.nodes("utterance")
                    if g.get(n, "state", None) is None]

        def holds(self, ctx, m):
            return ctx.graph.has_node(m.at("utterance"))

        def lock(self, ctx, m):
            return (ctx.graph.find_node("person"), 2)

        def start(self, ctx, m):
            with ctx.graph.transaction() as t:
                t.set(m.at("utterance"), "state", "speaking")

        def process(self, ctx, m):
            time.sleep(3.0)  # synthesis and playback, blocking
            return quiver.Progress.DONE

        def finish(self, ctx, m):
            with ctx.graph.transaction() as t:
                t.set(m.at("utterance"), "state", "spoken")

        def cancel(self, ctx, m, reason):
            ctx.log("cancelled: " + reason.name)

""") + SPEECH_AGENT


def test_a_blocking_process_keeps_its_agent_alive_and_its_lock(tmp_path):
    domain = 121
    with quiver.Agent("watcher", domain=domain) as obs:
        obs.write(lambda t: t.create_node("person", "person"))
        proc = start_speech(tmp_path, SPEECH, domain)
        try:
            assert obs.wait_until(lambda g: "speech" in obs.peers(), timeout=20), "speech never joined"
            time.sleep(0.5)
            obs.write(lambda t: t.create_node("utterance", "u1"))
            if not obs.wait_until(lambda g: g.get("u1", "state", None) == "speaking", timeout=20):
                proc.send_signal(signal.SIGTERM)
                raise AssertionError(proc.communicate(timeout=20)[1][-3000:])
            # While process() sleeps: sample who the watcher hears and who holds the person's lock.
            absent, not_locked, samples = 0, 0, 0
            end = time.monotonic() + 2.6
            while time.monotonic() < end:
                samples += 1
                if "speech" not in obs.peers():
                    absent += 1
                if not obs.locked_by_other(obs.call(lambda g: g.find_node("person"))):
                    not_locked += 1
                time.sleep(0.02)
            assert obs.wait_until(lambda g: g.get("u1", "state", None) == "spoken", timeout=20)
            print(f"[blocking] {samples} samples over 2.6 s of a 3 s process(): speech absent in {absent}, "
                  f"person not locked in {not_locked}")
        finally:
            if proc.poll() is None:
                proc.send_signal(signal.SIGTERM)
            out, err = proc.communicate(timeout=30)
        warnings = [l for l in err.splitlines() if "hung" in l or "blocked" in l or "has not returned" in l]
        print("[blocking] speech's warnings:", warnings)
        assert absent == 0, f"the watcher lost speech in {absent} of {samples} samples"
        assert not_locked == 0, f"the person's lock was not held in {not_locked} of {samples} samples"
        assert len(warnings) == 1 and "speech" in warnings[0] and "say" in warnings[0], err[-3000:]


SPEECH_WITH_A_JOB = textwrap.dedent("""
    import sys, time
    import quiver

    class Say(quiver.Action):
        def __init__(self):
            super().__init__("say")
            self.done = set()

        def find(self, ctx):
            g = ctx.graph
            return [quiver.Match("say@" + g.name_of(n), {"utterance": n}) for n in g.nodes("utterance")
                    if g.get(n, "state", None) is None]

        def holds(self, ctx, m):
            return ctx.graph.has_node(m.at("utterance"))

        def start(self, ctx, m):
            with ctx.graph.transaction() as t:
                t.set(m.at("utterance"), "state", "speaking")
            def finished(seconds):
                self.done.add(m.key)
                ctx.log("spoken for %.1f s" % seconds)
            def speak():
                t0 = time.monotonic()
                time.sleep(3.0)  # synthesis and playback, off the agent's thread
                return time.monotonic() - t0
            ctx.run_job(speak, finished)

        def process(self, ctx, m):
            # The loop goes on while the job runs: count the turns.
            with ctx.graph.transaction() as t:
                t.set(m.at("utterance"), "turns", ctx.graph.get(m.at("utterance"), "turns", 0) + 1)
            return quiver.Progress.DONE if m.key in self.done else quiver.Progress.RUNNING

        def finish(self, ctx, m):
            with ctx.graph.transaction() as t:
                t.set(m.at("utterance"), "state", "spoken")

        def cancel(self, ctx, m, reason):
            pass

""") + SPEECH_AGENT


def test_work_in_a_job_leaves_the_agents_loop_running(tmp_path):
    domain = 122
    with quiver.Agent("watcher", domain=domain) as obs:
        proc = start_speech(tmp_path, SPEECH_WITH_A_JOB, domain)
        try:
            assert obs.wait_until(lambda g: "speech" in obs.peers(), timeout=20), "speech never joined"
            time.sleep(0.5)
            obs.write(lambda t: t.create_node("utterance", "u1"))
            if not obs.wait_until(lambda g: g.get("u1", "state", None) == "spoken", timeout=20):
                proc.send_signal(signal.SIGTERM)
                raise AssertionError(proc.communicate(timeout=20)[1][-3000:])
            turns = obs.call(lambda g: g.get("u1", "turns", 0))
        finally:
            if proc.poll() is None:
                proc.send_signal(signal.SIGTERM)
            out, err = proc.communicate(timeout=30)
        print(f"[job] process() ran {turns} turns while the 3 s job ran")
        assert "spoken for 3." in err, err[-3000:]
        assert turns >= 100, f"the agent's loop ran only {turns} turns in 3 s"
        assert "has not returned" not in err, err[-3000:]
