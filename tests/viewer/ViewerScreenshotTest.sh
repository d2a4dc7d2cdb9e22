#!/bin/sh
# The viewer in a virtual display: the paper's drop scene a few frames in (no contact yet: red masses, no green, no
# black) and at the frame of its first contact with the block (green masses, the block's top face black), each
# screenshot checked by colour where the viewer says the sheet and obstacles are.
#
# usage: ViewerScreenshotTest.sh MASSE CHECKER SCENE OUTDIR
# Xvfb is started (xvfb-run -a) whenever it is installed, so the pictures do not depend on the desktop running the
# tests; without it the test uses $DISPLAY.
set -eu
masse=$1
check=$2
scene=$3
out=$4
mkdir -p "$out"

in_display() {
    if command -v xvfb-run >/dev/null 2>&1; then
        xvfb-run -a -s "-screen 0 1280x1024x24" "$@"
    elif [ -n "${DISPLAY:-}" ]; then
        "$@"
    else
        echo "no xvfb-run and no DISPLAY: install xvfb and xauth (.ci/build does)" >&2
        exit 1
    fi
}

capture="--no-ui --window 800x600 --steps-per-frame 1"
# shellcheck disable=SC2086
in_display "$masse" view "$scene" $capture --frames 3 \
    --screenshot "$out/before-contact.png" --regions "$out/before-contact.json"
"$check" "$out/before-contact.png" "$out/before-contact.json" no-contact

# The first contact with the block comes at about 0.51 s, the 17th step of 0.03 s.
# shellcheck disable=SC2086
in_display "$masse" view "$scene" $capture --until contact:block --frames 60 \
    --screenshot "$out/first-contact.png" --regions "$out/first-contact.json"
"$check" "$out/first-contact.png" "$out/first-contact.json" contact

# With the panel and HUD shown (as a user opens it), on the drop scene and on drape forming (a heater over the sheet):
# the panel's column leaves the whole sheet and every obstacle in view, uncovered. Drawn as masses, which the check
# finds by their colour (drape forming would open on its thickness map).
for scene_name in paper-drop drape-forming; do
    # shellcheck disable=SC2086
    in_display "$masse" view "$(dirname "$scene")/$scene_name.json" --window 1024x720 --steps-per-frame 1 --frames 3 \
        --draw masses --screenshot "$out/$scene_name-panel.png" --regions "$out/$scene_name-panel.json"
    "$check" "$out/$scene_name-panel.png" "$out/$scene_name-panel.json" docked
done

# What the viewer draws when the command line does not say: a scene that forms a part (a forming pressure, or a
# thickness section) opens on its wall thickness h / h0, or on the scalar --scalar names; any other on its masses.
expect_drawing() {
    expected=$1
    shift
    # shellcheck disable=SC2086
    line=$(in_display "$masse" view "$@" --size 8x2x8 --window 400x300 --steps-per-frame 1 --frames 2 --benchmark | tail -n 1)
    case "$line" in
    *"$expected"*) echo "ok   $* draws $expected" ;;
    *)
        echo "FAIL $* should draw $expected: $line" >&2
        exit 1
        ;;
    esac
}
scenes=$(dirname "$scene")
expect_drawing '"draw":"scalar","draw_ms"' "$scenes/vacuum-forming-cup.json"
expect_drawing '"scalar":"thickness_ratio"' "$scenes/vacuum-forming-cup.json"
expect_drawing '"scalar":"thickness_ratio"' "$scenes/drape-forming.json"
expect_drawing '"scalar":"temperature"' "$scenes/plug-assist-cup.json" --scalar temperature
expect_drawing '"draw":"masses","draw_ms"' "$scenes/plug-assist-cup.json" --draw masses
expect_drawing '"draw":"masses","draw_ms"' "$scene"
expect_drawing '"scalar":null' "$scene"
