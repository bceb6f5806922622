#!/usr/bin/env bash
# The DDS part of the demo: real agent processes on the embedded loopback configuration.
# Five agents change the graph at once; one is killed with SIGKILL mid-run and restarted (new
# incarnation); then an observer (`quiver dump`) joins late and every replica must hold the
# same digest.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/quiver
domain="${QUIVER_DEMO_DOMAIN:-21}"
tmp=$(mktemp -d)
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; rm -rf "$tmp"; }
trap cleanup EXIT

start() {  # name seed
  "$bin" agent --name "$1" --domain "$domain" --churn-hz 40 --churn-for 4 --seed "$2" --status-ms 250 \
    >"$tmp/$1.out" 2>"$tmp/$1.err" &
  pids+=($!)
  echo "  started agent $1 (pid $!)"
}

echo "== 5 agent processes on DDS domain $domain (127.0.0.1 only, multicast off), writing at once"
for i in 0 1 2 3 4; do start "agent$i" "$((10 + i))"; done
sleep 1.5
victim=${pids[2]}
echo "== kill -9 agent2 (pid $victim) in the middle of its writes"
kill -9 "$victim"
wait "$victim" 2>/dev/null || true
sleep 1.5
start agent2 99
echo "== waiting for the writes to stop and the replicas to converge"
sleep 5
field() { grep -o "\"$2\":[^,}]*" <<<"$1" | head -n1 | cut -d: -f2- | tr -d '"'; }
digests=$(for i in 0 1 2 3 4; do field "$(tail -n1 "$tmp/agent$i.out")" digest; done | sort -u)
observer=$("$bin" dump --digest --domain "$domain" --timeout 20)
for i in 0 1 2 3 4; do
  line=$(tail -n1 "$tmp/agent$i.out")
  echo "  agent$i: replica $(field "$line" replica), $(field "$line" nodes) nodes, digest $(field "$line" digest)"
done
echo "  late observer (quiver dump): digest $observer"
grep -h "left:" "$tmp"/agent0.err | head -2 | sed 's/^/  /' || true
if [ "$(echo "$digests" | wc -l)" = 1 ] && [ "$digests" = "$observer" ]; then
  echo "== converged: every replica and the late observer hold digest $observer"
else
  echo "== NOT converged" >&2
  exit 1
fi
