#!/bin/sh
# quiver render and quiver timeline from the command line: world files, recordings (the sample
# recording of tests/agents/view/render/sample_world.h, made by make_sample_recording), a live domain, and
# the messages of every error, each naming the file. DDS only on loopback (ctest runs in a
# network namespace of its own).
# usage: render_cli_test.sh QUIVER MAKE_SAMPLE_RECORDING SOURCE_DIR
set -eu
q=$1
make_recording=$2
src=$3
fail() { echo "FAILED: $*" >&2; exit 1; }
dir=$(mktemp -d "${TMPDIR:-/tmp}/quiver_render_cli.XXXXXX")
agent_pid=""
cleanup() {
  if [ -n "$agent_pid" ]; then kill "$agent_pid" 2>/dev/null || true; fi
  rm -rf "$dir"
}
trap cleanup EXIT
cd "$dir"
"$make_recording" run.qrec world.json || fail "make_sample_recording"

# A world file, in each format.
out=$($q render world.json -o w.svg 2>&1) || fail "render world.json: $out"
echo "$out" | grep -q "wrote w.svg: 7 nodes, 6 edges, dot layout" || fail "render's report: $out"
for n in world kitchen robot camera mug table note; do
  grep -q ">$n</text>" w.svg || fail "w.svg lacks node $n"
done
for t in in on RT; do grep -q ">$t</text>" w.svg || fail "w.svg lacks edge label $t"; done
$q render world.json -o h.svg --hide-geometry 2>/dev/null || fail "render --hide-geometry"
for n in kitchen robot mug table note; do grep -q ">$n</text>" h.svg || fail "h.svg lacks node $n"; done
if grep -q -e ">camera</text>" -e ">world</text>" -e ">RT</text>" h.svg; then fail "h.svg shows geometry"; fi
$q render world.json -o hl.dot --highlight robot mug --engine neato 2>/dev/null || fail "render --highlight"
[ "$(grep -c 'class=highlight' hl.dot)" -eq 2 ] || fail "two highlighted nodes in hl.dot: $(cat hl.dot)"
grep -q "pos=" hl.dot || fail "hl.dot has no positions"
$q render "$src/examples/worlds/kitchen.json" -o k.png --title "kitchen" 2>/dev/null || fail "render kitchen.png"
[ "$(head -c 8 k.png | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] || fail "k.png is no PNG"

# A recording: its final state, the state after frame 1, its timeline.
$q render run.qrec -o final.dot 2>/dev/null || fail "render run.qrec"
if grep -q person final.dot; then fail "the final state still shows person"; fi
$q render run.qrec --at 1 -o at1.dot 2>/dev/null || fail "render --at 1"
grep -q "person -> robot" at1.dot || fail "the state after frame 1 lacks person -with-> robot"
out=$($q timeline run.qrec -o frames/ 2>&1) || fail "timeline: $out"
echo "$out" | grep -q "wrote frames/: 5 pictures" || fail "timeline's report: $out"
[ "$(ls frames | tr '\n' ' ')" = "0000.png 0001.png 0002.png 0003.png 0004.png " ] || fail "frames: $(ls frames)"
out=$($q timeline run.qrec -o run.mp4 --hide-geometry --fps 3 2>&1) || fail "timeline mp4: $out"
echo "$out" | grep -q "wrote run.mp4: 4 pictures .* (1 left out" || fail "timeline mp4's report: $out"
[ -s run.mp4 ] || fail "run.mp4 is empty"
$q timeline run.qrec -o few/ --max-frames 2 2>/dev/null || fail "timeline --max-frames"
[ "$(ls few | wc -l)" -eq 2 ] || fail "--max-frames 2 wrote $(ls few | wc -l) frames"

# Errors name the file (and exit non-zero, writing nothing).
expect_error() {  # expect_error PATTERN COMMAND...
  pattern=$1
  shift
  if out=$("$@" 2>&1); then fail "'$*' exits non-zero"; fi
  echo "$out" | grep -q -e "$pattern" || fail "'$*' says: $out"
}
expect_error "cannot tell the picture format of 'x.jpg' from its extension '.jpg'" $q render world.json -o x.jpg
[ ! -e x.jpg ] || fail "x.jpg was written"
expect_error "load_world_file(): cannot open 'nosuch.json'" $q render nosuch.json -o x.png
expect_error "nosuch.qrec" $q render nosuch.qrec -o x.png
expect_error "nosuch.qrec" $q timeline nosuch.qrec -o x.mp4
cp run.qrec damaged.qrec
printf '\125' | dd of=damaged.qrec bs=1 seek=200 conv=notrunc 2>/dev/null
expect_error "damaged.qrec: frame 0 at byte 13: its hash does not match" $q render damaged.qrec -o x.png
expect_error "damaged.qrec: frame 0 at byte 13: its hash does not match" $q timeline damaged.qrec -o x.mp4
printf 'not a recording at all' > junk.qrec
expect_error "junk.qrec" $q timeline junk.qrec -o x.mp4
expect_error "cannot tell what to write to 'x.gif'" $q timeline run.qrec -o x.gif
expect_error "is a world file (.json) or a recording (.qrec)" $q render world.txt -o x.png
expect_error "\-\-at 9: the recording 'run.qrec' holds frames 0..4" $q render run.qrec --at 9 -o x.png
expect_error "\-\-at needs a recording" $q render world.json --at 1 -o x.png
expect_error "no node is named 'nobody' in 'world.json'" $q render world.json --highlight nobody -o x.png
expect_error "unknown layout engine 'circo'" $q render world.json --engine circo -o x.png
expect_error "give either an input file or --domain D" $q render -o x.png
expect_error "give either an input file or --domain D" $q render world.json --domain 3 -o x.png
[ ! -e x.png ] || fail "x.png was written"

# A live domain: nobody there, then an agent that seeded the sample world.
expect_error "\[quiver render\] error: no agent answered on DDS domain 195" $q render --domain 195 --timeout 0.3 -o x.png
$q agent --name seeder --domain 196 --world world.json --run-for 60 >agent.log 2>&1 &
agent_pid=$!
out=$($q render --domain 196 --timeout 20 -o live.svg --hide-geometry 2>&1) || fail "render --domain: $out"
for n in kitchen robot mug table note; do grep -q ">$n</text>" live.svg || fail "live.svg lacks node $n"; done
kill "$agent_pid"
wait "$agent_pid" 2>/dev/null || true
agent_pid=""
echo "render cli: ok"
