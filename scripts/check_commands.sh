#!/usr/bin/env bash
# Checks that every command the workspace's scripts, launch files, tests and READMEs call comes from a Debian
# package listed in scripts/debian_packages.txt (a command installed by hand on one machine is missing on the next).
# Exit 0 when all are listed.
set -uo pipefail
src="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$src"
list="$src/scripts/debian_packages.txt"
commands=(rosrun rospack roslaunch rostest rosparam rostopic rosservice rosnode roscore rosmsg check_urdf
  catkin_test_results rviz xterm clang-format clang++ cmake make python3 git)
status=0
for cmd in "${commands[@]}"; do
  git grep -qwF -e "$cmd" -- '*.sh' '*.py' '*.launch' '*.test' '*.md' '.ci/*' || continue
  path="$(command -v "$cmd")" || { echo "check_commands: '$cmd' is used but not installed" >&2; status=1; continue; }
  found=""
  for p in "$path" "$(readlink -f "$path")"; do
    pkg="$(dpkg -S "$p" 2>/dev/null | head -1 | cut -d: -f1)"
    if [ -n "$pkg" ] && grep -qx "$pkg" "$list"; then found="$pkg"; break; fi
  done
  # git and python3 come with every Debian system that can clone this repository; the rest must be listed.
  case "$cmd" in git|python3|make) [ -n "$found" ] || found="(base system)";; esac
  if [ -z "$found" ]; then
    echo "check_commands: '$cmd' ($path, package $(dpkg -S "$(readlink -f "$path")" 2>/dev/null | cut -d: -f1)) is not in scripts/debian_packages.txt" >&2
    status=1
  fi
done
[ "$status" = 0 ] && echo "check_commands: every command used comes from a listed package"
exit "$status"
