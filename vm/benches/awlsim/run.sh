#!/bin/sh
# Side by side (issue 17): 1,000,000 scans of the same logic on awlsim (scan_cost.awl,
# awlsim from PyPI in a venv outside the repository) and on gutta-vm (scan_cost.lad,
# compiled with gutta-cc, run with `gutta-vm --scans 1000000`). Times each with
# /usr/bin/time (hyperfine when installed: GUTTA_HYPERFINE=1) and prints the ratio.
# Usage: vm/benches/awlsim/run.sh [RUNS]   (from anywhere; builds the release binaries)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../../.." && pwd)
runs=${1:-3}
work=${TMPDIR:-/tmp}/gutta-awlsim
venv=$work/venv
mkdir -p "$work"

# awlsim in its own venv, never in the repository.
if [ ! -x "$venv/bin/awlsim-test" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet awlsim
fi
awlsim_version=$("$venv/bin/pip" show awlsim | sed -n 's/^Version: //p')

(cd "$repo" && cargo build --release -p gutta-cli --bin gutta-cc --bin gutta-vm)
"$repo/target/release/gutta-cc" "$here/scan_cost.lad" -o "$work/scan_cost_image" >/dev/null 2>&1

# "WALL USER": median wall and user CPU seconds of RUNS runs of the command. On a
# shared machine the wall time includes waiting for a core; user time does not.
median_seconds() {
    i=0
    : >"$work/times"
    while [ "$i" -lt "$runs" ]; do
        /usr/bin/time -f '%e %U' -o "$work/time" "$@" >"$work/out" 2>"$work/err"
        cat "$work/time" >>"$work/times"
        i=$((i + 1))
    done
    wall=$(cut -d' ' -f1 "$work/times" | sort -n | awk '{ t[NR] = $1 } END { print t[int((NR + 1) / 2)] }')
    user=$(cut -d' ' -f2 "$work/times" | sort -n | awk '{ t[NR] = $1 } END { print t[int((NR + 1) / 2)] }')
    echo "$wall $user"
}

if [ "${GUTTA_HYPERFINE:-0}" = 1 ] && command -v hyperfine >/dev/null; then
    hyperfine --runs "$runs" \
        "$venv/bin/awlsim-test -D -L 1 -m en $here/scan_cost.awl" \
        "$repo/target/release/gutta-vm $work/scan_cost_image --scans 1000000 --read MD0"
    exit 0
fi

echo "awlsim $awlsim_version: awlsim-test scan_cost.awl (stops itself after 1,000,000 cycles)"
awlsim=$(median_seconds "$venv/bin/awlsim-test" -D -L 1 -m en "$here/scan_cost.awl")
echo "  median of $runs: wall and user seconds $awlsim"
echo "gutta-vm --scans 1000000 --read MD0"
gutta=$(median_seconds "$repo/target/release/gutta-vm" "$work/scan_cost_image" --scans 1000000 --read MD0)
grep -q 'MD0 = 1000000' "$work/out" || { echo "gutta-vm did not count 1,000,000 scans" >&2; exit 1; }
echo "  median of $runs: wall and user seconds $gutta"
echo "$awlsim $gutta" | awk '{
    printf "per scan, wall: awlsim %.2f us, gutta-vm %.0f ns: %.0fx\n", $1, $3 * 1000, $1 / $3
    printf "per scan, user: awlsim %.2f us, gutta-vm %.0f ns: %.0fx\n", $2, $4 * 1000, $2 / $4
}'
