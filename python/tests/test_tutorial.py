"""The tutorial of docs/agents.md in Python, run as a newcomer would: examples/tutorial/greeter.py
beside `quiver agent --name speech`, both seeding the kitchen world; the person ends greeted and
the greeter hears speech."""
import os
import subprocess
import sys

from conftest import ROOT

PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable


def test_the_python_greeter_greets_beside_speech(quiver_bin):
    import quiver
    world = str(ROOT / "examples" / "worlds" / "kitchen.json")
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in [os.path.dirname(quiver.__file__), env.get("PYTHONPATH", "")] if p)
    speech = subprocess.Popen([quiver_bin, "agent", "--name", "speech", "--world", world, "--domain", "191",
                               "--run-for", "15"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        greeter = subprocess.run([PYTHON, str(ROOT / "examples" / "tutorial" / "greeter.py"), "--world", world,
                                  "--domain", "191", "--text", "Good morning", "--run-for", "6", "--status-ms", "500"],
                                 env=env, capture_output=True, text=True, timeout=60)
        assert greeter.returncode == 0, greeter.stderr
        last = [l for l in greeter.stdout.splitlines() if l.startswith("{")][-1]
        assert '"actions_finished":1' in last and '"person_changes":' in last, last
        assert "speech is here" in greeter.stderr, greeter.stderr
        dump = subprocess.run([quiver_bin, "dump", "--domain", "191", "--json", "--timeout", "10"],
                              capture_output=True, text=True, timeout=30)
        assert '"greeting": "Good morning"' in dump.stdout.replace('":"', '": "'), dump.stdout[-500:]
    finally:
        speech.kill()
        speech.wait()
