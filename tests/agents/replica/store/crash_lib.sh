# Shared by the store's crash tests (sourced): agent processes with stores, their cleanup, and the
# counts they print. The caller sets QUIVER, SEED, WORK and DOMAIN first.
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null; done
  [ -n "${QUIVER_KEEP:-}" ] && echo "kept $WORK" || rm -rf "$WORK"
}
trap cleanup EXIT
fail() {
  echo "FAIL (seed $SEED): $*"
  for f in "$WORK"/*.log; do echo "--- $f"; grep -v '^acked' "$f" | tail -4 | cut -c1-400; done
  exit 1
}

# start NAME STORE DURABILITY LOG [extra args]: starts an agent in the background; sets $started.
start() {
  local name=$1 store=$2 durability=$3 log=$4
  shift 4
  "$QUIVER" --log-level info agent --name "$name" --domain "$DOMAIN" --store "$store" --durability "$durability" \
    --store-compact-mb 0.01 "$@" >>"$log" 2>&1 &
  started=$!
  pids+=("$started")
}

last_acked() { grep -o '^acked [0-9]*' "$1" | tail -1 | cut -d' ' -f2; }
last_loaded() { grep -o '^loaded [0-9]*' "$1" | tail -1 | cut -d' ' -f2; }
