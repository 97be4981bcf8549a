#!/usr/bin/env bash
# Mutation testing of the laws (issue 36): mutmut 3 over one package at a time.
#
#   scripts/mutation.sh                 # every package in scripts/mutation_targets.toml, in turn
#   scripts/mutation.sh physics motion  # only these
#   JOBS=1 scripts/mutation.sh rig      # worker processes (default 2)
#   TARGETS=/path/to/targets.toml ...    # another table (test files it names that are missing are skipped)
#   scripts/mutation.sh --survivors motion  # after adding tests: rerun only the last run's survivors
#                                           # (the tests copied afresh and the target's test list read again:
#                                           # test files added to it run too; killed mutants stay killed; a test
#                                           # dropped from it or a changed deselect is refused: run it in full)
#
# Each package runs in its own copy of the tree (build/mutation/<package>/): the copy's
# pyproject.toml gets a [tool.mutmut] table naming the files to mutate and the tests that
# cover them, so each mutant runs only the tests that pin its package. numba is switched
# off (NUMBA_DISABLE_JIT=1): mutmut swaps functions through a trampoline numba cannot
# compile. In the copy the `@jitable` marks are removed, since mutmut leaves decorated
# functions alone and the laws are marked so (the marks only register them with numba).
#
# Prints, a package a line: mutants, killed, survived, no tests, timeouts, score, minutes;
# the survivors' names follow (`cd build/mutation/<package> && ../../../.venv/bin/mutmut show NAME`
# shows a diff). Not part of the test command: it takes tens of minutes (docs/guide/mutation.md).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
venv=${VENV:-$root/.venv}
jobs=${JOBS:-2}
targets=${TARGETS:-$root/scripts/mutation_targets.toml}
survivors_only=0
status=0
if [ "${1:-}" = "--survivors" ]; then
    survivors_only=1
    shift
fi
if [ $# -eq 0 ]; then
    mapfile -t packages < <("$venv/bin/python" -c "import tomllib,sys; print('\n'.join(tomllib.load(open(sys.argv[1],'rb'))))" "$targets")
else
    packages=("$@")
fi
[ -x "$venv/bin/mutmut" ] || {
    echo "mutation.sh: no mutmut in $venv: install the extra, $venv/bin/pip install -e '$root[test,mutation]'" >&2
    exit 2
}
summary=$root/build/mutation/summary.txt
mkdir -p "$root/build/mutation"
for package in "${packages[@]}"; do
    work=$root/build/mutation/$package
    if [ "$survivors_only" = 1 ]; then
        [ -f "$work/survivors.txt" ] || { echo "$package: no earlier run in $work" >&2; continue; }
        rm -rf "$work/tests"
        (cd "$root" && tar --exclude=__pycache__ -cf - tests) | tar -xf - -C "$work"
        # The target's current test list (scripts/mutation_config.py): tests added since the first run are run on the
        # survivors, the first run's verdicts kept; a test dropped or a deselect changed is refused.
        "$venv/bin/python" "$root/scripts/mutation_config.py" survivors "$targets" "$package" "$work" || {
            status=2
            continue
        }
        mapfile -t names < <(sed -n 's/^ *\([^:]*\): \(survived\|no tests\)$/\1/p' "$work/survivors.txt")
        start=$(date +%s)
        if [ "${#names[@]}" -gt 0 ]; then
            (cd "$work" && NUMBA_DISABLE_JIT=1 MPLBACKEND=Agg "$venv/bin/mutmut" run --max-children "$jobs" "${names[@]}" >"$work/rerun.log" 2>&1) || {
                echo "$package: mutmut failed, see $work/rerun.log" >&2
                continue
            }
        fi
    else
        rm -rf "$work"
        mkdir -p "$work"
        (cd "$root" && tar --exclude=__pycache__ --exclude='*.nbi' --exclude='*.nbc' -cf - hipsim models tests pyproject.toml) | tar -xf - -C "$work"
        # The laws without their numba mark (see above); `jitable` itself stays for other callers.
        find "$work/hipsim" -name '*.py' -exec sed -i '/^@jitable$/d' {} +
        "$venv/bin/python" "$root/scripts/mutation_config.py" write "$targets" "$package" "$work"
        start=$(date +%s)
        (cd "$work" && NUMBA_DISABLE_JIT=1 MPLBACKEND=Agg "$venv/bin/mutmut" run --max-children "$jobs" >"$work/run.log" 2>&1) || {
            echo "$package: mutmut failed, see $work/run.log" >&2
            tail -30 "$work/run.log" >&2
            continue
        }
    fi
    minutes=$(( ($(date +%s) - start + 59) / 60 ))
    (cd "$work" && "$venv/bin/mutmut" export-cicd-stats >/dev/null && "$venv/bin/mutmut" results >"$work/survivors.txt" 2>&1) || true
    "$venv/bin/python" - "$work" "$package" "$minutes" "$survivors_only" <<'PY' | tee -a "$summary"
import json, sys
from pathlib import Path

work, package, minutes, rerun = Path(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4] == "1"
s = json.loads((work / "mutants" / "mutmut-cicd-stats.json").read_text())
# A mutant no selected test reaches counts as a survivor: the score is of every mutant made.
killed = s["killed"] + s["timeout"] + s["segfault"]
score = 100.0 * killed / max(s["total"] - s["skipped"], 1)
print(f"{package}: {s['total']} mutants, {s['killed']} killed, {s['survived']} survived, "
      f"{s['no_tests']} without tests, {s['timeout']} timeouts, score {score:.1f} %, "
      + (f"survivors rerun in {minutes} min" if rerun else f"{minutes} min"))
PY
    # Survivors one a line; mutants no selected test reaches, counted by function.
    grep -v ": no tests" "$work/survivors.txt" | sed 's/^ */    /' || true
    grep ": no tests" "$work/survivors.txt" | sed 's/__mutmut_[0-9]*: no tests//; s/^ */    no tests: /' | sort | uniq -c || true
done
exit "$status"
