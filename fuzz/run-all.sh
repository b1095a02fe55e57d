#!/usr/bin/env bash
# Runs every cargo-fuzz target of fuzz/Cargo.toml (its [[bin]] names, in file order)
# for a given time each, with `cargo fuzz run -s none -O TARGET -- -max_total_time=N`,
# and prints one line per target: runs, coverage (libFuzzer's cov and ft), corpus size,
# and the finding (the artifact libFuzzer wrote) or "none". A finding ends that target's
# run only: the script goes on with the others. The routine before a release
# (docs/testing.md, "Every fuzz target before a release").
#
#   fuzz/run-all.sh [-t SECONDS] [-j JOBS] [TARGET...] [-- LIBFUZZER_ARGS...]
#
#   -t SECONDS  time per target (default 60)
#   -j JOBS     targets run at once (default 1; each takes one core)
#   TARGET...   only these targets (default: all)
#   -- ARGS     more libFuzzer arguments for every target (e.g. -timeout=10)
#
# The working corpus is fuzz/corpus/TARGET (kept between runs), findings go to
# fuzz/artifacts/TARGET/, each target's full output to fuzz/target/run-all/TARGET.log.
# A target with a dictionary fuzz/TARGET.dict gets it. Exit status: 0 when no target
# found anything, 1 when one did, 2 when a target did not build or run.
set -uo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
fuzz="$root/fuzz"
seconds=60
jobs=1
targets=()
extra=()

usage() {
    sed -n '2,/^set -uo/p' "${BASH_SOURCE[0]}" | sed -n 's/^# \{0,1\}//p' >&2
    exit 2
}

while (($#)); do
    case $1 in
    -t) seconds=${2:?-t needs seconds}; shift 2 ;;
    -j) jobs=${2:?-j needs a number}; shift 2 ;;
    -h | --help) usage ;;
    --) shift; extra=("$@"); break ;;
    -*) echo "run-all.sh: unknown option $1" >&2; usage ;;
    *) targets+=("$1"); shift ;;
    esac
done
[[ $seconds =~ ^[1-9][0-9]*$ ]] || { echo "run-all.sh: -t takes whole seconds" >&2; exit 2; }
[[ $jobs =~ ^[1-9][0-9]*$ ]] || { echo "run-all.sh: -j takes a positive number" >&2; exit 2; }

if ! cargo fuzz --version >/dev/null 2>&1; then
    echo "run-all.sh: cargo-fuzz is not installed; install it with:" >&2
    echo "    cargo install --locked cargo-fuzz" >&2
    exit 2
fi

# The [[bin]] names of fuzz/Cargo.toml: the first `name = "..."` in each [[bin]] table.
mapfile -t all < <(awk '
    /^\[\[bin\]\]/ { in_bin = 1; next }
    /^\[/ { in_bin = 0 }
    in_bin && /^name *=/ { gsub(/.*= *"|".*/, ""); print; in_bin = 0 }
' "$fuzz/Cargo.toml")
((${#all[@]})) || { echo "run-all.sh: no [[bin]] in $fuzz/Cargo.toml" >&2; exit 2; }
if ((${#targets[@]} == 0)); then
    targets=("${all[@]}")
else
    for t in "${targets[@]}"; do
        printf '%s\n' "${all[@]}" | grep -qx -- "$t" || {
            echo "run-all.sh: no fuzz target '$t' (fuzz/Cargo.toml has: ${all[*]})" >&2
            exit 2
        }
    done
fi

logs="$fuzz/target/run-all"
mkdir -p "$logs"
cd "$root" || exit 2

# Build first, one target after another, so parallel runs do not wait on cargo's lock
# and a build error is reported once.
for t in "${targets[@]}"; do
    if ! cargo fuzz build -s none -O "$t" >"$logs/$t.build.log" 2>&1; then
        echo "run-all.sh: $t does not build; see $logs/$t.build.log" >&2
        exit 2
    fi
done

# One target: run it, then write its result line to $logs/$t.line.
run_one() {
    local t=$1 log="$logs/$1.log" dict=() status
    echo "run-all.sh: $t for $seconds s" >&2
    mkdir -p "$fuzz/corpus/$t"
    [[ -f $fuzz/$t.dict ]] && dict=("-dict=$fuzz/$t.dict")
    cargo fuzz run -s none -O "$t" "$fuzz/corpus/$t" -- \
        -max_total_time="$seconds" -print_final_stats=1 "${dict[@]}" "${extra[@]}" \
        >"$log" 2>&1
    status=$?
    local runs cov ft corp artifact finding
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    # The last status line (#N ... cov: C ft: F corp: N/SIZE ...) has the final figures.
    local last
    last=$(grep -E '^#[0-9]+.*cov: ' "$log" | tail -n 1)
    cov=$(sed -n 's/.*cov: \([0-9]*\).*/\1/p' <<<"$last")
    ft=$(sed -n 's/.*ft: \([0-9]*\).*/\1/p' <<<"$last")
    corp=$(sed -n 's/.*corp: \([0-9]*\).*/\1/p' <<<"$last")
    : "${runs:=$(sed -n 's/^#\([0-9]*\).*/\1/p' <<<"$last")}"
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -n 1)
    if [[ -n $artifact ]]; then
        finding="FOUND ${artifact#"$root"/}"
    elif ((status != 0)); then
        finding="ERROR exit $status, see $log"
    else
        finding=none
    fi
    printf '%-20s %12s %8s %8s %8s  %s\n' "$t" "${runs:--}" "${cov:--}" "${ft:--}" \
        "${corp:--}" "$finding" >"$logs/$t.line"
}

printf '%-20s %12s %8s %8s %8s  %s\n' target runs cov ft corpus finding
running=0
for t in "${targets[@]}"; do
    rm -f "$logs/$t.line"
    run_one "$t" &
    running=$((running + 1))
    if ((running >= jobs)); then
        wait -n
        running=$((running - 1))
    fi
done
wait

found=0 failed=0
for t in "${targets[@]}"; do
    if [[ ! -f $logs/$t.line ]]; then
        printf '%-20s %12s %8s %8s %8s  %s\n' "$t" - - - - "ERROR no result, see $logs/$t.log"
        failed=1
        continue
    fi
    cat "$logs/$t.line"
    grep -q '  FOUND ' "$logs/$t.line" && found=1
    grep -q '  ERROR ' "$logs/$t.line" && failed=1
done
echo "${#targets[@]} targets, ${seconds} s each; logs in ${logs#"$root"/}/"
((failed)) && exit 2
((found)) && exit 1
exit 0
