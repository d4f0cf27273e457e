#!/usr/bin/env bash
# The fuzz targets' build of scripts/test.d/40-robustness.sh (nightly, AddressSanitizer, every
# target; `cargo fuzz build` takes the same defaults as `cargo fuzz run`), with the nightly
# tools it needs installed first. Usage: setsid bash scripts/fuzz-build.sh STATE_DIR (its own
# process group, so that `kill -- -PID` stops the build with it): writes its process id to
# STATE_DIR/pid, its output to STATE_DIR/log, STATE_DIR/tools once the nightly tools are
# installed and, when it ends, its exit status to STATE_DIR/status; `wait_fuzz_build
# STATE_DIR tools|status` (scripts/lib.sh) waits for one of these.
# scripts/test.sh starts it in the background beside the firmware step, whose QEMU runs and
# link-time-optimised links leave a core idle; 40-robustness.sh starts it itself when run
# alone.
set -uo pipefail
cd "$(dirname "$0")/.."
source scripts/lib.sh
state="$1"
echo $$ >"$state/pid"
status=0
{ need_fuzz_tools && touch "$state/tools" && (cd fuzz && cargo +nightly fuzz build); } >"$state/log" 2>&1 ||
  status=$?
echo "$status" >"$state/status.part" && mv "$state/status.part" "$state/status"
