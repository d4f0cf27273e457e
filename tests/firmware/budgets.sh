#!/usr/bin/env bash
# The firmware test's instruction budgets (budgets.txt beside this script), checked against
# the counts that run.sh prints:
#  check COUNTS [CORE...]: prints, for each budget of the cores CORE (m4, m0; default both),
#    `budget <count> <label>: N <= B ok` (B written as a number, or as FACTOR*LABEL2: FACTOR
#    times the count of the same kind printed for LABEL2), or a FAIL line if N is above B or if
#    run.sh did not print the line at all (a renamed or removed variant must not lose its
#    budget silently); where the budget has a target below its interim ceiling, also
#    `warning: ... target T missed by D` (or a note once the target is met). Counts that
#    have no budget are listed as such. Exits non-zero if any budget fails.
#  tamper COUNTS [CORE...]: shows that every budget can fail: runs `check` on a copy of
#    COUNTS with every budgeted count raised 0.1 above its ceiling, then on a copy without
#    the budgeted lines, and requires every budget to FAIL both times.
# COUNTS is a file of run.sh's output (`insns_per_update <label>: N` and the like). The
# BUDGETS environment variable overrides the budgets file.
set -euo pipefail
shopt -s inherit_errexit
budgets=${BUDGETS:-$(dirname "$0")/budgets.txt}

