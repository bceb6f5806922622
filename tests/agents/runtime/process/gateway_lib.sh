#!/usr/bin/env bash
# Shared by the gateway tests (sourced): robots as network namespaces (scripts/netns.sh), a
# work directory, the team file, and reading the JSON status lines the processes print.
# The caller sets QUIVER first; `team_up ROBOT...` builds the namespaces and $WORK/team.json.
. "$(dirname "${BASH_SOURCE[0]}")/../../../../scripts/netns.sh"
netns_require
WORK=$(mktemp -d)
trap 'netns_cleanup; [ -n "${QUIVER_KEEP:-}" ] && echo "kept $WORK" || rm -rf "$WORK"' EXIT
team_up() {  # ROBOT...: their namespaces, and a team file listing them (team domain 7)
  netns_up "$@" || { echo "FAIL: could not build the namespaces"; exit 1; }
  netns_team_file "$WORK/team.json" "$@"
}
fail() {
  echo "FAIL: $*"
  for f in "$WORK"/*.log; do echo "--- $f"; grep -v '^{' "$f" | tail -8 | cut -c1-300; last_of "$f" | cut -c1-400; done
  exit 1
}
last_of() { grep '^{' "$1" | tail -1; }
field() { last_of "$WORK/$1.log" | grep -o "\"$2\":[^,}]*" | head -1 | cut -d: -f2 | tr -d '"'; }  # NAME KEY
wait_until() {  # TIMEOUT_S CMD...: polls every 100 ms
  local i; for ((i = 0; i < $1 * 10; ++i)); do "${@:2}" 2>/dev/null && return 0; sleep 0.1; done; return 1
}
writer() {  # ROBOT NAME: changes for 2 s, hands over and exits; sets $started
  netns_run "$1" "$WORK/$2.log" "$QUIVER" agent --name "$2" --domain 0 --churn-hz 20 --churn-for 2 \
    --run-for 3 --status-ms 100
}
