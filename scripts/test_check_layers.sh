#!/usr/bin/env bash
# Tests scripts/check_layers.sh: copies the repository's tracked files to a temporary folder, plants one violation
# of each rule in a copy of its own and checks that check_layers.sh fails naming the rule and the planted file.
# The clean copy must pass if the repository passes; while the repository still violates rules, it prints which
# instead of failing (the planted violations are then recognised as lines the clean copy does not print).
# Exit 0 when every case passes, 1 otherwise. Takes a few seconds.
set -euo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
check="$src/scripts/check_layers.sh"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
passed=0
failed=0

ok() { echo "[test_check_layers] PASS $1"; passed=$((passed + 1)); }
bad() { echo "[test_check_layers] FAIL $1" >&2; failed=$((failed + 1)); }

# The tracked files as they are in the working tree (a file deleted but not yet staged is left out).
mkdir "$tmp/clean"
(cd "$src" && git ls-files -z --cached | while IFS= read -r -d '' f; do
  [ -f "$f" ] && printf '%s\0' "$f"
done | xargs -0 cp --parents -t "$tmp/clean")

set +e
"$check" --root "$tmp/clean" >"$tmp/clean.out" 2>&1
clean_rc=$?
set -e
if [ "$clean_rc" -eq 0 ]; then
  ok "the clean copy passes"
elif "$check" >/dev/null 2>&1; then
  bad "the repository passes but its clean copy does not:"; cat "$tmp/clean.out" >&2
else
  echo "[test_check_layers] the repository violates these rules now (not counted as failures):"
  grep -v '^check_layers:' "$tmp/clean.out" | cut -d: -f1 | sort | uniq -c | sed 's/^/    /'
fi

"$check" --help >/dev/null && ok "--help exits 0" || bad "--help does not exit 0"
set +e; "$check" --no-such-option >/dev/null 2>&1; rc=$?; set -e
[ "$rc" -eq 2 ] && ok "an unknown option exits 2" || bad "an unknown option exits $rc, not 2"

# plant NAME RULE FILE SCRIPT: runs SCRIPT in the working copy, expects check_layers.sh to fail with a line
# "RULE: FILE..." that the clean copy does not print, then restores the copy (plants touch only the folders below).
touched=(thorvald_model greenhouse_rail_nav/package.xml)
cp -a "$tmp/clean" "$tmp/work"
plant() {
  local name="$1" rule="$2" file="$3" script="$4" dir="$tmp/work" rc new
  (cd "$dir" && eval "$script")
  set +e
  "$check" --root "$dir" >"$tmp/$name.out" 2>&1
  rc=$?
  set -e
  new="$(grep -vxF -f "$tmp/clean.out" "$tmp/$name.out" | grep -v '^check_layers:' || true)"
  if [ "$rc" -ne 0 ] && grep -q "^$rule: $file\b" <<<"$new"; then
    ok "$name: $(grep -m1 "^$rule: $file" <<<"$new" | cut -c1-150)"
  else
    bad "$name: expected a new line '$rule: $file...' and a non-zero exit (got $rc); new lines:"
    printf '%s\n' "${new:-    (none)}" >&2
  fi
  for f in "${touched[@]}"; do
    rm -rf "${dir:?}/$f" && cp -a "$tmp/clean/$f" "$dir/$f"
  done
}

node_main='#include <ros/ros.h>
int main(int argc, char** argv) { ros::init(argc, argv, "planted"); return 0; }'

plant ros-header core-includes thorvald_model/src/planted_core.cpp \
  'printf "#include <ros/ros.h>\n" >thorvald_model/src/planted_core.cpp'
plant message-header core-includes thorvald_model/include/thorvald_model/planted.h \
  'printf "#pragma once\n#include <thorvald_base/BaseState.h>\n" >thorvald_model/include/thorvald_model/planted.h'
plant adapter-header core-includes thorvald_model/src/planted_core.cpp \
  'printf "#include \"nodes/planted.h\"\n" >thorvald_model/src/planted_core.cpp
   mkdir -p thorvald_model/src/nodes && touch thorvald_model/src/nodes/planted.h'
plant catkin-link core-links thorvald_model/CMakeLists.txt \
  'touch thorvald_model/src/planted_core.cpp
   printf "add_library(planted_core src/planted_core.cpp)\ntarget_link_libraries(planted_core \${catkin_LIBRARIES})\n" \
     >>thorvald_model/CMakeLists.txt'
plant node-outside-nodes node-location thorvald_model/src/planted_node.cpp \
  'printf "%s\n" "$node_main" >thorvald_model/src/planted_node.cpp'
plant node-links-fixture fixtures thorvald_model/CMakeLists.txt \
  'mkdir -p thorvald_model/src/testing thorvald_model/src/nodes
   touch thorvald_model/src/testing/planted_fixture.cpp
   printf "%s\n" "$node_main" >thorvald_model/src/nodes/planted_node.cpp
   printf "%s\n" "add_library(\${PROJECT_NAME}_planted_testing src/testing/planted_fixture.cpp)" \
     "add_executable(planted_node src/nodes/planted_node.cpp)" \
     "target_link_libraries(planted_node \${PROJECT_NAME}_planted_testing)" >>thorvald_model/CMakeLists.txt'
plant generator-outside-testing fixtures thorvald_model/src/synthetic_planted.cpp \
  'printf "int syntheticValue() { return 1; }\n" >thorvald_model/src/synthetic_planted.cpp'
plant app-depends-on-bringup package-arrows greenhouse_rail_nav/package.xml \
  'sed -i "s|</package>|  <exec_depend>thorvald_bringup</exec_depend>\n</package>|" greenhouse_rail_nav/package.xml'
plant cli11-parse command-line thorvald_model/bench/planted_bench.cpp \
  'mkdir -p thorvald_model/bench
   printf "%s\n" "#include <CLI/CLI.hpp>" \
     "int main(int argc, char** argv) { CLI::App app; CLI11_PARSE(app, argc, argv); return 0; }" \
     >thorvald_model/bench/planted_bench.cpp'
plant app-exit command-line thorvald_model/bench/planted_bench.cpp \
  'mkdir -p thorvald_model/bench
   printf "%s\n" "#include <CLI/CLI.hpp>" "int main(int argc, char** argv) {" "  CLI::App app;" \
     "  try { app.parse(argc, argv); } catch (const CLI::ParseError& e) { return app.exit(e); }" "}" \
     >thorvald_model/bench/planted_bench.cpp'

echo "[test_check_layers] $passed passed, $failed failed"
[ "$failed" -eq 0 ]
