#!/bin/sh
# Regenerates the figures in the docs: the table of docs/performance.md (performance), the validation table of
# docs/heat-and-forming.md (validation) and the plots the pages show from data/figures (pictures). It runs each command
# below on this machine, reads its figure from what the command prints or writes, and rewrites the lines between the
# page's two marker comments (nothing else in the page changes) or copies the plot the command drew. Run it after
# building, from anywhere:
#     .ci/build && sh docs/figures.sh [performance|validation|pictures]    (all three without an argument)
# on a shared machine: nice -n 10 sh docs/figures.sh. It takes about a quarter of an hour on a 2-core machine. Needs python3
# (to read JSON); the viewer row needs xvfb-run.
set -eu
cd "$(dirname "$0")/.."
masse=build/bin/masse
page=docs/performance.md
tables=${1:-all}
case "$tables" in
all | performance | validation | pictures) ;;
*)
    echo "docs/figures.sh: unknown table '$tables': give performance, validation, pictures or nothing (all three)" >&2
    exit 2
    ;;
esac
if [ ! -x "$masse" ]; then
    echo "docs/figures.sh: $masse is missing: build first (.ci/build)" >&2
    exit 2
fi
grep -q '^<!-- figures:begin -->$' "$page" && grep -q '^<!-- figures:end -->$' "$page" || {
    echo "docs/figures.sh: $page lacks the marker lines <!-- figures:begin --> and <!-- figures:end -->" >&2
    exit 2
}
work=$(mktemp -d "${TMPDIR:-/tmp}/masse-figures.XXXXXX")
trap 'rm -rf "$work"' EXIT INT TERM
rows="$work/rows.md"
: >"$rows"
begin=$(date +%s)

cores=$(nproc)
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -n 1 |
    sed 's/([^)]*)//g; s/ CPU//; s/ @.*//; s/ [0-9]*-Core Processor//; s/  */ /g; s/ *$//')
[ -n "$cpu" ] || cpu=$(uname -m)

# py EXPRESSION FILE: prints a Python expression over the JSON document d read from FILE: the whole file (summary.json,
# compare.json), or else its last line that starts with "{" (a command's JSON line among its other output).
py() {
    python3 - "$1" "$2" <<'EOF'
import json, sys
text = open(sys.argv[2]).read()
try:
    d = json.loads(text)
except ValueError:
    d = json.loads([line for line in text.splitlines() if line.startswith("{")][-1])
print(eval(sys.argv[1]))
EOF
}

# calc EXPRESSION: prints a Python expression of numbers.
calc() { python3 -c "print($1)"; }

# built_commit PATH...: the commit the build comes from, saying so when PATHs hold local changes.
built_commit() {
    c=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
    if [ -n "$(git status --porcelain --untracked-files=no -- "$@" 2>/dev/null)" ]; then
        c="$c with local changes in $*"
    fi
    echo "$c"
}

# rewrite_marked PAGE NAME FILE: replaces the lines between PAGE's <!-- NAME:begin --> and <!-- NAME:end --> with
# FILE's (a blank line on each side).
rewrite_marked() {
    python3 - "$1" "$2" "$3" <<'EOF'
import sys
page, name, body = sys.argv[1:]
text = open(page).read().split("\n")
begin = text.index("<!-- %s:begin -->" % name)
end = text.index("<!-- %s:end -->" % name)
lines = ["<!-- %s:begin -->" % name, ""] + open(body).read().rstrip("\n").split("\n") + ["", "<!-- %s:end -->" % name]
open(page, "w").write("\n".join(text[:begin] + lines + text[end + 1:]))
EOF
}

# timed COMMAND...: runs a command (stdout to $work/out, stderr to $work/err), its wall time in $wall (s) and the
# load average before it started in $load.
timed() {
    load=$(cut -d' ' -f1 /proc/loadavg)
    start=$(date +%s.%N)
    if ! "$@" >"$work/out" 2>"$work/err"; then
        echo "docs/figures.sh: failed: $*" >&2
        tail -n 20 "$work/err" >&2
        exit 1
    fi
    wall=$(calc "round($(date +%s.%N) - $start, 2)")
}

# row WHAT COMMAND FIGURE: one row of the table; the machine column names the cores, the processor and the load
# average just before the command ran.
row() {
    if [ -z "$3" ]; then
        echo "docs/figures.sh: no figure for: $1" >&2
        exit 1
    fi
    printf '| %s | `%s` | %s | %s cores, %s, load %s |\n' "$1" "$2" "$3" "$cores" "$cpu" "$load" >>"$rows"
    echo "docs/figures.sh: $1: $3 ($wall s)" >&2
}

