"""docs/dsr-api.md's Python column names only what the `quiver` module has.

Every `code span` of that column is read as a Python expression: `g.find_node(name)`,
`quiver.Agent(name, domain=0)`, `NodeChange.kind`, `batch.origin`. Its name must exist on the
module (receivers such as `g` or `tx` stand for the classes the page's abbreviations give), a call
must fit the function's parameters, and a property must not be called. A row without any name
must say why with a "—". So the table cannot rot when the bindings change.
"""
import ast
import inspect
import pathlib
import re

import pytest

import quiver

DOC = pathlib.Path(__file__).resolve().parents[2] / "docs" / "dsr-api.md"

# The page's Python abbreviations (docs/dsr-api.md, "Abbreviations (Python)").
RECEIVERS = {
    "g": "Graph",
    "tx": "Transaction",
    "agent": "Agent",
    "tree": "FrameTree",
    "reader": "FrameReader",
    "batch": "ChangeBatch",
}

CELL_SPLIT = re.compile(r"(?<!\\)\|")
CODE_SPAN = re.compile(r"`([^`]+)`")


def split_row(line):
    """The cells of a markdown table row (escaped pipes stay inside their cell, unescaped)."""
    line = line.strip()
    if line.startswith("|"):
        line = line[1:]
    if line.endswith("|") and not line.endswith("\\|"):
        line = line[:-1]
    return [c.strip().replace("\\|", "|") for c in CELL_SPLIT.split(line)]


def is_separator(line):
    cells = split_row(line)
    return bool(cells) and all(re.fullmatch(r":?-{3,}:?", c) for c in cells)


def python_column_rows(text):
    """[(label, python cell)] of the table whose header has a Python column."""
    lines = text.splitlines()
    for i, line in enumerate(lines[:-1]):
        if not line.lstrip().startswith("|") or not is_separator(lines[i + 1]):
            continue
        header = split_row(line)
        cols = [j for j, h in enumerate(header) if "python" in h.lower() and "quiver" in h.lower()]
        if not cols:
            continue
        col = cols[0]
        rows = []
        for row_line in lines[i + 2:]:
            if not row_line.lstrip().startswith("|"):
                break
            cells = split_row(row_line)
            assert len(cells) == len(header), f"{DOC.name}: row {cells[0]!r} has {len(cells)} cells, not {len(header)}"
            label = f"row {cells[0]} ({cells[1][:60]})"
            rows.append((label, cells[col]))
        return header[col], rows
    raise AssertionError(f"{DOC}: no table with a 'Quiver Python' column")


HEADER, ROWS = python_column_rows(DOC.read_text(encoding="utf-8"))


# ---- signatures of pybind11 functions, from their docstrings ----

def split_params(text):
    """Splits a parameter list at top-level commas (defaults and types may hold brackets, strings)."""
    parts, depth, quote, cur = [], 0, None, ""
    for ch in text:
        if quote:
            cur += ch
            if ch == quote:
                quote = None
            continue
        if ch in "'\"":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(cur.strip())
            cur = ""
            continue
        cur += ch
    if cur.strip():
        parts.append(cur.strip())
    return parts


def signature_from_text(params_text):
    params, kind = [], inspect.Parameter.POSITIONAL_OR_KEYWORD
    for p in split_params(params_text):
        if p == "/":
            params = [q.replace(kind=inspect.Parameter.POSITIONAL_ONLY) for q in params]
            continue
        if p == "*":
            kind = inspect.Parameter.KEYWORD_ONLY
            continue
        if p.startswith("**"):
            params.append(inspect.Parameter(p[2:].split(":")[0].strip(), inspect.Parameter.VAR_KEYWORD))
            continue
        if p.startswith("*"):
            params.append(inspect.Parameter(p[1:].split(":")[0].strip(), inspect.Parameter.VAR_POSITIONAL))
            kind = inspect.Parameter.KEYWORD_ONLY
            continue
        name = re.match(r"\s*(\w+)", p).group(1)
        has_default = "=" in p.split(":", 1)[-1] if ":" in p else "=" in p
        params.append(inspect.Parameter(name, kind, default=None if has_default else inspect.Parameter.empty))
    return inspect.Signature(params)


def signatures(fn, name):
    """Every signature of `fn` (one per pybind11 overload); None when unknown."""
    doc = getattr(fn, "__doc__", None) or ""
    found = []
    for line in doc.splitlines():
        m = re.match(r"\s*(?:\d+\.\s+)?" + re.escape(name) + r"\((.*)\)(?:\s*->.*)?$", line)
        if m and m.group(1) != "*args, **kwargs":
            found.append(signature_from_text(m.group(1)))
    if found:
        return found
    try:
        return [inspect.signature(fn)]
    except (TypeError, ValueError):
        return None


def drop_self(sig):
    params = list(sig.parameters.values())
    if params and params[0].name == "self":
        params = params[1:]
    return sig.replace(parameters=params)


# ---- checking one code span ----

