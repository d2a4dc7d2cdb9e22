#!/bin/sh
# The forming bench under Xvfb, driven with xdotool as a user drives it: the plug-assist cup at 16x2x16, started
# paused; the plug sent down two steps (j, j) and the vacuum switched (u) before it runs; then, running, the plug sent
# up (k) and held (h), and the run saved (w). The saved scene file must replay headless (masse run) to the state hash
# the viewer printed when it saved, and hold the actions typed. A screenshot of the last frame goes to OUTDIR.
#
# usage: FormingBenchTest.sh MASSE SCENE OUTDIR
set -eu
masse=$1
scene=$2
out=$3
mkdir -p "$out"
. "$(dirname "$0")/XdotoolSession.sh"
under_xvfb "$@"

saved="$out/bench.run.json"
log="$out/bench.log"
rm -f "$saved"
"$masse" view "$scene" --size 16x2x16 --paused --window 1024x720 --frames 100000 --save-run "$saved" \
    --draw scalar --scalar thickness_ratio --view left \
    --screenshot "$out/forming-bench.png" > "$log" 2>&1 &
pid=$!
wait_for_window "$pid" "$log"
sleep 2 # the first frames
# Keys reach the window whatever the mouse is over; a key lost on a loaded machine only changes what is saved, which
# the replay must still match. Each with a pause, so that they arrive in separate frames.
for key in j j u space; do
    xdotool key --window "$window" "$key"
    sleep 0.4
done
sleep 1.5
for key in k h; do
    xdotool key --window "$window" "$key"
    sleep 0.4
done
sleep 0.5
xdotool key --window "$window" w
# The save is carried out by the simulation thread between steps; wait for its line before quitting.
for _ in $(seq 1 100); do
    grep -q "saved the run to" "$log" && break
    sleep 0.1
done
xdotool key --window "$window" q
status=0
wait "$pid" || status=$?
cat "$log"
if [ "$status" -ne 0 ]; then
    echo "FAIL: the viewer ended with status $status" >&2
    exit 1
fi
live=$(sed -n 's/.*saved the run to .*state \(0x[0-9a-f]*\).*/\1/p' "$log" | tail -n 1)
if [ -z "$live" ] || [ ! -s "$saved" ]; then
    echo "FAIL: the viewer did not save the run (no state hash in its output, or no $saved)" >&2
    exit 1
fi
for action in '"steer"' '"pressure"'; do
    if ! grep -q "$action" "$saved"; then
        echo "FAIL: the saved run holds no $action action (the keys did not reach the viewer)" >&2
        exit 1
    fi
done
replay=$("$masse" run "$saved" --quiet --out "$out/replay" --force | sed -n 's/.*state \(0x[0-9a-f]*\).*/\1/p')
if [ "$replay" != "$live" ]; then
    echo "FAIL: the live run saved at state $live, its replay ended at $replay" >&2
    exit 1
fi
echo "ok: the run saved from the viewer replays headless to the same state, $live"