out="$work/runs"
mkdir -p "$out"

# Two validation rows from masse converge on the vacuum cup at 64 and 128 with the extra flags $1, the checks named
# with the suffix $2: the section's differences and the thinnest wall's change.
converge_rows() {
    cdir="$out/converge$(printf '%s' "$1" | tr -c 'a-z0-9' '_')"
    ccmd="$masse converge data/scenes/vacuum-forming-cup.json --sizes 64,128$1 --quiet --out $cdir"
    timed $ccmd
    converge=$(echo "$ccmd" | sed "s|$cdir|OUT/converge|")
    python3 - "$cdir/convergence.json" "$converge" "$2" >>"$work/validation.rows" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
step = d["differences"][-1]
pair = "%s and %s%s" % (step["from"], step["to"], sys.argv[3])
command = "`%s`" % sys.argv[2]
print("validation|cup section, %s|the finer lattice|0.03 h0 on average, 0.08 h0 at most|%.3f h0 on average, %.3f h0 at most|%s|%s"
      % (pair, step["section_mean"], step["section_largest"],
         "holds" if step["section_mean"] <= 0.03 and step["section_largest"] <= 0.08 else "fails", command))
sizes = {s["size"]: s["thinnest_ratio"] for s in d["sizes"]}
print("validation|cup thinnest wall, %s|the finer lattice|5%%|%.1f%% (%.3f and %.3f h0)|%s|%s"
      % (pair, 100 * step["thinnest_change"], sizes[step["from"]], sizes[step["to"]],
         "holds" if step["thinnest_change"] <= 0.05 else "fails", command))
EOF
}

# The forming validation table: each physics test prints its row (tests/support/ValidationRow.h); the cone at 45
# degrees is a disabled test that fails, and the layers at 64x2x64 and 128x2x128 disabled tests of minutes, all run
# here so that their rows say how they stand. The convergence rows come from masse converge.
validate() {
    vpage=docs/heat-and-forming.md
    tests=build/bin/masse_forming_tests
    grep -q '^<!-- validation:begin -->$' "$vpage" && grep -q '^<!-- validation:end -->$' "$vpage" || {
        echo "docs/figures.sh: $vpage lacks the marker lines <!-- validation:begin --> and <!-- validation:end -->" >&2
        exit 2
    }
    vbegin=$(date +%s)
    filter='PressureLoad.FreeBubbleMatchesMembraneTheory:Forming.*ConeLaw*:Forming.VolumeIsConservedThroughVacuumForming'
    filter="$filter:Forming.PlugAssistThickensTheCupBottom:Forming.MirrorSymmetric*:Forming.*LayersStayApartOnTheMouldAt*"
    "$tests" --gtest_also_run_disabled_tests --gtest_filter="$filter" >"$work/validation.out" 2>&1 || true
    grep '^validation|' "$work/validation.out" >"$work/validation.rows" || {
        echo "docs/figures.sh: $tests printed no validation rows" >&2
        tail -n 20 "$work/validation.out" >&2
        exit 1
    }
    # The cup as shipped (a strain-hardening sheet), then as a softening sheet (heat-and-forming.md).
    converge_rows "" ""
    converge_rows " --set material.strain_hardening=0" ", a softening sheet (strain_hardening 0)"
    vtotal=$(($(date +%s) - vbegin))
    {
        echo "Generated by \`sh docs/figures.sh validation\` from the Release build of commit $(built_commit src tests) ($vtotal s)."
        echo
        echo "| check | reference | tolerance | measured | | test or command |"
        echo "| --- | --- | --- | --- | --- | --- |"
        python3 - "$work/validation.rows" <<'EOF'
import sys
for line in open(sys.argv[1]).read().splitlines():
    _, check, reference, tolerance, measured, verdict, source = line.split("|")
    source = source if source.startswith("`") else "`%s`" % source
    print("| %s | %s | %s | %s | %s | %s |" % (check, reference, tolerance, measured, verdict, source))
EOF
    } >"$work/validation.md"
    rewrite_marked "$vpage" validation "$work/validation.md"
    echo "docs/figures.sh: rewrote the validation table in $vpage (${vtotal} s)" >&2
}

