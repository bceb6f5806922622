import pytest
import quiver
from conftest import GRAMMAR


def test_grammar_parses_and_names_its_rules():
    g = quiver.Grammar.parse(GRAMMAR, "test.aggl")
    assert g.name == "test" and g.rules == ["changeRoom"]
    with pytest.raises(ValueError, match="test.aggl:1"):
        quiver.Grammar.parse("grammer x", "test.aggl")


def test_guard_allows_a_rule_and_refuses_anything_else(world):
    guard = quiver.GrammarGuard(world, quiver.Grammar.parse(GRAMMAR), "tester")
    guard.install()
    # One application of changeRoom: the robot goes from the kitchen to the hallway.
    with world.transaction() as t:
        t.delete_edge("robot", "kitchen", "in")
        t.insert_edge("robot", "hallway", "in")
    assert world.has_edge("robot", "hallway", "in")
    # Attributes are free.
    with world.transaction() as t:
        t.set("robot", "battery", 0.5)
    # Teleporting without a transitable edge is no rule of the grammar: refused, nothing applied.
    before = world.digest()
    t = world.transaction()
    t.delete_edge("robot", "hallway", "in")
    t.insert_edge("robot", "kitchen", "in")
    with pytest.raises(quiver.RefusedError, match="changeRoom"):
        t.commit()
    assert world.digest() == before
    assert world.has_edge("robot", "hallway", "in")
