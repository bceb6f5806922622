#!/bin/sh
# quiver import-dsr / import-agm / export-dsr / export-agm from the command line: files in and
# out, warnings and --strict, a file handed to the wrong command, option mistakes.
#   cli_test.sh QUIVER FIXTURES_DIR
set -eu
q=$1
fx=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAILED: $*" >&2; exit 1; }

# A CORTEX world to a world file, then back to CORTEX and to AGM, and in again.
out=$($q import-dsr "$fx/dsr/current_layout.json" -o "$tmp/w.json" 2>&1) || fail "import-dsr: $out"
echo "$out" | grep -q "5 nodes, 3 edges, 4 RT edges written to '$tmp/w.json'" || fail "import-dsr says what it wrote: $out"
$q lookup "$tmp/w.json" world hand --json | grep -q '"translation"' || fail "the imported world is a world file"
$q export-dsr "$tmp/w.json" -o "$tmp/back.json" 2>/dev/null || fail "export-dsr"
$q import-dsr "$tmp/back.json" -o "$tmp/w2.json" --strict 2>/dev/null || fail "import-dsr of an exported file"
$q export-agm "$tmp/w.json" -o "$tmp/back.xml" 2>"$tmp/err" || fail "export-agm: $(cat "$tmp/err")"
grep -q "warning:" "$tmp/err" || fail "export-agm warns about values AGM's strings cannot give back"
$q import-agm "$tmp/back.xml" -o "$tmp/w3.json" 2>/dev/null || fail "import-agm of an exported file"
$q import-agm "$fx/agm/world.xml" -o "$tmp/a.json" --units mm 2>/dev/null || fail "import-agm"

# Warnings, and --strict.
out=$($q import-dsr "$fx/dsr/cortex_quirks.json" -o "$tmp/q.json" 2>&1) || fail "quirks import: $out"
echo "$out" | grep -q "warning: .*no symbol with id 999: the link 'has' is skipped" || fail "warnings are logged: $out"
if out=$($q import-dsr "$fx/dsr/cortex_quirks.json" -o "$tmp/q.json" --strict 2>&1); then fail "--strict refuses"; fi
echo "$out" | grep -q "refused: strict import" || fail "--strict says why: $out"

# Malformed files and files for another command.
if out=$($q import-agm "$fx/malformed/agm_missing_symbol.xml" -o "$tmp/x.json" 2>&1); then fail "a malformed file"; fi
echo "$out" | grep -q 'agm_missing_symbol.xml:5: <link src="7" dst="99" label="sees">: no symbol with id 99' || fail "$out"
if out=$($q import-agm "$fx/dsr/current_layout.json" -o "$tmp/x.json" 2>&1); then fail "DSR to import-agm"; fi
echo "$out" | grep -q 'this is a CORTEX DSR JSON world ("DSRModel"); use quiver import-dsr' || fail "$out"
if out=$($q import-dsr "$fx/agm/world.xml" -o "$tmp/x.json" 2>&1); then fail "AGM to import-dsr"; fi
echo "$out" | grep -q "this is an AGM XML world (root <AGMModel>); use quiver import-agm" || fail "$out"
if out=$($q import-dsr "$tmp/w.json" -o "$tmp/x.json" 2>&1); then fail "a Quiver world to import-dsr"; fi
echo "$out" | grep -q "this is a Quiver world file" || fail "$out"
if out=$($q export-agm "$fx/dsr/current_layout.json" -o "$tmp/x.xml" 2>&1); then fail "DSR to export-agm"; fi
echo "$out" | grep -q "is a CORTEX DSR JSON world, not a Quiver world file; import it first (quiver import-dsr)" || fail "$out"
[ ! -e "$tmp/x.json" ] || fail "nothing is written for a refused file"

# Options.
if out=$($q import-dsr "$fx/dsr/current_layout.json" 2>&1); then fail "no output"; fi
echo "$out" | grep -q "give either -o WORLD.json or --domain D" || fail "$out"
if out=$($q import-dsr "$fx/dsr/current_layout.json" -o "$tmp/x.json" --domain 3 2>&1); then fail "two outputs"; fi
echo "$out" | grep -q "give either -o WORLD.json or --domain D" || fail "$out"
if $q import-agm "$fx/agm/world.xml" -o "$tmp/x.json" --units cm 2>/dev/null; then fail "--units cm is refused"; fi
# --domain joins a running graph (on loopback; ctest runs in a namespace of its own): with nobody
# there it says so.
out=$($q import-dsr "$fx/dsr/current_layout.json" --domain 197 --timeout 0.3 2>&1) || true
echo "$out" | grep -q "no agent answered on DDS domain 197" || fail "--domain with no agent: $out"
echo "interop cli: ok"