# The plots in the pages (data/figures), each drawn by the command named in its page's caption.
if [ "$tables" = all ] || [ "$tables" = pictures ]; then
    pictures="$work/pictures"
    mkdir -p "$pictures"
    # picture COMMAND... -- DRAWN TARGET: runs the command and copies the plot DRAWN (under $pictures) to
    # data/figures/TARGET.
    picture() {
        pcmd=""
        while [ "$1" != "--" ]; do
            pcmd="$pcmd $1"
            shift
        done
        # shellcheck disable=SC2086
        timed $pcmd
        cp "$pictures/$2" "data/figures/$3"
        echo "docs/figures.sh: data/figures/$3 from$(echo "$pcmd" | sed "s|$pictures|OUT|")" >&2
    }
    picture "$masse" paper --out "$pictures/paper" -- paper/figure18.png figure18.png
    cp "$pictures/paper/figure18.csv" data/figures/figure18.csv
    picture "$masse" run data/scenes/sag.json --quiet --out "$pictures/sag" -- sag/sag.png sag.png
    picture "$masse" run data/scenes/drape-forming.json --size 64x2x64 --quiet --out "$pictures/drape" -- \
        drape/thickness_section.png drape-forming-thickness.png
    picture "$masse" compare data/scenes/box-landing.json --quiet --out "$pictures/box" -- \
        box/penetration.png compare-box-penetration.png
    "$masse" sweep data/studies/drape-window.json --out "$pictures/window" --jobs 2 >"$work/out" 2>"$work/err"
    picture "$masse" sweep --collect "$pictures/window" -- window/plots/thinnest-vs-heater_power.png \
        drape-window-thinnest.png
fi

if [ "$tables" = all ] || [ "$tables" = performance ]; then
# Spring forces and the symplectic step: the bench scene (a Table 1 sheet in free fall), against a plain loop.
for size in 128x2x128 256x2x256; do
    cmd="$masse bench --size $size --baseline --steps 3 --repeat 3"
    timed $cmd
    row "symplectic step, $size sheet in free fall" "$cmd" "$(py '"%.0f M spring-steps/s, %.2fx the plain scalar loop, %.2fx real time; %d substeps a 0.03 s step; %d threads, %s" % (d["spring_steps_per_second"] / 1e6, d["baseline"]["speedup"], d["realtime_factor"], d["substeps"] / d["steps"], d["threads"], d["simd"])' "$work/out")"
done

# Contact: the same sheet resting on two boxes.
cmd="$masse bench --contact --steps 3 --repeat 3"
timed $cmd
row "contact, 256x2x256 sheet resting on two boxes" "$cmd" "$(py '"contact %.0f%% of the step (detection %.3f s, projection %.3f s), %.2fx real time" % (100 * d["contact"]["contact_share_of_step"], d["contact"]["detection_seconds"], d["contact"]["projection_seconds"], d["realtime_factor"])' "$work/out")"

# Contact in the forming scenes: the mould searched per mass from the start of the forming.
for scene in vacuum-forming-cup pressure-forming-tray plug-assist-cup drape-forming; do
    cmd="$masse bench data/scenes/$scene.json --size 64x2x64 --steps 20 --repeat 3"
    timed $cmd
    row "where the step goes, $scene, 64x2x64, its first 20 frames" "$cmd" "$(py '"contact %.0f%% of the step (detection %.3f s, projection %.3f s), implicit solve %.0f%% (iterations %.0f%%, preconditioner %.0f%%, assembly %.0f%%), %.2fx real time, %.1f CG iterations a step" % (100 * d["contact"]["contact_share_of_step"], d["contact"]["detection_seconds"], d["contact"]["projection_seconds"], 100 * d["solver_stages"]["share_of_step"], 100 * d["solver_stages"]["iterations_share"], 100 * d["solver_stages"]["preconditioner_share"], 100 * d["solver_stages"]["assembly_share"], d["realtime_factor"], d["solver_iterations_per_step"])' "$work/out")"
