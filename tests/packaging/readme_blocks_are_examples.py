#!/usr/bin/env python3
"""Every ```cpp block of README.md is, verbatim, one whole file under examples/ (which CI builds
against the installed package), so the README's code compiles as written.

usage: readme_blocks_are_examples.py SOURCE_DIR
"""
import pathlib
import re
import sys


def main() -> int:
    src = pathlib.Path(sys.argv[1])
    readme = (src / "README.md").read_text()
    blocks = re.findall(r"^```cpp\n(.*?)^```$", readme, flags=re.S | re.M)
    examples = {p: p.read_text() for p in sorted((src / "examples").rglob("*.cc"))}
    if not blocks:
        print("README.md has no ```cpp block")
        return 1
    failed = 0
    for n, block in enumerate(blocks, 1):
        match = [p for p, text in examples.items() if text == block]
        first = block.splitlines()[0] if block else ""
        if match:
            print(f"ok   block {n} is {match[0].relative_to(src)}")
        else:
            failed += 1
            print(f"FAIL block {n} ({first!r}) is not the whole of any examples/**/*.cc")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