usage() { echo "usage: bash tests/firmware/budgets.sh check|tamper COUNTS [m4|m0...]" >&2; exit 1; }
[ $# -ge 2 ] || usage
mode=$1 counts=$2
shift 2
cores=("$@")
[ ${#cores[@]} -gt 0 ] || cores=(m4 m0)
for c in "${cores[@]}"; do
  case $c in m4 | m0) ;; *) echo "unknown core $c (m4 or m0)" >&2; exit 1 ;; esac
done
[ -r "$budgets" ] || { echo "no budgets file $budgets" >&2; exit 1; }
[ -r "$counts" ] || { echo "no counts file $counts" >&2; exit 1; }

# applicable: the budgets of the selected cores, one `COUNT LABEL CEILING TARGET REASON...` a
# line (a label ending in -m0 is the Cortex-M0's, any other the Cortex-M4F's); fails on a
# malformed or repeated line.
applicable() {
  awk -v cores=" ${cores[*]} " '
    /^[[:space:]]*(#|$)/ { next }
    {
      number = "^[0-9]+(\\.[0-9]+)?$"
      relative = "^[0-9]+(\\.[0-9]+)?[*][^ ]+$"
      if (NF < 5 || $1 !~ /^(insns_|flash_bytes$)/ || ($3 !~ number && $3 !~ relative) ||
          ($4 != "-" && $4 !~ number && $4 !~ relative)) {
        printf "%s:%d: expected COUNT LABEL CEILING TARGET REASON: %s\n", FILENAME, FNR, $0 > "/dev/stderr"
        exit 1
      }
      if ($4 ~ number && $3 ~ number && $4 + 0 >= $3 + 0) {
        printf "%s:%d: target %s is not below the ceiling %s (write - for no target)\n", FILENAME, FNR, $4, $3 > "/dev/stderr"
        exit 1
      }
      key = $1 " " $2
      if (key in seen) {
        printf "%s:%d: a second budget for %s\n", FILENAME, FNR, key > "/dev/stderr"
        exit 1
      }
      seen[key] = 1
      core = $2 ~ /-m0$/ ? "m0" : "m4"
      if (index(cores, " " core " ")) print
    }' "$budgets"
}

# check COUNTS: the check itself (see the header).
check() {
  local list
  list=$(applicable)
  awk -v list="$list" -v cores=" ${cores[*]} " -v file="$budgets" '
    # The counts: `COUNT LABEL: N`.
    /^(insns_[a-z_]+|flash_bytes) [^ ]+: [0-9.]+$/ { key = $1 " " substr($2, 1, length($2) - 1); count[key] = $3; order[++n] = key }
    # A limit as written: a number, or FACTOR*LABEL, FACTOR times the count of the same kind
    # printed for LABEL (in `why`; "" if LABEL was not printed).
    function limit(kind, v,    star) {
      star = index(v, "*")
      why = ""
      if (star == 0) return v
      ref = kind " " substr(v, star + 1)
      if (!(ref in count)) { why = "(" ref " not printed)"; return "" }
      why = sprintf(" (%s x %s)", substr(v, 1, star - 1), count[ref])
      return sprintf("%.1f", substr(v, 1, star - 1) * count[ref])
    }
    END {
      budgets = split(list, line, "\n")
      failed = 0
      for (i = 1; i <= budgets; i++) {
        if (line[i] == "") continue
        split(line[i], f, " ")
        key = f[1] " " f[2]; ceiling = f[3]; target = f[4]
        budgeted[key] = 1
        if (!(key in count)) {
          printf "budget %s: not printed: FAIL (renamed or removed? its budget in budgets.txt must follow)\n", key
          failed++
          continue
        }
        c = count[key]
        ceiling = limit(f[1], ceiling)
        if (ceiling == "") {
          printf "budget %s: the reference of its ceiling %s: FAIL\n", key, why
          failed++
          continue
        }
        ceiling_why = why
        if (c + 0 > ceiling + 0) {
          printf "budget %s: %s > %s%s FAIL (over by %.1f)\n", key, c, ceiling, ceiling_why, c - ceiling
          failed++
          continue
        }
        printf "budget %s: %s <= %s%s ok%s\n", key, c, ceiling, ceiling_why, target == "-" ? "" : " (interim ceiling)"
        if (target == "-") continue
        target = limit(f[1], target)
        if (target == "") {
          printf "warning: budget %s: the reference of its target %s\n", key, why
        } else if (c + 0 > target + 0) {
          printf "warning: budget %s: target %s%s missed by %.1f\n", key, target, why, c - target
        } else {
          printf "note: budget %s: target %s%s met (%s): the ceiling can be the target now\n", key, target, why, c
        }
      }
      for (i = 1; i <= n; i++) {
        core = order[i] ~ /-m0$/ ? "m0" : "m4"
        if (!(order[i] in budgeted) && order[i] !~ /^insns_per_iteration / && index(cores, " " core " ")) {
          printf "budget %s: %s, no budget\n", order[i], count[order[i]]
        }
      }
      if (failed > 0) {
        printf "%d of %d budgets exceeded or not printed (%s)\n", failed, budgets, file > "/dev/stderr"
        exit 1
      }
    }' "$1"
}

# tampered HOW: COUNTS with every budgeted count raised above its ceiling (HOW raise; a
# ceiling FACTOR*LABEL on LABEL's count as tampered) or its line removed (HOW drop).
tampered() {
  awk -v how="$1" -v list="$(applicable)" '
    BEGIN {
      n = split(list, line, "\n")
      for (i = 1; i <= n; i++) { split(line[i], f, " "); ceiling[f[1] " " f[2] ":"] = f[3] }
    }
    # The raised value of the line `key` whose count is `c`.
    function raised(key, c,    star, ref) {
      if (!(key in ceiling)) return c
      star = index(ceiling[key], "*")
      if (star == 0) return ceiling[key] + 0.1
      split(key, k, " ")
      ref = k[1] " " substr(ceiling[key], star + 1) ":"
      return substr(ceiling[key], 1, star - 1) * raised(ref, count[ref]) + 0.1
    }
    NR == FNR { count[$1 " " $2] = $3; next }
    {
      key = $1 " " $2
      if (key in ceiling) {
        if (how == "drop") next
        printf "%s %.1f\n", key, raised(key, $3)
        next
      }
      print
    }' "$counts" "$counts"
}

case $mode in
  check) check "$counts" ;;
  tamper)
    total=$(applicable | wc -l)
    [ "$total" -gt 0 ] || { echo "no budgets for ${cores[*]} in $budgets" >&2; exit 1; }
    for how in raise drop; do
      copy=$(mktemp)
      tampered "$how" >"$copy"
      if output=$(check "$copy" 2>/dev/null); then
        rm -f "$copy"
        echo "$output"
        echo "the budget check passed with every budgeted count tampered ($how)" >&2
        exit 1
      fi
      rm -f "$copy"
      failed=$(grep -c "^budget .*FAIL" <<<"$output" || true)
      if [ "$failed" -ne "$total" ]; then
        echo "$output"
        echo "with every budgeted count tampered ($how), $failed of $total budgets FAIL; all must" >&2
        exit 1
      fi
    done
    echo "budget check with every budgeted count raised 0.1 above its ceiling, then removed" \
      "(${cores[*]}): all $total budgets FAIL both times, as they must"
    ;;
  *) usage ;;
esac