done
# The frame's stages (docs/step.md) on the heated drape sheet at 128x2x128, its first 20 frames under the panel.
cmd="$masse bench data/scenes/drape-forming.json --size 128x2x128 --steps 20 --repeat 3"
timed $cmd
row "where the frame goes, drape-forming, 128x2x128, its first 20 frames" "$cmd" "$(py '"integrate %.0f%% (implicit solve %.0f%%: iterations %.0f%%, preconditioner %.0f%%, assembly %.0f%%), beginFrame %.0f%% (the springs follow the heat), endFrame %.0f%% (the heat step), afterSubstep %.0f%%, the other stages %.0f%%; %.2fx real time, %.1f CG iterations a step" % (100 * d["step_stages"]["integrate"]["share"], 100 * d["solver_stages"]["share_of_step"], 100 * d["solver_stages"]["iterations_share"], 100 * d["solver_stages"]["preconditioner_share"], 100 * d["solver_stages"]["assembly_share"], 100 * d["step_stages"]["beginFrame"]["share"], 100 * d["step_stages"]["endFrame"]["share"], 100 * d["step_stages"]["afterSubstep"]["share"], 100 * sum(v["share"] for k, v in d["step_stages"].items() if k not in ("integrate", "beginFrame", "endFrame", "afterSubstep")), d["realtime_factor"], d["solver_iterations_per_step"])' "$work/out")"
cmd="$masse bench data/scenes/vacuum-forming-cup.json --size 128x2x128 --steps 10 --repeat 1"
timed $cmd
row "where the step goes, vacuum-forming-cup, 128x2x128, its first 10 frames" "$cmd" "$(py '"contact %.0f%% of the step, implicit solve %.0f%% (iterations %.0f%%, preconditioner %.0f%%, assembly %.0f%%), %.2fx real time, %.1f CG iterations a step" % (100 * d["contact"]["contact_share_of_step"], 100 * d["solver_stages"]["share_of_step"], 100 * d["solver_stages"]["iterations_share"], 100 * d["solver_stages"]["preconditioner_share"], 100 * d["solver_stages"]["assembly_share"], d["realtime_factor"], d["solver_iterations_per_step"])' "$work/out")"

# The implicit solve on the free-falling sheet.
for spec in "64x2x64 10" "128x2x128 5"; do
    set -- $spec
    cmd="$masse bench --size $1 --integrator implicit --steps $2 --repeat 2"
    timed $cmd
    row "implicit Euler step, $1 sheet in free fall, dt 0.03" "$cmd" "$(py '"%.1f ms a step, %.1f CG iterations a step, first step (analysis and factorisation) %.2f s" % (1000 * d["wall_seconds"] / d["steps"], d["solver_iterations_per_step"], d["setup_seconds"]["first_step"])' "$work/out")"
done

# The paper's drop scene at a fine size, whole command.
cmd="$masse run data/scenes/paper-drop.json --size 128x2x128 --duration 1 --quiet --out $out/drop"
timed $cmd
row "drop scene, 128x2x128, first simulated second" "$(echo "$cmd" | sed "s|$out|OUT|")" "$(calc "'%.2fx real time (1 s simulated in %.1f s, the whole command)' % (1 / $wall, $wall)")"

# The paper's Figure 18: five sizes to rest.
cmd="$masse paper --out $out/paper"
timed $cmd
row "Figure 18: the drop at the five Table 2 sizes, to rest" "$(echo "$cmd" | sed "s|$out|OUT|")" "$wall s for the whole command"

