#!/bin/sh
# quiver schema infer writes a starting schema from a world and grammars that then admits them;
# quiver schema check and quiver grammar check --schema name what a narrower schema refuses (a
# world's node type, a grammar rule's edge label, a mission's node type), and a malformed schema
# file is refused naming the entry. No network.
# Usage: schema_cli_test.sh QUIVER SOURCE_DIR
set -u
q=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAILED: $*"; exit 1; }
world=$src/agents/apps/agm/world/clean-table.json
"$q" schema infer "$world" "$src"/agents/apps/agm/grammars/*.aggl -o "$work/vocab.json" >"$work/out" 2>&1 ||
  fail "infer: $(cat "$work/out")"
grep -q "node types" "$work/out" || fail "infer printed no summary: $(cat "$work/out")"
grep -q '"quiver_schema": 1' "$work/vocab.json" || fail "no schema written"
grep -q '"mug"' "$work/vocab.json" || fail "the world's mug type is missing from the inferred schema"
"$q" schema check "$work/vocab.json" "$world" "$src"/agents/apps/agm/grammars/*.aggl >"$work/check" 2>&1 ||
  fail "the inferred schema does not admit what it was inferred from: $(cat "$work/check")"
[ "$(grep -c ': ok$' "$work/check")" -ge 2 ] || fail "check printed no ok lines: $(cat "$work/check")"

# A narrower schema: no mugs, and only an 'in' edge.
python3 - "$work/vocab.json" "$work/narrow.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["node_types"] = {k: v for k, v in s["node_types"].items() if k != "mug" and v.get("is") != "mug"}
for t in list(s["node_types"]):
    if s["node_types"][t].get("is") == "mug":
        del s["node_types"][t]
s["edge_types"] = {"in": {}, "RT": {}}
s["attributes"] = {k: {"type": "any"} for k in s["attributes"]}
json.dump(s, open(sys.argv[2], "w"))
PY
"$q" schema check "$work/narrow.json" "$world" >"$work/narrow_world" 2>&1 && fail "a world with mugs passed a schema without them"
grep -q "declares no node type 'mug'" "$work/narrow_world" || fail "the refusal does not name the mug: $(cat "$work/narrow_world")"
grammar=$src/agents/apps/agm/grammars/grasping.aggl
"$q" grammar check --schema "$work/narrow.json" "$grammar" >"$work/narrow_grammar" 2>&1 && fail "a grammar with undeclared edges passed"
grep -q "rule '.*' (.*grasping.aggl:[0-9]*): the edge type '.*' (.*) is not in the schema" "$work/narrow_grammar" ||
  fail "the grammar error does not name the rule, file, line and edge: $(cat "$work/narrow_grammar")"
printf '{\n  m:mug\n  t:room\n  m->t(in)\n}\n' >"$work/m.aggt"
"$q" schema check "$work/narrow.json" "$work/m.aggt" >"$work/narrow_mission" 2>&1 && fail "a mission with a mug passed"
grep -q "mission: the node type 'mug' (variable m) is not in the schema" "$work/narrow_mission" ||
  fail "the mission error does not name the type: $(cat "$work/narrow_mission")"
# quiver mission check and quiver plan take the schema too: exit 2, naming what it lacks.
"$q" mission check "$world" "$work/m.aggt" --schema "$work/narrow.json" >"$work/mc" 2>&1
[ $? = 2 ] || fail "mission check --schema did not exit 2: $(cat "$work/mc")"
grep -q "does not declare what the mission or the grammar uses" "$work/mc" && grep -q "node type 'mug' (variable m)" "$work/mc" ||
  fail "mission check --schema: $(cat "$work/mc")"
"$q" plan "$grammar" "$world" "$work/m.aggt" --schema "$work/narrow.json" >"$work/pl" 2>&1
[ $? = 2 ] || fail "plan --schema did not exit 2: $(cat "$work/pl")"
grep -q "grasping.aggl:[0-9]*): the edge type" "$work/pl" || fail "plan --schema does not name the grammar's rule: $(cat "$work/pl")"
# AGM's XML targets too (--mission: a file name cannot tell a target from an AGM world).
printf '<AGMModel>\n<symbol id="tazaR" type="mug"/>\n<symbol id="5" type="room"/>\n<link src="tazaR" dst="5" label="in"/>\n</AGMModel>\n' >"$work/target.xml"
"$q" schema check "$work/narrow.json" --mission "$work/target.xml" >"$work/narrow_xml" 2>&1 && fail "an XML target with a mug passed"
grep -q "target.xml: error: mission: the node type 'mug' (variable tazaR) is not in the schema" "$work/narrow_xml" ||
  fail "the XML target's error does not name the type: $(cat "$work/narrow_xml")"

# The importers take it too: a CORTEX world imported under a schema that lacks its types is refused.
dsr=$src/tests/graph/interop/fixtures/dsr/current_layout.json
"$q" schema infer "$dsr" -o "$work/dsr_vocab.json" >/dev/null 2>&1 || fail "infer from a DSR world"
"$q" import-dsr "$dsr" -o "$work/dsr.json" --schema "$work/dsr_vocab.json" >"$work/imp1" 2>&1 ||
  fail "a DSR world refused by the schema inferred from it: $(cat "$work/imp1")"
printf '{"quiver_schema": 1, "node_types": {"world": {}}}' >"$work/tiny.json"
"$q" import-dsr "$dsr" -o "$work/dsr2.json" --schema "$work/tiny.json" >"$work/imp2" 2>&1 && fail "import-dsr ignored --schema"
grep -q "the schema .*tiny.json declares no" "$work/imp2" || fail "import-dsr's refusal: $(cat "$work/imp2")"
[ ! -e "$work/dsr2.json" ] || fail "a refused import wrote a world"

# A malformed schema file is refused naming the entry.
printf '{"quiver_schema": 1, "attributes": {"x": {"type": "float128"}}}' >"$work/bad.json"
"$q" schema check "$work/bad.json" "$world" >"$work/bad" 2>&1 && fail "a bad schema was accepted"
grep -q "bad.json: attribute 'x': unknown value type 'float128'" "$work/bad" || fail "bad schema message: $(cat "$work/bad")"
"$q" agent --name x --schema "$work/bad.json" --run-for 1 >"$work/agent" 2>&1 && fail "an agent started with a bad schema"
grep -q "schema" "$work/agent" || fail "the agent's error does not name the schema: $(cat "$work/agent")"
echo "schema CLI: ok"
