#!/bin/sh
# The simulator knows no app (issue 21): nothing under sim/ includes a header of agents/apps/ or
# links one of its targets. Fails naming each offending line.
src=${1:?usage: sim_knows_no_app.sh SOURCE_DIR}
[ -d "$src/sim" ] || { echo "no $src/sim"; exit 2; }
bad=0
if grep -rn '#include *[<"]quiver/agents/apps/' "$src/sim"; then
  echo "FAILED: sim/ includes an app's header (above)"
  bad=1
fi
if grep -n -E 'quiver(_|::)(barthel|agm|planning)|agents/apps' "$src/sim/CMakeLists.txt"; then
  echo "FAILED: sim/CMakeLists.txt names an app's target or folder (above)"
  bad=1
fi
n=$(find "$src/sim" -name '*.cc' -o -name '*.h' | wc -l)
[ "$n" -gt 0 ] || { echo "FAILED: no sources found under $src/sim"; exit 1; }
[ $bad -eq 0 ] && echo "sim/: $n sources, none includes or links an app"
exit $bad
