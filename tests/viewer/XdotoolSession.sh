# Sourced by the viewer's xdotool tests (ViewerTypingTest.sh, FormingBenchTest.sh): their own Xvfb server, and the
# viewer's window in it.

# under_xvfb ARGS...: unless already inside one, runs the calling script again with ARGS under a new Xvfb server and
# ends with its exit code.
# -ardelay: no key autorepeat. xdotool holds each key for half its delay, but on a loaded machine it can be kept from
# running between a press and its release for longer than Xvfb's 660 ms autorepeat delay, and the server then types
# the held key again (a 64x2x64 scene under ctest -j2 loaded "Typped_SSScenne_B.json", 1 run in 8; a key held 1.5 s
# gives 23 characters with the default, 1 with -ardelay 60000). -noreset: the server otherwise resets when its last
# client leaves (the first viewer), and a viewer that connects during the reset is refused. Under the address
# sanitizer, with Mesa's driver preloaded and leaks checked at exit (tests/CMakeLists.txt), one of two viewers met
# "cannot open display" in 3 runs of 4 (presumably that reset: the cause was not traced further); with -noreset in
# none of 4.
under_xvfb() {
    [ -n "${MASSE_XVFB_INNER:-}" ] && return 0
    command -v xdotool >/dev/null 2>&1 || { echo "xdotool is missing (.ci/build installs it)" >&2; exit 1; }
    command -v xvfb-run >/dev/null 2>&1 || { echo "xvfb-run is missing (.ci/build installs it)" >&2; exit 1; }
    MASSE_XVFB_INNER=1 exec xvfb-run -a -s "-screen 0 1280x1024x24 -ardelay 60000 -noreset" sh "$0" "$@"
}

# wait_for_window PID LOG: sets `window` to the viewer's window once it appears (10 s at most); if it does not, kills
# the viewer (PID), prints its LOG and fails.
wait_for_window() {
    window=""
    for _ in $(seq 1 100); do
        window=$(xdotool search --name "MaSSE" 2>/dev/null | head -n 1) || true
        [ -n "$window" ] && return 0
        sleep 0.1
    done
    kill "$1" 2>/dev/null || true
    echo "the viewer's window did not appear" >&2
    cat "$2" >&2
    exit 1
}
