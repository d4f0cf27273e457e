#!/usr/bin/env bash
# Runs every test of the project on a fresh machine: installs what is missing, then runs the
# steps in scripts/test.d/ (each one a self-contained shell script) in two lanes side by side,
# each lane's steps in order. Stops at the first failure. Usage:
# bash scripts/test.sh [STEP-NAME-SUBSTRING]
#
# Why two lanes: on two cores, much of a step's time leaves one core idle (the last crate of a
# build and its link, a link-time-optimised library, QEMU and Miri, which run on one thread,
# downloads). Each lane is a chain of steps; cargo's lock on a build directory makes the two
# lanes' builds in one profile wait for each other, so they share the cores where one lane
# alone would leave one idle. The lanes balance the steps' measured times; a new step must be
# placed in one. 15-publish ends the second lane: by then 10-rust's lints have checked the
# dependencies its checks of the packages reuse.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib.sh
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"
only="${1:-}"
start=$(date +%s)
lanes=(
  "10-rust 20-python"
  "12-msrv 16-c-api 30-firmware 40-robustness 15-publish"
)

steps_of_lane() { # $1: the lane's step names; prints the lane's scripts that match $only
  local name
  for name in $1; do
    case "$name" in *"$only"*) echo "scripts/test.d/$name.sh" ;; esac
  done
}
for step in scripts/test.d/*.sh; do
  grep -qw "$(basename "$step" .sh)" <<<"${lanes[*]}" ||
    { echo "FAIL: $step is in no lane of scripts/test.sh" >&2; exit 1; }
done

# What more than one step installs, installed once before the lanes start: two package
# managers running at once would fail on each other's locks.
need_rust
need_msrv_toolchains
need_debian_packages gcc libc6-dev qemu-system-arm gcc-arm-none-eabi libnewlib-arm-none-eabi \
  binutils-arm-none-eabi

logs=$(mktemp -d)
declare -A lane_of # a running lane's process id -> its index in lanes
cleanup() {
  for pid in "${!lane_of[@]}"; do kill -- -"$pid" 2>/dev/null || true; done
  rm -rf "$logs"
}
trap cleanup EXIT
# Each lane in a process group of its own (set -m), so that a failure can stop the other
# lane's steps and everything they started.
set -m
for i in "${!lanes[@]}"; do
  mapfile -t steps < <(steps_of_lane "${lanes[$i]}")
  [ ${#steps[@]} -gt 0 ] || continue
  (
    for step in "${steps[@]}"; do
      echo "=== $(basename "$step") ($(($(date +%s) - start)) s)"
      bash "$step"
    done
    echo "=== lane ${lanes[$i]// /, } passed ($(($(date +%s) - start)) s)"
  ) >"$logs/lane-$i.log" 2>&1 &
  lane_of[$!]=$i
  echo "lane $i: ${steps[*]##*/} (output shown when it ends)"
done
set +m

# Waits for the lanes in the order they end; the first failure stops the others.
while [ ${#lane_of[@]} -gt 0 ]; do
  lane_status=0
  wait -n -p ended "${!lane_of[@]}" || lane_status=$?
  i=${lane_of[$ended]}
  unset "lane_of[$ended]"
  cat "$logs/lane-$i.log"
  if [ "$lane_status" -ne 0 ]; then
    echo "FAIL: lane ${lanes[$i]// /, } (status $lane_status, $(($(date +%s) - start)) s)" >&2
    for pid in "${!lane_of[@]}"; do
      kill -- -"$pid" 2>/dev/null || true
      echo "stopped lane ${lanes[${lane_of[$pid]}]// /, }; its output so far:" >&2
      cat "$logs/lane-${lane_of[$pid]}.log" >&2
    done
    exit 1
  fi
done
echo "=== all test steps passed in $(($(date +%s) - start)) s"
