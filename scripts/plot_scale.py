#!/usr/bin/python3
"""Draws `quiver bench scale` JSON lines as log-log curves (PNG and SVG): bytes and messages per
op per agent, and idle bytes per second per agent, against the number of agents, one curve per
input file (e.g. today's protocol and a new one, side by side).

    build/quiver bench scale > scale.jsonl
    scripts/plot_scale.py scale.jsonl [LABEL=other.jsonl ...] -o docs/scale   # docs/scale.png, .svg
"""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_lines(path):
    rows = []
    with (sys.stdin if path == "-" else open(path)) as f:
        for k, line in enumerate(f, 1):
            line = line.strip()
            if not line.startswith("{"):
                continue
            try:
                j = json.loads(line)
            except json.JSONDecodeError as e:
                sys.exit(f"plot_scale: {path}:{k}: not JSON: {e}")
            if j.get("bench") == "scale":
                rows.append(j)
    if not rows:
        sys.exit(f"plot_scale: {path}: no `quiver bench scale` lines")
    return sorted(rows, key=lambda j: j["agents"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("inputs", nargs="+", help="FILE or LABEL=FILE (- for stdin)")
    ap.add_argument("-o", "--out", required=True, help="output path without extension")
    a = ap.parse_args()
    panels = [("bytes_per_op_per_agent", "bytes per op per agent"),
              ("messages_per_op_per_agent", "messages per op per agent"),
              ("idle_bytes_per_s_per_agent", "idle bytes per second per agent")]
    fig, axes = plt.subplots(1, len(panels), figsize=(16, 4.5))
    for spec in a.inputs:
        label, _, path = spec.rpartition("=")
        rows = read_lines(path)
        label = label or path
        for ax, (key, _) in zip(axes, panels):
            points = [(r["agents"], r[key]) for r in rows if r.get(key, 0) > 0]
            if points:
                ax.plot([p[0] for p in points], [p[1] for p in points], "o-", label=label)
    axes[2].axhline(1000, ls="--", color="grey", label="target (issue 22): 1 KB/s")
    for ax, (_, what) in zip(axes, panels):
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xlabel("agents")
        ax.set_ylabel(what)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle("quiver bench scale (simulator: the samples DDS would carry)")
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(f"{a.out}.{ext}")
        print(f"{a.out}.{ext}")


if __name__ == "__main__":
    main()
