#!/usr/bin/env bash
# Regenerates the pictures of the user guide (docs/paper_2d_eta.png, docs/img/*.png) and the
# generated validation report (docs/validation-report.md) from slosh runs.
#
#   docs/regenerate-figures.sh [NAME ...]     # NAME: a figure (its file stem), a group or `report`
#   docs/regenerate-figures.sh list           # the names, what each runs and what it costs
#
# Environment:
#   SLOSH  the slosh binary (default target/release/slosh; build it with
#          `cargo build --release -p slosh-cli`)
#   OUT    the folder the runs write into (default: a new temporary folder, kept and printed at
#          the end; the runs' folders are not removed)
#
# Without a NAME every figure is made, the long studies included: that is about a day of wall
# time on 2 cores (the costs below are wall times measured on the machine of
# docs/performance.md). Each figure is copied over its file in docs/ only when its run wrote it.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SLOSH="${SLOSH:-target/release/slosh}"
case "$SLOSH" in
    /*) ;;
    *) if [ -e "$SLOSH" ]; then SLOSH="$(cd "$(dirname "$SLOSH")" && pwd)/$(basename "$SLOSH")";
       else SLOSH="$repo/$SLOSH"; fi ;;
esac
if [ ! -x "$SLOSH" ]; then
    echo "error: no slosh binary at $SLOSH: build it with \`cargo build --release -p slosh-cli\` or set SLOSH" >&2
    exit 1
fi
cd "$repo"

# copy SRC DEST: one figure into docs/, said on the terminal.
copy_failed=0
copy() {
    if [ ! -f "$1" ]; then
        echo "error: $1 was not written (see the run's output above)" >&2
        copy_failed=1
        return 1
    fi
    cp "$1" "$2"
    echo "wrote $2 (from $1)"
}

# validate_stage DIR ONLY [--quick]: one stage of the validation suite into DIR. A FAIL row makes
# slosh exit with 1 but the plots are still written; it is reported, not fatal here.
validate_stage() {
    local dir="$1" only="$2"
    shift 2
    if ! "$SLOSH" validate "$@" --only "$only" --out "$dir"; then
        echo "warning: slosh validate --only \"$only\" has a FAIL row (see $dir/report.md); its plots are copied all the same" >&2
    fi
}

# --- the jobs: each makes one or more figures -------------------------------------------------

# The paper's §3.1 case (≈ 25–40 s): plots/eta.png.
job_paper_2d_eta() {
    "$SLOSH" run scripts/paper_2d_sloshing.rhai --out "$OUT/paper_2d_sloshing"
    copy "$OUT/paper_2d_sloshing/plots/eta.png" docs/paper_2d_eta.png
}

# Validation, quick suite, stage "paper case §3.1" (its 12 s paper run, under a minute):
# Fig. 3, 4 and 5 of the paper.
job_paper_case() {
    validate_stage "$OUT/validate_paper_case" "paper case" --quick
    for f in fig3_resonant_eta_left fig4_housner_pressure fig5_base_shear; do
        copy "$OUT/validate_paper_case/$f.png" "docs/img/$f.png"
    done
}

# Validation, quick suite, stage "modern scheme: period, hydrostatics, resonance, roof impact".
job_modern() {
    validate_stage "$OUT/validate_modern" "modern scheme: period" --quick
    for f in modern_resonant_eta_left modern_roof_pressure; do
        copy "$OUT/validate_modern/$f.png" "docs/img/$f.png"
    done
}

# Validation, quick suite, stage "dam break: front".
job_dambreak() {
    validate_stage "$OUT/validate_dambreak" "dam break: front" --quick
    copy "$OUT/validate_dambreak/dambreak_front.png" docs/img/dambreak_front.png
}

# Validation, full suite, stage "nonlinear sloshing against experiments": the figure of
# docs/validation.md shows 50 particles per depth, the full suite's level (the quick suite runs
# 25). Long: the full suite's levels of three experiments (cost not measured on its own).
job_experiments() {
    validate_stage "$OUT/validate_experiments" "nonlinear sloshing against experiments"
    copy "$OUT/validate_experiments/experiment_okamoto1992.png" docs/img/experiment_okamoto1992.png
}

# Validation, full suite, stage "modern scheme: sloshing damping (free decay)" (≈ 9 min).
job_damping() {
    validate_stage "$OUT/validate_damping" "modern scheme: sloshing damping"
    copy "$OUT/validate_damping/damping_free_decay.png" docs/img/damping_free_decay.png
}

# Paper Fig. 8 as a sweep: 18 cases of the §3.2 roof case (3 min 41 s with --jobs 2).
job_fig8() {
    "$SLOSH" sweep scripts/paper_2d_roof.rhai \
        --vary tank_height=0.56,0.58,0.60,0.62,0.64,0.66 --vary smoothing_steps=8,20,40 \
        --plot tank_height:max_roof_p:smoothing_steps \
        --plot tank_height:max_roof_force_up:smoothing_steps \
        --plot tank_height:kurihara_at_max,malhotra_at_max --jobs 2 --out "$OUT/F8"
    copy "$OUT/F8/plot_max_roof_p_vs_tank_height_by_smoothing_steps.png" docs/img/fig8_roof_pressure.png
    copy "$OUT/F8/plot_max_roof_force_up_vs_tank_height_by_smoothing_steps.png" docs/img/fig8_roof_force.png
}

# Paper Fig. 10 shortened to 15 s runs: 9 cases (12 min 47 s with --jobs 2).
job_fig10_roof_force() {
    "$SLOSH" sweep scripts/paper_2d_roof_sweep.rhai --vary width=0.5,1.0,1.5 \
        --vary clearance_ratio=0.1,0.2,0.3 --vary duration=15 \
        --plot clearance_ratio:max_roof_force_up:width --jobs 2 --out "$OUT/F10_15s"
    copy "$OUT/F10_15s/plot_max_roof_force_up_vs_clearance_ratio_by_width.png" docs/img/fig10_roof_force.png
}

# Paper Fig. 10 with the paper's 50 s runs at dx = 0.02 m, A = 0.0093 m: 9 cases, paper scheme
# with the paper's stiffness (≈ 10 min with --jobs 2).
job_fig10_50s_paper() {
    "$SLOSH" sweep scripts/paper_2d_roof_sweep.rhai --vary width=0.5,1.0,1.5 \
        --vary amplitude=0.0093 --vary clearance_ratio=0.1,0.2,0.3 \
        --plot clearance_ratio:max_roof_force_up:width --jobs 2 --out "$OUT/F10_50s_paper"
    copy "$OUT/F10_50s_paper/plot_max_roof_force_up_vs_clearance_ratio_by_width.png" docs/img/fig10_roof_force_50s_paper.png
}

# The same with the modern preset, c0 from the tank (514–523 s with --jobs 2).
job_fig10_50s_modern() {
    "$SLOSH" sweep scripts/paper_2d_roof_sweep.rhai --vary width=0.5,1.0,1.5 \
        --vary amplitude=0.0093 --vary clearance_ratio=0.1,0.2,0.3 \
        --vary scheme=modern --vary eos_b=0 \
        --plot clearance_ratio:max_roof_force_up:width --jobs 2 --out "$OUT/F10_50s_modern"
    copy "$OUT/F10_50s_modern/plot_max_roof_force_up_vs_clearance_ratio_by_width.png" docs/img/fig10_roof_force_50s_modern.png
}

# Paper Fig. 10 on both lattices (dx = 0.02 and 0.01 m), 50 s runs, one sweep per scheme and
# amplitude: 18 cases each. LONG: the 72 cases of the four sweeps took 20.0 h of wall time in
# all (one thread each, two at a time); a fine case 436–2,328 s, some longer. A case finished
# before is not run again, one stopped part way continues from its checkpoint: run the same
# NAME again with the same OUT after an interruption.
fig10_two_lattices() {
    local scheme="$1" amplitude="$2" extra=()
    if [ "$scheme" = modern ]; then extra=(--vary scheme=modern --vary eos_b=0); fi
    local dir="$OUT/F10_two_lattices_${scheme}_A${amplitude}"
    "$SLOSH" sweep scripts/paper_2d_roof_sweep.rhai --vary width=0.5,1.0,1.5 \
        --vary clearance_ratio=0.1,0.2,0.3 --vary dx=0.02,0.01 --vary amplitude="$amplitude" \
        "${extra[@]}" --plot post_clearance_ratio_actual:max_roof_force_up:width+dx \
        --plot post_clearance_ratio_actual:max_roof_force_up_lp:width+dx \
        --jobs 2 --out "$dir"
    copy "$dir/plot_max_roof_force_up_vs_post_clearance_ratio_actual_by_width_dx.png" \
        "docs/img/fig10_two_lattices_${scheme}_A${amplitude}.png"
}
job_fig10_two_lattices_paper_A0_0093() { fig10_two_lattices paper 0.0093; }
job_fig10_two_lattices_paper_A0_00415() { fig10_two_lattices paper 0.00415; }
job_fig10_two_lattices_modern_A0_0093() { fig10_two_lattices modern 0.0093; }
job_fig10_two_lattices_modern_A0_00415() { fig10_two_lattices modern 0.00415; }

# The 24 m section of the real-scale tank with its cone roof under El Centro at 3 m/s² (≈ 15 s):
# plots/frame_peak.png.
job_cone2d() {
    "$SLOSH" run scripts/tank_real_scale_2d_cone.rhai --out "$OUT/CONE2D"
    copy "$OUT/CONE2D/plots/frame_peak.png" docs/img/tank_real_scale_2d_cone_frame_peak.png
}

# The half-full horizontal cylinder sloshing freely from a 5 cm tilt, 10 s (≈ 2.5 min).
job_hcyl() {
    "$SLOSH" run scripts/horizontal_cylinder_2d.rhai --out "$OUT/HCYL"
    copy "$OUT/HCYL/plots/eta.png" docs/img/horizontal_cylinder_eta.png
}

# The same cylinder for 2 s, its frame at the largest wave (33 s).
job_hcyl_frame() {
    "$SLOSH" run scripts/horizontal_cylinder_2d.rhai --set duration=2.0 --out "$OUT/HCYL2"
    copy "$OUT/HCYL2/plots/frame_peak.png" docs/img/horizontal_cylinder_frame_peak.png
}

# The example assessment of the real-scale tank at a coarse 10 particles per radius: 4 runs of
# 32 s (9 min 11 s with --jobs 2).
job_assess() {
    "$SLOSH" assess scripts/tank_real_scale.rhai --motions scripts/tank_real_scale_suite.csv \
        --set particles_per_radius=10 --set frame_interval=0 --jobs 2 --out "$OUT/tank-assess"
    copy "$OUT/tank-assess/plots/wave_heights.png" docs/img/assess_wave_heights.png
}

# The quick validation suite (≈ 6 min) into docs/validation-report.md. The report's plots are
# linked to docs/img/ where a figure of the same name is there, and named otherwise.
job_report() {
    local dir="$OUT/validate_quick" status=0
    "$SLOSH" validate --quick --out "$dir" || status=$?
    if [ ! -f "$dir/report.md" ]; then
        echo "error: slosh validate --quick wrote no report (exit status $status)" >&2
        return 1
    fi
    local version
    version="$("$SLOSH" --version 2>/dev/null || echo slosh)"
    {
        echo "# The latest quick validation report"
        echo
        echo "<!-- quick-report: generated by docs/regenerate-figures.sh report -->"
        echo
        echo "*Generated by \`docs/regenerate-figures.sh report\`: \`slosh validate --quick --out DIR\` ($version, exit status $status), \`DIR/report.md\` below, its plots in \`DIR\`. Do not edit by hand. What the suite checks: [Validation](validation-summary.md).*"
        echo
        awk -v img="$repo/docs/img" '
            /^# slosh validation report/ { next }
            match($0, /^!\[.*\]\([^)]*\)$/) {
                file = $0; sub(/^.*\]\(/, "", file); sub(/\)$/, "", file)
                caption = $0; sub(/^!\[/, "", caption); sub(/\]\([^)]*\)$/, "", caption)
                if ((getline _ < (img "/" file)) >= 0) { close(img "/" file); print "![" caption "](img/" file ")" }
                else { print "*Plot `" file "` (in the report'"'"'s folder): " caption "*" }
                next
            }
            { print }
        ' "$dir/report.md"
    } > docs/validation-report.md
    echo "wrote docs/validation-report.md (from $dir/report.md)"
    return "$status"
}

# --- names -----------------------------------------------------------------------------------

# figure stem (or group name) → job
declare -A JOB=(
    [paper_2d_eta]=paper_2d_eta
    [fig3_resonant_eta_left]=paper_case [fig4_housner_pressure]=paper_case
    [fig5_base_shear]=paper_case [paper_case]=paper_case
    [modern_resonant_eta_left]=modern [modern_roof_pressure]=modern [modern]=modern
    [dambreak_front]=dambreak
    [experiment_okamoto1992]=experiments
    [damping_free_decay]=damping
    [fig8_roof_pressure]=fig8 [fig8_roof_force]=fig8 [fig8]=fig8
    [fig10_roof_force]=fig10_roof_force
    [fig10_roof_force_50s_paper]=fig10_50s_paper
    [fig10_roof_force_50s_modern]=fig10_50s_modern
    [fig10_two_lattices_paper_A0.0093]=fig10_two_lattices_paper_A0_0093
    [fig10_two_lattices_paper_A0.00415]=fig10_two_lattices_paper_A0_00415
    [fig10_two_lattices_modern_A0.0093]=fig10_two_lattices_modern_A0_0093
    [fig10_two_lattices_modern_A0.00415]=fig10_two_lattices_modern_A0_00415
    [tank_real_scale_2d_cone_frame_peak]=cone2d [cone2d]=cone2d
    [horizontal_cylinder_eta]=hcyl [hcyl]=hcyl
    [horizontal_cylinder_frame_peak]=hcyl_frame [hcyl_frame]=hcyl_frame
    [assess_wave_heights]=assess [assess]=assess
    [report]=report
)
# every figure in the order `all` makes them, shortest first
ALL_JOBS=(paper_2d_eta paper_case modern dambreak cone2d hcyl_frame hcyl fig8 assess damping
    fig10_roof_force fig10_50s_paper fig10_50s_modern experiments
    fig10_two_lattices_paper_A0_0093 fig10_two_lattices_paper_A0_00415
    fig10_two_lattices_modern_A0_0093 fig10_two_lattices_modern_A0_00415)

if [ "${1:-}" = list ]; then
    for name in $(printf '%s\n' "${!JOB[@]}" | sort); do
        printf '%-40s job %s\n' "$name" "${JOB[$name]}"
    done
    echo "(the cost of each job is in the comment above its function in $0)"
    exit 0
fi

OUT="${OUT:-$(mktemp -d "${TMPDIR:-/tmp}/slosh-figures.XXXXXX")}"
mkdir -p "$OUT"

jobs=()
if [ "$#" -eq 0 ]; then
    jobs=("${ALL_JOBS[@]}")
else
    for name in "$@"; do
        name="${name%.png}"
        if [ -z "${JOB[$name]+set}" ]; then
            echo "error: unknown figure or group \"$name\"; \`$0 list\` lists the names" >&2
            exit 2
        fi
        job="${JOB[$name]}"
        case " ${jobs[*]} " in *" $job "*) ;; *) jobs+=("$job") ;; esac
    done
fi

failed=0
for job in "${jobs[@]}"; do
    echo "== $job (runs in $OUT)"
    copy_failed=0
    # A job's status is its last command's: a figure it failed to copy earlier counts too.
    if ! "job_$job" || [ "$copy_failed" = 1 ]; then
        echo "warning: $job did not complete" >&2
        failed=1
    fi
done
echo "runs kept in $OUT"
exit "$failed"
