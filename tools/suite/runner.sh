#!/usr/bin/env bash
# Cargo's runner for the test binaries (.ci/run sets it through
# CARGO_TARGET_<triple>_RUNNER): runs one binary, asks libtest for each
# test's time, and appends the binary's wall time to $SUITE_TIMES.
#
# libtest's --report-time is still unstable: RUSTC_BOOTSTRAP=1 is set for
# the test process only, to unlock that flag of the test harness; nothing
# is compiled with it, the code builds on stable as always. A binary that
# is not a libtest harness (none here) would get flags it does not know.
set -uo pipefail
bin=$1
shift
start=$(date +%s.%N)
RUSTC_BOOTSTRAP=1 "$bin" "$@" -Z unstable-options --report-time
rc=$?
end=$(date +%s.%N)
if [ -n "${SUITE_TIMES:-}" ]; then
  name=$(basename "$bin")
  printf '%s\t%.1f\t%s\n' "${name%-*}" "$(echo "$end - $start" | bc)" "$rc" >>"$SUITE_TIMES"
fi
exit $rc
