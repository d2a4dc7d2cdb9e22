#!/bin/sh
# `masse view` with bad input: each case must exit with code 2 and say what is wrong, before any window opens.
#
# usage: ViewerBadInputTest.sh MASSE SOURCE_DIR
set -u
masse=$1
source_dir=$2
failures=0

expect_input_error() {
    description=$1
    pattern=$2
    shift 2
    output=$("$@" 2>&1)
    code=$?
    if [ "$code" -eq 2 ] && printf '%s' "$output" | grep -q -- "$pattern"; then
        echo "ok   $description"
    else
        echo "FAIL $description: exit $code, output: $output"
        failures=$((failures + 1))
    fi
}

expect_input_error "no display: says how to run headless or under Xvfb" "xvfb-run -a masse view" \
    env -u DISPLAY "$masse" view
expect_input_error "no display: names the headless commands" "masse run SCENE" \
    env -u DISPLAY "$masse" view
expect_input_error "a scene that does not exist: its own error" "missing.json: cannot be read" \
    env -u DISPLAY "$masse" view "$source_dir/missing.json"
bad=$(mktemp)
printf '{ "sheet": { "sizes": "8x2x8" } }' >"$bad"
expect_input_error "a scene with an unknown key: the loader's message" "sizes" \
    env -u DISPLAY "$masse" view "$bad"
rm -f "$bad"
expect_input_error "an unknown view" "--view: unknown view" env -u DISPLAY "$masse" view --view sideways
expect_input_error "a capture without an end" "need --frames" \
    env -u DISPLAY "$masse" view --screenshot out.png
expect_input_error "an unknown scalar" "unknown scalar 'pressure'" \
    env -u DISPLAY "$masse" view --draw scalar --scalar pressure --frames 1
expect_input_error "a scalar the scene lacks: says why instead of painting one colour" \
    "--scalar temperature: this scene has no heat" \
    env -u DISPLAY "$masse" view "$source_dir/data/scenes/paper-drop.json" --draw scalar --scalar temperature --frames 1
expect_input_error "a scalar the scene lacks: names those it can show" "can show speed, strain" \
    env -u DISPLAY "$masse" view "$source_dir/data/scenes/paper-drop.json" --draw scalar --scalar thickness --frames 1
# Not an error, but said before the window opens as `masse run` says it: here the display's absence ends the run after
# the warning.
expect_input_error "a scene needing over 1,000 substeps a step: says so and names the implicit integrator" \
    "symplectic integrator needs [0-9]* substeps for each 0.03 s step.*--integrator implicit" \
    env -u DISPLAY "$masse" view "$source_dir/data/scenes/own-forming.json" --integrator symplectic

[ "$failures" -eq 0 ]
