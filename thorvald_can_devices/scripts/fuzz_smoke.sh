#!/usr/bin/env bash
# Builds the libFuzzer targets with clang in a scratch build of this package alone (no ROS needed) and runs each
# for a few seconds on the corpus kept in fuzz/corpus/<target> (new inputs go to a scratch copy, the repository's
# corpus is not changed). Exit 0 when every target ran without a crash. The scratch folder is removed at the end
# (after printing the log of a failing target) unless FUZZ_WORK_DIR names one to keep.
#   thorvald_can_devices/scripts/fuzz_smoke.sh [seconds per target, default 5]
set -euo pipefail
pkg="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
base="$(cd "$pkg/.." && pwd)/thorvald_base"
seconds="${1:-5}"
if [ -n "${FUZZ_WORK_DIR:-}" ]; then
  work="$FUZZ_WORK_DIR"
else
  work="$(mktemp -d /tmp/thorvald_can_fuzz.XXXXXX)"
  trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work/obj"
command -v clang++ >/dev/null || { echo "fuzz_smoke: clang++ not found (apt-get install clang libclang-rt-14-dev)" >&2; exit 2; }
flags=(-std=c++17 -O1 -g -fsanitize=fuzzer-no-link,address,undefined -I"$pkg/include" -I"$base/include" -I"$pkg/fuzz")
objs=()
for src in can_frame bus_error virtual_can_bus candump_log thorvald_drive_protocol battery_protocol canopen_protocol; do
  clang++ "${flags[@]}" -c "$pkg/src/$src.cpp" -o "$work/obj/$src.o"
  objs+=("$work/obj/$src.o")
done
clang++ "${flags[@]}" -c "$pkg/fuzz/decoders.cpp" -o "$work/obj/decoders.o"
objs+=("$work/obj/decoders.o")
status=0
for target in thorvald_frames battery_frames canopen_frames candump_line; do
  clang++ "${flags[@]}" -fsanitize=fuzzer "$pkg/fuzz/fuzz_$target.cpp" "${objs[@]}" -o "$work/fuzz_$target"
  mkdir -p "$work/corpus_$target"
  cp "$pkg/fuzz/corpus/$target/"* "$work/corpus_$target/"
  echo "fuzz_smoke: $target for ${seconds}s"
  if ! "$work/fuzz_$target" -max_total_time="$seconds" -max_len=64 -print_final_stats=1 \
       -artifact_prefix="$work/crash_$target-" "$work/corpus_$target" >"$work/$target.log" 2>&1; then
    echo "fuzz_smoke: $target FAILED; the end of its log:" >&2
    tail -30 "$work/$target.log" >&2
    for crash in "$work/crash_$target-"*; do
      [ -e "$crash" ] && { echo "fuzz_smoke: crashing input (hex): $(od -An -tx1 -v "$crash" | tr -d '\n')" >&2; }
    done
    status=1
  else
    grep -E "stat::number_of_executed_units" "$work/$target.log" || true
  fi
done
[ "$status" = 0 ] && echo "fuzz_smoke: all targets ok"
exit "$status"
