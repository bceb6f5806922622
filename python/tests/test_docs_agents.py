"""docs/agents.md shows the tutorial's agent twice, in C++ and in Python ("A complete agent"):
each block is the code of its file, examples/tutorial/greeter.cc and greeter.py, compared without
comment lines (and the Python file's docstring) and blank lines. An edit to one side only fails
here."""
import ast
import re

from conftest import ROOT

PAGE = ROOT / "docs" / "agents.md"
TUTORIAL = ROOT / "examples" / "tutorial"


def page_block(language, marker):
    """The page's ```language block that holds `marker`."""
    blocks = re.findall(r"^```" + language + r"\n(.*?)^```$", PAGE.read_text(), re.S | re.M)
    found = [b for b in blocks if marker in b]
    assert len(found) == 1, f"docs/agents.md: {len(found)} ```{language} blocks hold {marker!r}"
    return found[0]


def code_lines(text, comment):
    return [line.rstrip() for line in text.splitlines() if line.strip() and not line.lstrip().startswith(comment)]


def without_docstring(source):
    body = ast.parse(source).body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
            and isinstance(body[0].value.value, str):
        return "\n".join(source.splitlines()[body[0].end_lineno:])
    return source


def test_the_cpp_block_is_greeter_cc():
    file = code_lines((TUTORIAL / "greeter.cc").read_text(), "//")
    page = code_lines(page_block("cpp", "class Greeter"), "//")
    assert page == file, "docs/agents.md's C++ agent differs from examples/tutorial/greeter.cc"


def test_the_python_block_is_greeter_py():
    file = code_lines(without_docstring((TUTORIAL / "greeter.py").read_text()), "#")
    page = code_lines(without_docstring(page_block("python", "class Greeter")), "#")
    assert page == file, "docs/agents.md's Python agent differs from examples/tutorial/greeter.py"