# Forming runs, whole: forming_row LABEL SCENE SIZE SECONDS OUTNAME.
forming_row() {
    cmd="$masse run data/scenes/$2.json --size $3 --quiet --out $out/$5"
    timed $cmd
    row "$1, $3, whole $4 s" "$(echo "$cmd" | sed "s|$out|OUT|")" "$(py '"%.2fx real time (%.1f s wall), %.1f CG iterations a step, %d refactorisations" % ('"$4"' / '"$wall"', '"$wall"', d["solver"]["mean_iterations"], d["solver"]["refactorisations"])' "$out/$5/summary.json")"
}
forming_row "vacuum-formed cup" vacuum-forming-cup 32x2x32 2.5 cup
forming_row "vacuum-formed cup" vacuum-forming-cup 64x2x64 2.5 cup64
forming_row "vacuum-formed cup" vacuum-forming-cup 128x2x128 2.5 cup128
forming_row "plug-assist cup" plug-assist-cup 64x2x64 3 plug64
forming_row "pressure-formed tray" pressure-forming-tray 64x2x64 1.5 tray64
forming_row "drape forming" drape-forming 64x2x64 60 drape
forming_row "drape forming" drape-forming 128x2x128 60 drape128
# The same forming runs on the AVX2 path, which a processor without AVX-512 takes (the same bits).
for run in "vacuum-formed cup:vacuum-forming-cup:2.5" "plug-assist cup:plug-assist-cup:3" "pressure-formed tray:pressure-forming-tray:1.5"; do
    label=${run%%:*}; rest=${run#*:}; scene=${rest%%:*}; seconds=${rest#*:}
    cmd="env MASSE_SIMD=avx2 $masse run data/scenes/$scene.json --size 64x2x64 --quiet --out $out/$scene-avx2"
    timed $cmd
    row "$label, 64x2x64, whole $seconds s, AVX2 path" "$(echo "$cmd" | sed "s|$out|OUT|")" "$(py '"%.2fx real time (%.1f s wall), %s" % ('"$seconds"' / '"$wall"', '"$wall"', d["simd"])' "$out/$scene-avx2/summary.json")"
done

# Self-collision's cost on the fold over the rod, with the implicit integrator.
cmd="$masse run data/scenes/fold-over-rod.json --size 32x2x32 --integrator implicit --quiet --out $out/fold"
timed $cmd
with=$wall
withload=$load
timed $cmd --set contact.self_collision=false --force
without=$wall
load=$withload
row "self-collision, fold over the rod, 32x2x32, implicit, 3 s" "$(echo "$cmd" | sed "s|$out|OUT|")" "$(calc "'%.1f s wall; %.1f s with --set contact.self_collision=false: %.0f%% more' % ($with, $without, 100 * ($with / $without - 1))")"

# Parameter studies.
cmd="$masse sweep data/studies/drape-window.json --out $out/window --jobs 2"
timed $cmd
sweep=$wall
sweepload=$load
timed "$masse" sweep --collect "$out/window"
load=$sweepload
row "parameter study: drape window, 9 cases, 2 at a time" "$(echo "$cmd" | sed "s|$out|OUT|")" "$sweep s for the 9 cases; $wall s for \`masse sweep --collect\` (table and plots)"

cmd="$masse sweep tests/studies/overhead.json --out $out/overhead --jobs 1 --no-plots"
timed $cmd
row "sweep overhead per case: 20 one-step cases" "$(echo "$cmd" | sed "s|$out|OUT|")" "$(sed -n 's/.*overhead per case[^:]*: \(median [0-9.]* ms\).*/\1/p' "$work/out" | head -n 1) per case (its wall time minus the simulation's)"

# MaSSE beside Bullet on the box landing.
cmd="$masse compare data/scenes/box-landing.json --quiet --out $out/box"
timed $cmd
row "box landing, MaSSE beside Bullet (8x2x8, dt 0.03)" "$(echo "$cmd" | sed "s|$out|OUT|")" "$(py '"; ".join("%s: deepest penetration %.3g mm, %.1f ms per simulated second" % (e["label"], 1000 * e["penetration"]["max"], e["wall_ms_per_simulated_second"]) for e in d["engines"])' "$out/box/compare.json")"

# The viewer under Xvfb.
if command -v xvfb-run >/dev/null 2>&1; then
    cmd="xvfb-run -a $masse view --size 64x2x64 --frames 300 --benchmark"
    timed $cmd
    row "viewer, 64x2x64 drop scene under Xvfb (software rendering)" "$cmd" "$(py '"%.1f frames/s, %.2fx real time, a pick carried out in %.0f ms" % (d["fps"], d["realtime_factor"], d.get("pick_applied_ms") or float("nan"))' "$work/out")"
    # The forming bench (docs/forming-bench.md): forming scenes live.
    for run in "vacuum cup:vacuum-forming-cup:64x2x64:400" "plug-assist cup:plug-assist-cup:64x2x64:200" \
        "vacuum cup, its start:vacuum-forming-cup:128x2x128:150"; do
        label=${run%%:*}; rest=${run#*:}; scene=${rest%%:*}; rest=${rest#*:}; size=${rest%%:*}; frames=${rest#*:}
        cmd="xvfb-run -a $masse view data/scenes/$scene.json --size $size --frames $frames --benchmark"
        timed $cmd
        row "viewer, $label, $size under Xvfb ($frames frames)" "$cmd" "$(py '"%.1f frames/s drawing %s (%.1f ms a frame), %.2fx real time over its first %.2f simulated s, a pick carried out in %.0f ms" % (d["fps"], d.get("scalar") or d["draw"], d["draw_ms"], d["realtime_factor"], d["sim_seconds"], d.get("pick_applied_ms") or float("nan"))' "$work/out")"
    done
fi

total=$(($(date +%s) - begin))
{
    echo "Generated by \`sh docs/figures.sh\` from the Release build of commit $(built_commit src) (the script took $total s)."
    echo
    echo "| what | command | figure | machine |"
    echo "| --- | --- | --- | --- |"
    cat "$rows"
} >"$work/performance.md"
rewrite_marked "$page" figures "$work/performance.md"
echo "docs/figures.sh: rewrote the table in $page (${total} s)" >&2
fi

if [ "$tables" = all ] || [ "$tables" = validation ]; then
    validate
fi
