#!/usr/bin/env bash
# Prints the table of the fault-injection campaign (issue 36, item 2) as Markdown: per fault
# and onset, the wrong samples, the coverage (the wrong ones flagged), the false alarms on
# the healthy runs of the same setups, and the worst latency, beside the issue's targets.
# It runs the test that measures and holds them, crates/angletrack/tests/fault_coverage.rs
# (the campaign is crates/angletrack/src/fault_campaign/), and takes the table it prints.
# Usage: bash scripts/fault-coverage.sh [--write]
#   --write: also replace the table in docs/guide/diagnostics.md (between its
#     <!-- fault-coverage:begin --> and <!-- fault-coverage:end --> markers).
# The figures do not depend on the machine: the campaign is deterministic from its seeds.
set -euo pipefail
cd "$(dirname "$0")/.."
page=docs/guide/diagnostics.md

write=false
case ${1:-} in
  --write) write=true ;;
  "") ;;
  *) echo "usage: bash scripts/fault-coverage.sh [--write]" >&2; exit 1 ;;
esac

output=$(cargo test -q -p angletrack --release --test fault_coverage -- --nocapture 2>/dev/null)
table=$(sed -n '/^BEGIN fault-coverage table$/,/^END fault-coverage table$/p' <<<"$output" | sed '1d;$d')
if [ -z "$table" ]; then
  echo "the test printed no table" >&2
  exit 1
fi
printf '%s\n' "$table"

if $write; then
  grep -q '^<!-- fault-coverage:begin -->$' "$page" && grep -q '^<!-- fault-coverage:end -->$' "$page" || {
    echo "$page has no <!-- fault-coverage:begin --> / <!-- fault-coverage:end --> markers" >&2
    exit 1
  }
  tmp=$(mktemp)
  printf '%s\n' "$table" >"$tmp"
  awk -v table="$tmp" '
    /^<!-- fault-coverage:begin -->$/ { print; while ((getline line < table) > 0) print line; skip = 1; next }
    /^<!-- fault-coverage:end -->$/ { skip = 0 }
    !skip { print }
  ' "$page" >"$page.new"
  mv "$page.new" "$page"
  rm -f "$tmp"
  echo "wrote the table into $page" >&2
fi
