"""The hand-written stubs (python/quiver.pyi) name every public name of the module and every
public member of its classes."""
import ast
import os
import pathlib

import quiver

PYI = pathlib.Path(os.environ.get("QUIVER_PYI", pathlib.Path(__file__).resolve().parents[1] / "quiver.pyi"))


def stub_names():
    tree = ast.parse(PYI.read_text())
    top, members = set(), {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            top.add(node.name)
            members[node.name] = {n.name for n in node.body if isinstance(n, (ast.FunctionDef, ast.AnnAssign))
                                  and hasattr(n, "name")} | {n.target.id for n in node.body
                                                             if isinstance(n, ast.AnnAssign)}
        elif isinstance(node, ast.FunctionDef):
            top.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            top.add(node.target.id)
    return top, members


def test_every_public_name_is_in_the_stub():
    top, members = stub_names()
    public = {n for n in dir(quiver) if not n.startswith("_")}
    assert public - top == set()
    for name in public:
        obj = getattr(quiver, name)
        if isinstance(obj, type) and name in members and not issubclass(obj, BaseException):
            missing = {m for m in vars(obj) if not m.startswith("_")} - members[name]
            assert missing == set(), f"{name}: {missing}"