def dotted(node):
    """['g', 'find_node'] for g.find_node; None for anything but names and attributes."""
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name):
        return None
    parts.append(node.id)
    return parts[::-1]


def check_span(span):
    """The problem with a code span of the Python column, or None if it names what the module has."""
    try:
        expr = ast.parse(span.strip(), mode="eval").body
    except SyntaxError as e:
        return f"`{span}` is not a Python expression ({e.msg})"
    call = expr if isinstance(expr, ast.Call) else None
    parts = dotted(call.func if call else expr)
    if not parts:
        return f"`{span}` does not name a function, class or attribute"

    head, rest = parts[0], parts[1:]
    bound = False  # reached through an instance (a receiver): `self` is implied
    if head == "quiver":
        obj, where = quiver, "quiver"
    elif head in RECEIVERS:
        if not rest:
            return f"`{span}` names only the receiver {head!r}"
        obj, where, bound = getattr(quiver, RECEIVERS[head]), f"quiver.{RECEIVERS[head]}", True
    elif head[:1].isupper() and hasattr(quiver, head):
        obj, where = getattr(quiver, head), f"quiver.{head}"
    else:
        return f"`{span}`: {head!r} is neither `quiver`, a quiver class nor one of {sorted(RECEIVERS)}"
    owner = None
    for i, part in enumerate(rest):
        owner = obj
        raw = inspect.getattr_static(obj, part, None) if isinstance(obj, type) else None
        if not hasattr(obj, part):
            return f"`{span}`: {where} has no attribute {part!r}"
        obj = raw if isinstance(raw, property) else getattr(obj, part)
        where = f"{where}.{part}"
        if isinstance(obj, property) and i < len(rest) - 1:
            return f"`{span}`: {where} is a property; its value's attributes cannot be checked here"

    if call is None:
        return None
    if isinstance(obj, property):
        return f"`{span}`: {where} is a property, not a method: write it without a call"
    if any(isinstance(a, ast.Starred) for a in call.args) or any(k.arg is None for k in call.keywords) or any(
            isinstance(a, ast.Constant) and a.value is Ellipsis for a in call.args):
        return None  # `f(...)`, `f(*xs)`: no shape to check
    if isinstance(obj, type):
        sigs, bound = signatures(obj.__init__, "__init__"), True
    else:
        sigs = signatures(obj, (rest or [head])[-1])
        bound = bound or (owner is not None and not isinstance(owner, type))
    if sigs is None:
        return None
    if bound:
        sigs = [drop_self(s) for s in sigs]
    args = [None] * len(call.args)
    kwargs = {k.arg: None for k in call.keywords}
    errors = []
    for sig in sigs:
        try:
            sig.bind(*args, **kwargs)
            return None
        except TypeError as e:
            errors.append(f"{sig}: {e}")
    return f"`{span}` does not fit {where}" + "".join(f"\n    {e}" for e in errors)


def test_the_table_has_a_python_column():
    assert "python" in HEADER.lower()
    assert len(ROWS) >= 30, f"only {len(ROWS)} rows parsed from {DOC}"
    numbers = [int(label.split()[1]) for label, _ in ROWS]
    assert numbers == list(range(1, len(ROWS) + 1)), f"row numbers are not 1..n: {numbers}"
    assert sum(len(CODE_SPAN.findall(cell)) for _, cell in ROWS) >= 50


@pytest.mark.parametrize("label,cell", ROWS, ids=[label.split(" (")[0].replace(" ", "-") for label, _ in ROWS])
def test_python_names_exist(label, cell):
    spans = CODE_SPAN.findall(cell)
    if not spans:
        assert cell.startswith("—"), f"{label}: the Python cell names nothing and does not say why with '—': {cell!r}"
        return
    problems = [p for p in map(check_span, spans) if p]
    assert not problems, f"{DOC.name} {label}, Python column:\n  " + "\n  ".join(problems)


@pytest.mark.parametrize("span", [
    "g.no_such_method(x)",          # missing method
    "quiver.no_such_function()",    # missing module-level name
    "NoSuchClass.attr",             # missing class
    "Graph.no_such_attr",           # missing attribute of a class
    "tx.set_rt(a, b, X, stamp)",    # stamp is keyword-only
    "g.find_node()",                # a required argument left out
    "g.find_node(name, nonsense=1)",  # an unknown keyword
    "agent.id()",                   # a property called
    "rep.spin_for(ns)",             # an unknown receiver
    "tx.set(id, from, value)",      # not Python
])
def test_the_check_rejects(span):
    assert check_span(span) is not None


@pytest.mark.parametrize("span", [
    "g.find_node(name)", "quiver.Agent(name, domain=0)", "NodeChange.kind", "batch.origin",
    "tx.set_rt(parent, child, translation=t, rotation=q, stamp=s)", "quiver.pose_matrix(t)",
    "quiver.Value(\"int32\", 4)", "agent.call(fn, x, y)", "quiver.Graph.has_edge",
])
def test_the_check_accepts(span):
    assert check_span(span) is None
